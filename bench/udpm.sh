# make bench: kelp's udpm transport beside raw liblcm, same run, same machine.
#  1. bursts of 10,000 messages of 100 B, 2 KB, 8 KB, 60 KB between two processes
#     (kelp socket -> kelp socket, liblcm -> liblcm): sent msg/s, delivered, received msg/s
#  2. publish cost alone (no subscriber), kelp beside liblcm
#  3. fan-out: one kelp publisher, 10 kelp subscriber processes, paced at 2k, 10k, 50k msg/s
#     for 2 s each: deliveries/s, latency p50 (median of subscribers) and p99 (worst one)
# Inside a private network namespace (loopback multicast, ttl=0); about a minute.
set -uo pipefail
BIN=${BUILD:-build}/bin
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ]; then
  export KELP_IN_NETNS=1
  exec unshare -n bash "$0" "$@"
fi
if [ -n "${KELP_IN_NETNS:-}" ]; then
  ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true
fi
# both sides ask for a 32 MiB kernel buffer: liblcm's SO_RCVBUF stops at net.core.rmem_max,
# kelp's socket uses SO_RCVBUFFORCE when it may (root); kelp's queue is 256 MiB for the
# 60 KB burst (600 MB offered in well under a second)
U="udpm://239.255.76.67:7801?ttl=0&recv_buf_size=33554432&queue_size=268435456"
T=$(mktemp -d)
P() { "$BIN/kelp-lcmprobe" --lcm-url="$U" "$@"; }
ready() { for i in $(seq 50); do grep -q ready "$1" && return 0; sleep 0.1; done; return 1; }
echo "bursts of 10,000 messages, two processes:"
printf '  %-7s %-7s %12s %12s %12s\n' size impl "sent msg/s" delivered "recv msg/s"
for size in 100 2000 8000 60000; do
  for impl in kelp lcm; do
    P recv $impl 10000 20 > "$T/r" 2>&1 & rp=$!
    ready "$T/r" || { echo "  receiver not ready"; kill $rp; continue; }
    P send $impl 10000 $size > "$T/s" 2>&1
    wait $rp
    sr=$(grep -o '[0-9]* msg/s' "$T/s" | head -1 | cut -d' ' -f1)
    got=$(grep -o 'received [0-9]*/[0-9]*' "$T/r" | cut -d' ' -f2)
    rr=$(grep -o 'at [0-9]* msg/s' "$T/r" | cut -d' ' -f2)
    printf '  %-7s %-7s %12s %12s %12s\n' $size $impl "${sr:-?}" "${got:-0/10000}" "${rr:--}"
  done
done
echo "publish cost, 100,000 x 100 B, no subscriber (best of 3, alternating):"
best_k=0; best_l=0
for i in 1 2 3; do
  k=$(P send kelp 100000 100 | grep -o '[0-9]* msg/s' | cut -d' ' -f1)
  l=$(P send lcm 100000 100 2>/dev/null | grep -o '[0-9]* msg/s' | cut -d' ' -f1)
  [ "${k:-0}" -gt $best_k ] && best_k=$k
  [ "${l:-0}" -gt $best_l ] && best_l=$l
done
printf '  kelp %s msg/s, liblcm %s msg/s: kelp at %s%% of liblcm\n' $best_k $best_l $((best_l ? best_k * 100 / best_l : 0))
echo "fan-out: 1 kelp publisher -> 10 kelp subscriber processes, 100 B, 2 s per rate:"
printf '  %-10s %12s %14s %10s %10s\n' "rate/s" delivered "deliveries/s" "p50 us" "p99 us"
for rate in 2000 10000 50000; do
  n=$((rate * 2))
  rps=()
  for i in $(seq 10); do P recv kelp $n 12 > "$T/f$i" 2>&1 & rps+=($!); done
  for i in $(seq 10); do ready "$T/f$i" || true; done
  P send kelp $n 100 $rate > "$T/s" 2>&1
  for p in "${rps[@]}"; do wait $p; done
  secs=$(grep -o 'in [0-9.]* s' "$T/s" | cut -d' ' -f2)
  tot=$(cat "$T"/f* | grep -o 'received [0-9]*' | awk '{t += $2} END {print t + 0}')
  p50=$(cat "$T"/f* | grep -o 'p50 [0-9]*' | awk '{print $2}' | sort -n | awk '{a[NR] = $1} END {print NR ? a[int((NR + 1) / 2)] : "-"}')
  p99=$(cat "$T"/f* | grep -o 'p99 [0-9]*' | awk '{print $2}' | sort -n | tail -1)
  dps=$(awk -v t=$tot -v s="${secs:-0}" 'BEGIN {printf "%.0f", (s > 0) ? t / s : 0}')
  printf '  %-10s %12s %14s %10s %10s\n' $rate "$tot/$((n * 10))" "$dps" "$p50" "${p99:--}"
done
rm -rf "$T"
