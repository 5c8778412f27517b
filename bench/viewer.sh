#!/usr/bin/env bash
# kelp-viewer (make bench): the pMarineViewer role with 500 vehicles at 4 Hz. bench_viewer_feed
# posts N vehicles' NODE_REPORTs on the bus (each on its own circle, so every report moves it
# and grows its trail) for 20 s, in a private network namespace; kelp-viewer serves the page to
# headless Chromium (bench/viewer_fps.py). Figures: kelp-viewer's CPU (utime + stime from
# /proc/PID/stat over the feeding window) as % of one core, and the page's frames drawn per
# second and stream messages applied per second once it shows every vehicle.
# Goal (issue 18): 500 vehicles, page >= 10 frames/s, kelp-viewer < 25% of one core.
set -uo pipefail
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ]; then export KELP_IN_NETNS=1; exec unshare -n bash "$0" "$@"; fi
if [ -n "${KELP_IN_NETNS:-}" ]; then ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true; fi
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
N=${VIEWER_BENCH_N:-500}
SECS=${VIEWER_BENCH_SECONDS:-20}
cd "$ROOT"
if [ ! -x /usr/bin/chromium ] || ! /usr/bin/python3 -c 'import selenium' 2>/dev/null; then
  echo "viewer bench: chromium / python3-selenium missing (scripts/deps.sh test)"; exit 0
fi
mkdir -p "$B/bench"
gcc -std=c11 -O2 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Iinclude $(pkg-config --cflags lcm) -o "$B/bench/bench_viewer_feed" \
  bench/bench_viewer_feed.c "$B/libkelp.a" "$B/libkelp_core.a" $(pkg-config --libs lcm) -lexpat -lmbedtls -lmbedx509 \
  -lmbedcrypto -lserialport -lm -lpthread -lutil || exit 1
export KELP_LCM_URL="udpm://239.255.76.67:7798?ttl=0"
W=$(mktemp -d /tmp/kelp-viewerbench.XXXXXX)
cleanup() { [ -n "${app:-}" ] && kill "$app" 2>/dev/null; [ -n "${page:-}" ] && kill "$page" 2>/dev/null; wait 2>/dev/null; rm -rf "$W"; }
trap cleanup EXIT
cat > "$W/v.moos" <<M
Community  = shoreside
LatOrigin  = 43.825300
LongOrigin = -70.330400
ProcessConfig = kelp-viewer
{
  AppTick       = 10
  port          = 0
  trails_length = 100
  button_one    = DEPLOY # DEPLOY_ALL=true
}
M
tick=$(getconf CLK_TCK)
cpu_of() { awk '{print $14 + $15}' "/proc/$1/stat"; }
"$B/bin/kelp-viewer" "$W/v.moos" > "$W/app.log" 2>&1 & app=$!
for i in $(seq 50); do grep -q '^kelp-viewer: http' "$W/app.log" && break; sleep 0.1; done
url=$(grep -o 'http://127.0.0.1:[0-9]*/' "$W/app.log" | head -1)
[ -n "$url" ] || { cat "$W/app.log"; echo "viewer bench: kelp-viewer did not start"; exit 1; }
/usr/bin/python3 bench/viewer_fps.py "$url" "$N" 10 > "$W/page.out" 2>&1 & page=$!
sleep 2
c0=$(cpu_of $app); t0=$(date +%s.%N)
feed=$("$B/bench/bench_viewer_feed" "$N" "$SECS")
c1=$(cpu_of $app); t1=$(date +%s.%N)
wait $page; page=
pct=$(awk -v a="$c0" -v b="$c1" -v s="$t0" -v e="$t1" -v hz="$tick" 'BEGIN{printf "%.1f", 100 * (b - a) / hz / (e - s)}')
read -r _ _ fps _ mps _ dms _ nv _ tr < <(grep '^page fps' "$W/page.out") || { cat "$W/page.out"; echo "viewer bench: page measure failed"; }
kill -INT $app; wait $app 2>/dev/null; app=
grep -E '^vehicles|^frames' "$W/app.log" | tail -2 | sed 's/^/  kelp-viewer: /'
printf "%6s %14s %10s %12s %10s %10s %12s\n" N "viewer %core" "page fps" "messages/s" "draw ms" vehicles "trail pts"
printf "%6s %14s %10s %12s %10s %10s %12s\n" "$N" "$pct" "${fps:--}" "${mps:--}" "${dms:--}" "${nv:--}" "${tr:--}"
echo "  ($feed; goal: page >= 10 fps, kelp-viewer < 25% of one core)"
