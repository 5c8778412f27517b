#!/usr/bin/env bash
# acomms glue and tools: TextFormat, the node with a busy queue, kelp-acomms-replay throughput,
# pAcommsHandler's resident memory.
set -euo pipefail
B=${BUILD:-build}
R=${KELP_ROOT:-.}
cc -std=c11 -D_DEFAULT_SOURCE -O2 -I"$R/include" -o "$B/acomms_handler_bench" "$R/bench/acomms_handler_bench.c" "$B/libkelp_core.a" -lm
"$B/acomms_handler_bench"
# replay: 5000 pushes and 5000 data requests
tl=$(mktemp /tmp/kelp-bench-tl.XXXXXX)
for i in $(seq 5000); do echo "push VehicleStatus nav_x=$((i % 1000)) nav_y=3 health=good"; echo "data_request bytes=32"; echo "advance 0.1"; done > "$tl"
s=$(date +%s.%N)
"$B/bin/kelp-acomms-replay" --xml "$R/missions/acomms/example1.xml" "$tl" > "$tl.out"
e=$(date +%s.%N)
frames=$(grep -c ' frame .*bytes=' "$tl.out")
echo "kelp-acomms-replay: 15000 timeline lines ($frames frames handed out) in $(echo "$e - $s" | bc) s"
rm -f "$tl" "$tl.out"
# pAcommsHandler RSS (DRIVER_NONE, example1 + simple_status), in a private netns for LCM
if command -v unshare >/dev/null && [ "$(id -u)" = 0 ]; then
  d=$(mktemp -d /tmp/kelp-bench-h.XXXXXX)
  cp "$R"/missions/acomms/{loopback.moos,example1.xml,simple_status.xml,modemidlookup.txt} "$d/"
  unshare -n bash -c "ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo
    cd $d; KELP_LCM_URL='udpm://239.255.76.67:7911?ttl=0' $(cd "$B" && pwd)/bin/pAcommsHandler loopback.moos > h.out 2>&1 & p=\$!
    sleep 3; echo \"pAcommsHandler (DRIVER_NONE, 3 DCCL queues): VmRSS \$(awk '/VmRSS/{print \$2, \$3}' /proc/\$p/status)\"; kill \$p; wait \$p 2>/dev/null || true"
  rm -rf "$d"
fi
