#!/usr/bin/env bash
# uFldNodeComms as an app (make bench): the uFldNodeComms program on the LCM bus, fed by
# bench_ncomms_feed with N vehicles 60 m apart reporting at 4 Hz (comms range 100 m, critical
# 30 m, report pulses on) for 10 s, in a private network namespace. Figures: the app's CPU
# (utime + stime from /proc over the feeding window) as % of one core, relays made / relays
# owed (pairs within range, brute force), reports sent. Goals: 500 vehicles under 25% of one
# core and 2,000 under 50% (issue 28), every owed relay made. The largest N runs a second time
# with gso=0 in the URL (each datagram its own send, as before segmented sends) for comparison.
set -uo pipefail
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ]; then export KELP_IN_NETNS=1; exec unshare -n bash "$0" "$@"; fi
if [ -n "${KELP_IN_NETNS:-}" ]; then ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true; fi
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Iinclude $(pkg-config --cflags lcm) -o "$B/bench/bench_ncomms_feed" \
  bench/bench_ncomms_feed.c "$B/libkelp.a" "$B/libkelp_core.a" $(pkg-config --libs lcm) -lexpat -lmbedtls -lmbedx509 \
  -lmbedcrypto -lserialport -lm -lpthread -lutil || exit 1
# the shoreside publishes ~60,000 relays and as many pulses a second: it asks for a 4 MB send
# buffer (kelp's send_buf_size; the kernel's default 208 KB fills whenever the loopback's
# delivery falls behind, and each full buffer puts the sender to sleep)
export KELP_LCM_URL="udpm://239.255.76.67:7799?ttl=0&send_buf_size=${NCOMMS_SNDBUF:-4194304}"
W=$(mktemp -d /tmp/kelp-ncbench.XXXXXX)
trap 'rm -rf "$W"' EXIT
cat > "$W/nc.moos" <<M
Community = shoreside
ProcessConfig = uFldNodeComms
{
  AppTick              = 10   // relays are made per iteration for each vehicle's newest report
  CommsTick            = 10   // (as MOOS-IvP's): iterate faster than the 4 Hz reports
  COMMS_RANGE          = 100
  CRITICAL_RANGE       = 30
  STALE_TIME           = 5
  VIEW_NODE_RPT_PULSES = true
  VERBOSE              = false
}
M
tick=$(getconf CLK_TCK)
cpu_of() { awk '{print $14 + $15}' "/proc/$1/stat"; }
sys_of() { awk '{print $15}' "/proc/$1/stat"; }
ksirq() { ps -eo comm=,time= | awk '/^ksoftirqd/ {split($2,a,":"); s += a[1]*3600 + a[2]*60 + a[3]} END {print s + 0}'; }
printf "%6s %10s %8s %10s %10s %10s %10s\n" N "cpu %core" "sys %" relayed owed sent "us/post"
NS=${NCOMMS_BENCH_N:-10 100 500 2000}
GSO_URL=$KELP_LCM_URL
for n in $NS ${NS##* }:plain; do
  plain=0
  case $n in *:plain) n=${n%:plain}; plain=1; export KELP_LCM_URL="$GSO_URL&gso=0" ;; *) export KELP_LCM_URL=$GSO_URL ;; esac
  [ "${NCOMMS_PLAIN:-1}" = 0 ] && [ $plain = 1 ] && continue
  "$B/bin/uFldNodeComms" "$W/nc.moos" > "$W/app_$n.log" 2>&1 & app=$!
  sleep 1
  c0=$(cpu_of $app); s0=$(sys_of $app); k0=$(ksirq); t0=$(date +%s.%N)
  out=$("$B/bench/bench_ncomms_feed" "$n" 10 2>"$W/feed_$n.err")
  # where relays are lost: the feeder's socket (datagrams read, queue drops), the app's report
  # (mail received, published, transport drops), the kernel (/proc/net/udp drops)
  c1=$(cpu_of $app); s1=$(sys_of $app); k1=$(ksirq); t1=$(date +%s.%N)
  kill -INT $app; wait $app 2>/dev/null
  posts=$(sed -n 's/^Sent: \([0-9]*\) messages.*/\1/p' "$W/app_$n.log" | tail -1)
  if [ "$n" = "${NS##* }" ] && [ $plain = 0 ]; then
    cat "$W/feed_$n.err"; grep -E "^(Mail|Transport|Sent):" "$W/app_$n.log" | tail -3
    echo "kernel's ksoftirqd threads (network delivery deferred from the senders): $(awk -v a="$k0" -v b="$k1" 'BEGIN{print b - a}') s of CPU in the window"
    awk '/^uFldNodeComms/ {it=$NF} /elapsed/ {for (i=1;i<=NF;i++) if ($i=="elapsed") el=$(i+1)} END {if (el>0) printf "app: %d iterations in %.1f s: %.1f Hz (AppTick 10)\n", it, el, it/el}' "$W/app_$n.log"
  fi >&2
  read -r _ _ N _ _ _ rel _ owed _ sent <<<"$out"
  pct=$(awk -v a="$c0" -v b="$c1" -v s="$t0" -v e="$t1" -v hz="$tick" 'BEGIN{printf "%.1f", 100 * (b - a) / hz / (e - s)}')
  spct=$(awk -v a="$s0" -v b="$s1" -v c0="$c0" -v c1="$c1" 'BEGIN{printf "%.0f", (c1 > c0 ? 100 * (b - a) / (c1 - c0) : 0)}')
  # CPU per posting (relays, pulses, status) over the app's whole run (its CPU is nearly all
  # in the feeding window)
  upp=$(awk -v b="$c1" -v hz="$tick" -v p="${posts:-0}" 'BEGIN{printf "%.1f", (p > 0 ? 1e6 * b / hz / p : 0)}')
  mark=""; [ "${rel:-0}" = "${owed:-x}" ] || mark="  (relayed != owed)"
  [ $plain = 1 ] && mark="$mark  (gso=0: one send per datagram)"
  printf "%6s %10s %8s %10s %10s %10s %10s%s\n" "$N" "$pct" "$spct" "$rel" "$owed" "$sent" "$upp" "$mark"
done
