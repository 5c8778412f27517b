#!/usr/bin/env bash
# kelp-ivp cpa: one name=value line per quantity, values a script can check (head-on, crossing
# ahead of the contact, still vessels, bad input refused).
. "$(dirname "$0")/lib.sh"
cd "$T"
get() { sed -n "s/^$1=//p" out; }
"$BIN/kelp-ivp" cpa 100 0 270 2 0 0 90 2 > out || fail "head-on: exit $?"
[ "$(get cpa)" = 0 ] && [ "$(get tcpa)" = 25 ] && [ "$(get roc)" = 4 ] && [ "$(get range)" = 100 ] \
  || fail "head-on: $(tr '\n' ' ' < out)"
# as MOOS-IvP 24.8's CPAEngine: on the contact's bow line no crossing (bow distance: the range),
# the beam passed to starboard at 0
[ "$(get rel_bearing)" = 0 ] && [ "$(get abs_bearing)" = 90 ] && [ "$(get os_crosses_cn_bow)" = false ] \
  && [ "$(get os_crosses_cn_bow_dist)" = 100 ] && [ "$(get os_passes_cn_star)" = true ] \
  || fail "head-on bearings: $(tr '\n' ' ' < out)"
for k in cpa tcpa roc range bearing_rate rel_bearing abs_bearing os_fore_of_cn os_crosses_cn_bow \
         os_crosses_cn_stern_dist os_passes_cn_port os_passes_cn_star_dist; do
  grep -q "^$k=" out || fail "no $k line"
done
"$BIN/kelp-ivp" cpa -- 100 -110 0 2 0 0 90 2 0 > out || fail "crossing: exit $?"
[ "$(get os_crosses_cn_bow)" = true ] && [ "$(get os_crosses_cn_bow_dist)" = 10 ] \
  && [ "$(get os_passes_cn_star)" = true ] || fail "crossing: $(tr '\n' ' ' < out)"
"$BIN/kelp-ivp" cpa 30 40 0 0 0 0 0 0 > out || fail "still: exit $?"
[ "$(get cpa)" = 50 ] && [ "$(get tcpa)" = 0 ] || fail "still: $(tr '\n' ' ' < out)"
rc=0; "$BIN/kelp-ivp" cpa 1 2 3 x 0 0 0 0 > out 2> err || rc=$?
[ $rc -ne 0 ] && grep -q "not a number" err || fail "bad number accepted (rc $rc)"
rc=0; "$BIN/kelp-ivp" cpa 1 2 3 > out 2> err || rc=$?
[ $rc -ne 0 ] || fail "too few arguments accepted"
ok "kelp-ivp cpa: head-on, crossing, still, bad input"
