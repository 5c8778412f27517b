#!/usr/bin/env bash
# make demo: the pXRelay mission of seed 004 run through kelp-launch for a bounded time,
# seeded with a poke as the seed does (uPokeDB xrelay.moos APPLES=1), then a report.
# Runs inside a private network namespace when root (nothing leaves the machine); otherwise
# on the host bus with ttl=0.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
B=$(cd "${1:-$ROOT/build}" && pwd)
SECS=${DEMO_SECONDS:-8}
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ] && command -v unshare >/dev/null; then
  export KELP_IN_NETNS=1
  exec unshare -n "$0" "$@"
fi
if [ -n "${KELP_IN_NETNS:-}" ]; then
  ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true
fi
W=$ROOT/build/demo
rm -rf "$W"; mkdir -p "$W"; cd "$W"
cp "$ROOT/missions/xrelay/xrelay.moos" .
echo "== kelp demo: pXRelay mission (seed 004 section 3.8) for $SECS s"
"$B/bin/kelp-launch" --run-seconds "$SECS" --log-dir logs --report xrelay.moos > launch.out 2>&1 &
LP=$!
sleep 1.5
echo "== seeding the relay: kelp-poke xrelay.moos APPLES=1"
"$B/bin/kelp-poke" xrelay.moos APPLES=1
wait $LP; rc=$?
cat launch.out
echo "== uXMS (kelp-scope) at the end of the run:"
awk '/^VarName/{last=""; show=1} /^(=+)?$/{show=0} show{last=last $0 "\n"} END{printf "%s", last}' logs/uXMS.log
apples=$(grep -E '^  APPLES +' launch.out | awk '{print $2}')
pears=$(grep -E '^  PEARS +' launch.out | awk '{print $2}')
echo "== report: APPLES written ${apples:-0} times, PEARS ${pears:-0} times; launcher exit $rc"
[ "$rc" -eq 0 ] && [ "${apples:-0}" -gt 10 ] && [ "${pears:-0}" -gt 10 ]
