# Shared helpers for integration tests. Source it first thing:
#   . "$(dirname "$0")/lib.sh"
# It re-runs the test inside a private network namespace (loopback with a multicast route),
# so the test's LCM traffic never leaves it, and gives it a unique multicast port.
set -euo pipefail
if [ -z "${KELP_IN_NETNS:-}" ]; then
  export KELP_IN_NETNS=1
  if [ "$(id -u)" -eq 0 ]; then exec unshare -n bash "$0" "$@"; else exec unshare -rn bash "$0" "$@"; fi
fi
ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo 2>/dev/null || true
KELP_ROOT=${KELP_ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
BUILD=${BUILD:-$KELP_ROOT/build}
BIN=$BUILD/bin
TEST_NAME=$(basename "$0" .sh)
TEST_PORT=$((7700 + $(echo "$TEST_NAME" | cksum | cut -d' ' -f1) % 1000))
export KELP_LCM_URL="udpm://239.255.76.67:$TEST_PORT?ttl=0"
T=$(mktemp -d /tmp/kelp-$TEST_NAME.XXXXXX)
PIDS=()
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  [ -n "${KEEP_T:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
bg() { "$@" & PIDS+=($!); }
fail() { echo "FAIL: $*"; exit 1; }
ok() { echo "ok: $*"; }
# closest APP "x1,y1 x2,y2 ..." LOG: the closest approach (m, 2 decimals) of APP's NAV_X/NAV_Y
# postings in a kelp-logcheck --print listing to each point, one line, space separated
closest() {
  awk -v app="$1" -v pts="$2" '$2==app && $3=="NAV_X" {x=$4; hx=1; next}
     $2==app && $3=="NAV_Y" && hx {
       y=$4; n = split(pts, w, " ")
       for (i = 1; i <= n; i++) { split(w[i], p, ","); d = sqrt((x-p[1])^2 + (y-p[2])^2); if (m[i]=="" || d < m[i]) m[i] = d } }
     END { n = split(pts, w, " "); for (i = 1; i <= n; i++) printf "%.2f ", m[i]; print "" }' "$3"
}
# wait_for FILE PATTERN SECONDS
wait_for() {
  local f=$1 pat=$2 s=${3:-10} i=0
  while [ $i -lt $((s * 10)) ]; do
    grep -qE "$pat" "$f" 2>/dev/null && return 0
    sleep 0.1; i=$((i + 1))
  done
  return 1
}
