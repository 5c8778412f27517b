#!/usr/bin/env bash
# One simulated vehicle stack (make bench): missions/moos248 (uSimMarineV22, pMarinePIDV22,
# pHelmIvP, pNodeReporter, uTimerScript as a stock MOOS-IvP 24.8 vehicle) under kelp-launch at
# MOOSTimeWarp 10, in a private network namespace when run as root. Figures: each app's CPU
# (utime + stime from /proc over a 12 s window while the vehicle flies its survey) as % of one
# core, and the stack's total.
set -uo pipefail
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ]; then export KELP_IN_NETNS=1; exec unshare -n bash "$0" "$@"; fi
if [ -n "${KELP_IN_NETNS:-}" ]; then ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true; fi
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
export KELP_LCM_URL="udpm://239.255.76.67:7799?ttl=0"
W=$(mktemp -d /tmp/kelp-vsbench.XXXXXX)
trap 'rm -rf "$W"' EXIT
cp "$ROOT/missions/moos248/alpha.moos" "$ROOT/missions/moos248/alpha.bhv" "$W/"
sed -i 's/^MOOSTimeWarp *= *4 *$/MOOSTimeWarp = 10/' "$W/alpha.moos"
tick=$(getconf CLK_TCK)
cpu_of() { awk '{print $14 + $15}' "/proc/$1/stat" 2>/dev/null || echo 0; }
(cd "$W" && exec "$B/bin/kelp-launch" --run-seconds 20 --log-dir logs alpha.moos) > "$W/launch.out" 2>&1 & lp=$!
sleep 3   # started, deployed (uTimerScript: 5 s of MOOS time), flying
declare -A pid c0
for app in uSimMarine pMarinePID pHelmIvP pNodeReporter uTimerScript; do
  pid[$app]=$(pgrep -P "$lp" -x "$app" | head -1)
  [ -n "${pid[$app]}" ] || { echo "bench vehicle_stack: $app not running"; cat "$W/launch.out"; exit 1; }
done
t0=$(date +%s.%N)
for app in "${!pid[@]}"; do c0[$app]=$(cpu_of "${pid[$app]}"); done
sleep 12
t1=$(date +%s.%N)
printf "%-16s %10s\n" app "cpu %core"
total=0
for app in uSimMarine pMarinePID pHelmIvP pNodeReporter uTimerScript; do
  c1=$(cpu_of "${pid[$app]}")
  pct=$(awk -v a="${c0[$app]}" -v b="$c1" -v s="$t0" -v e="$t1" -v hz="$tick" 'BEGIN{printf "%.2f", 100 * (b - a) / hz / (e - s)}')
  total=$(awk -v t="$total" -v p="$pct" 'BEGIN{printf "%.2f", t + p}')
  printf "%-16s %10s\n" "$app" "$pct"
done
printf "%-16s %10s   (MOOSTimeWarp 10)\n" total "$total"
wait $lp 2>/dev/null
