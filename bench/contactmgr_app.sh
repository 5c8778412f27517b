#!/usr/bin/env bash
# pContactMgrV20 as an app (make bench): the pContactMgrV20 program on the LCM bus (AppTick 4,
# an avoidance alert, CONTACT_RANGES on, max_contacts 2000), fed by bench_cmgr_feed with N
# contacts reporting at 1 Hz and ownship NAV_* at 4 Hz for 10 s, in a private network
# namespace. Figures: the app's CPU (utime + stime from /proc over the feeding window) as % of
# one core, reports sent, names in the last CONTACTS_LIST (cut at the 4 KB bus limit).
# Goal (issue 15): 500 contacts under 5% of one core.
set -uo pipefail
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ]; then export KELP_IN_NETNS=1; exec unshare -n bash "$0" "$@"; fi
if [ -n "${KELP_IN_NETNS:-}" ]; then ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true; fi
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Iinclude $(pkg-config --cflags lcm) -o "$B/bench/bench_cmgr_feed" \
  bench/bench_cmgr_feed.c "$B/libkelp.a" "$B/libkelp_core.a" $(pkg-config --libs lcm) -lexpat -lmbedtls -lmbedx509 \
  -lmbedcrypto -lserialport -lm -lpthread -lutil || exit 1
export KELP_LCM_URL="udpm://239.255.76.67:7798?ttl=0"
W=$(mktemp -d /tmp/kelp-cmbench.XXXXXX)
trap 'rm -rf "$W"' EXIT
cat > "$W/cm.moos" <<'M'
Community = abe
ProcessConfig = pContactMgrV20
{
  AppTick   = 4
  CommsTick = 4
  alert = id=avd, alert_range=80, cpa_range=100, on_flag=CONTACT_INFO=name=avd_$[VNAME] # contact=$[VNAME]
  max_contacts    = 2000
  post_all_ranges = true
}
M
tick=$(getconf CLK_TCK)
cpu_of() { awk '{print $14 + $15}' "/proc/$1/stat"; }
printf "%6s %10s %10s %10s\n" N "cpu %core" sent listed
for n in ${CMGR_BENCH_N:-10 100 500 2000}; do
  "$B/bin/pContactMgrV20" "$W/cm.moos" > "$W/app_$n.log" 2>&1 & app=$!
  sleep 1
  c0=$(cpu_of $app); t0=$(date +%s.%N)
  out=$("$B/bench/bench_cmgr_feed" "$n" 10)
  c1=$(cpu_of $app); t1=$(date +%s.%N)
  kill -INT $app; wait $app 2>/dev/null
  read -r _ _ N _ sent _ listed <<<"$out"
  pct=$(awk -v a="$c0" -v b="$c1" -v s="$t0" -v e="$t1" -v hz="$tick" 'BEGIN{printf "%.1f", 100 * (b - a) / hz / (e - s)}')
  printf "%6s %10s %10s %10s\n" "$N" "$pct" "$sent" "$listed"
done
