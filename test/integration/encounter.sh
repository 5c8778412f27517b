#!/usr/bin/env bash
# The encounter mission (missions/encounter/five.conf): five vehicles on head-on, crossing and
# overtaking tracks, each running pContactMgrV20 and the BHV_AvoidCollision template, contacts
# learned through the shoreside (uFldNodeComms relays). With avoidance:
#  - no pair comes closer than min_util_cpa_dist (closest approach from the shoreside's node
#    reports, exact between fixes: kelp-plot --closest);
#  - every vehicle spawned avoidance behaviours from the contact manager's alerts, and every
#    spawned behaviour died (was removed) once its contact had passed;
#  - every vehicle reaches its goal.
# The same mission with AVOID=false does bring a pair closer than min_util_cpa_dist (so the
# first check can fail).
. "$(dirname "$0")/lib.sh"
cd "$T"
MIN=$(sed -n 's/^ *min_util_cpa_dist *= *\([0-9.]*\).*/\1/p' "$KELP_ROOT/missions/encounter/meta_vehicle.bhv")
[ -n "$MIN" ] || fail "no min_util_cpa_dist in the template"
# MOOSTimeWarp 10: at 20 a loaded host (three tests at once, or ASan) lets the helms fall behind
# the simulated time and a pair can pass inside min_util_cpa_dist for that reason alone
run() { # DIR [--no-avoid]
  local d=$1; shift
  ENC_WARP=10 ENC_TIMEOUT=80 ENC_DIR="$T/$d" "$KELP_ROOT/scripts/encounter.sh" "$@" "$KELP_ROOT/missions/encounter/five.conf" \
    "$BUILD" > "$d.out" 2>&1 || { cat "$d.out"; tail -20 "$T/$d"/logs_*/pHelmIvP.log 2>/dev/null; fail "$d: not every vehicle reached its goal"; }
}
run avoid
cat avoid.out
pairs=$(grep -c '^closest ' avoid/plot.out || true)
[ "$pairs" -eq 10 ] || fail "avoid: $pairs pairs measured, want 10"
least=$(awk '/^closest / {print $4}' avoid/plot.out | sort -g | head -1)
awk -v a="$least" -v m="$MIN" 'BEGIN {exit !(a >= m)}' || fail "avoid: a pair came within $least m (min_util_cpa_dist $MIN)"
ok "with avoidance the closest pair is $least m apart (min_util_cpa_dist $MIN)"
for v in alpha bravo charlie delta echo; do
  l=$(grep -E "^   $v +alerts" avoid.out) || fail "no summary for $v"
  sp=$(echo "$l" | awk '{print $5}'); rm=$(echo "$l" | awk '{print $7}')
  [ "$sp" -ge 1 ] || fail "$v spawned no avoidance behaviour: $l"
  [ "$sp" -eq "$rm" ] || fail "$v: $sp spawned but $rm removed: $l"
done
ok "every vehicle spawned avoidance behaviours and every one was removed after its contact passed"
run noavoid --no-avoid
least0=$(awk '/^closest / {print $4}' noavoid/plot.out | sort -g | head -1)
awk -v a="$least0" -v m="$MIN" 'BEGIN {exit !(a < m)}' || { cat noavoid.out; fail "without avoidance no pair came within $MIN m ($least0)"; }
ok "without avoidance a pair comes within $least0 m"
