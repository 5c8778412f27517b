#!/usr/bin/env bash
# uTimerScript on the bus: nothing posts until its condition holds (GO = true); then TICK
# (script time 1); UTS_PAUSE = true holds the script even across UTS_FORWARD = 0 (a jump to
# FAR, script time 300); UTS_PAUSE = false lets FAR post at once, the pass ends (reset_time =
# all-posted) and TICK posts again; UTS_RESET = reset starts a third pass. Values carry
# $[TCOUNT], so the log shows the order; UTS_STATUS shows paused and the resets.
. "$(dirname "$0")/lib.sh"
cd "$T"
cat > t.moos <<'M'
Community = alpha
ServerPort = 9000
MOOSTimeWarp = 1
ProcessConfig = uTimerScript
{
  AppTick = 10
  event = var=TICK, val="tick=$[TCOUNT]", time=1
  event = var=FAR, val=$[TCOUNT], time=300
  reset_time = all-posted
  condition = GO = true
  script_name = ITEST
  seed = 7
}
M
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f t.lcmlog
sleep 0.5
bg "$BIN/uTimerScript" t.moos
sleep 2
"$BIN/kelp-poke" t.moos GO:=true > /dev/null || fail "poke GO"
sleep 1.5
"$BIN/kelp-poke" t.moos UTS_PAUSE:=true UTS_FORWARD=0 > /dev/null || fail "poke pause"
sleep 5.5 # a pause brings no status of its own (as in MOOS-IvP): the 5 s one shows it
"$BIN/kelp-poke" t.moos UTS_PAUSE:=false > /dev/null || fail "poke unpause"
sleep 1.5
"$BIN/kelp-poke" t.moos UTS_RESET:=reset > /dev/null || fail "poke reset"
sleep 2
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print t.lcmlog > t.txt || fail "log undecodable"
vals() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print}' t.txt | tr '\n' ' '; }
at() { awk -v v="$1" -v x="${2:-}" '$3==v && (x=="" || index($0, x)) {print $1; exit}' t.txt; }
[ "$(vals TICK)" = "tick=0 tick=2 tick=3 " ] || fail "TICK values: $(vals TICK) (expected tick=0 tick=2 tick=3)"
[ "$(vals FAR)" = "1 " ] || fail "FAR values: $(vals FAR) (expected one post, a number: 1)"
t_go=$(at GO); t_tick=$(at TICK); t_pause=$(at UTS_PAUSE true); t_unpause=$(at UTS_PAUSE false); t_far=$(at FAR)
t_reset=$(at UTS_RESET); t_tick3=$(at TICK tick=3)
awk -v a="$t_go" -v b="$t_tick" 'BEGIN{exit !(b > a + 0.8 && b < a + 1.6)}' || fail "TICK at $t_tick, GO at $t_go: expected ~1 s after"
awk -v a="$t_unpause" -v b="$t_far" -v p="$t_pause" 'BEGIN{exit !(b >= a && b < a + 0.5 && a > p + 1)}' \
  || fail "FAR at $t_far: expected right after the unpause at $t_unpause (paused at $t_pause)"
awk -v a="$t_reset" -v b="$t_tick3" 'BEGIN{exit !(b > a + 0.8 && b < a + 1.6)}' || fail "third TICK at $t_tick3, reset at $t_reset"
grep -q 'UTS_STATUS name=ITEST, .*paused=true' t.txt || fail "no status with paused=true"
grep -q 'UTS_STATUS name=ITEST, .*conditions_ok=false' t.txt || fail "no status with conditions_ok=false"
last=$(grep ' UTS_STATUS ' t.txt | tail -1)
echo "$last" | grep -q 'resets=2/any' || fail "last status: $last"
ok "TICK $(vals TICK)at $t_tick; paused at $t_pause; FAR at $t_far after the unpause at $t_unpause; reset at $t_reset, TICK at $t_tick3; $last"
