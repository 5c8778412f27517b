#!/usr/bin/env bash
# pShare's multicast channels and an output's limits, as MOOS-IvP 24.8 applies them: two
# communities on one host (kelp-bridge as pShare), the vehicle's outputs on multicast_7
# (224.1.1.11:24467 by default; the shore listens with `input = route = multicast_7`) and one
# output on a second group set by multicast_address / multicast_base_port. Limits: `@2` (two
# shares a second at most), max_shares = 3, duration = 3 (s: it ends while the values
# still come), and duration = 0 stated again at
# run time (the latest value once). Each is checked on what the shore receives.
. "$(dirname "$0")/lib.sh"
cd "$T"
cat > veh.moos <<'M'
ServerPort = 9101
Community  = veh
LCM_URL    = udpm://239.255.76.67:7801?ttl=0
ProcessConfig = pShare
{
  AppTick = 10
  output = src_name = FAST, dest_name = FAST_IN, route = multicast_7
  output = SLOW->SLOW_IN:multicast_7@2
  output = src_name = FEW, route = multicast_7, max_shares = 3
  output = src_name = BRIEF, route = multicast_7, duration = 3
}
ProcessConfig = pShare2
{
  multicast_address   = 239.1.2.3
  multicast_base_port = 30000
  output = src_name = OTHER, route = multicast_4
}
M
cat > shore.moos <<'M'
ServerPort = 9100
Community  = shore
LCM_URL    = udpm://239.255.76.67:7800?ttl=0
ProcessConfig = pShare
{
  input = route = multicast_7
}
ProcessConfig = pShare2
{
  multicast_address   = 239.1.2.3
  multicast_base_port = 30000
  input = route = multicast_4
}
M
bg env -u KELP_LCM_URL "$BIN/kelp-record" --lcm-url="udpm://239.255.76.67:7800?ttl=0" -f shore.lcmlog
bg env -u KELP_LCM_URL "$BIN/kelp-bridge" shore.moos pShare > shore1.out 2>&1
bg env -u KELP_LCM_URL "$BIN/kelp-bridge" shore.moos pShare2 > shore2.out 2>&1
bg env -u KELP_LCM_URL "$BIN/kelp-bridge" veh.moos pShare > veh1.out 2>&1
bg env -u KELP_LCM_URL "$BIN/kelp-bridge" veh.moos pShare2 > veh2.out 2>&1
sleep 1.5
poke() { env -u KELP_LCM_URL "$BIN/kelp-poke" veh.moos "$@" > /dev/null || fail "poke $*"; }
# 20 values of each, 0.1 s apart (2 s); kelp-poke prints the values after its post (0.6 s),
# so each runs in the background and posts on time
pp=()
for i in $(seq 1 20); do
  env -u KELP_LCM_URL "$BIN/kelp-poke" veh.moos FAST=$i SLOW=$i FEW=$i BRIEF=$i > poke$i.out 2>&1 & pp+=($!)
  sleep 0.1
done
for p in "${pp[@]}"; do wait "$p" || fail "a poke failed: $(cat poke*.out | tail -3)"; done
poke OTHER=42
sleep 1 # BRIEF's 3 s are over by now: this one is not shared
poke BRIEF=99
# duration = 0 stated again at run time: FEW's latest value (20) once more, then nothing
poke "PSHARE_CMD:=cmd=output,src_name=FEW,route=multicast_7,duration=0"
sleep 0.5
poke FEW=77
sleep 1
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print shore.lcmlog > shore.txt || fail "shore log undecodable"
count() { awk -v v="$1" '$3==v' shore.txt | wc -l; }
vals() { awk -v v="$1" '$3==v {print $4}' shore.txt | tr '\n' ' '; }
[ "$(count FAST_IN)" -eq 20 ] || fail "FAST_IN: $(count FAST_IN) of 20 arrived over multicast_7 ($(vals FAST_IN))"
ok "multicast_7: 20 of 20 values, renamed FAST -> FAST_IN"
n=$(count SLOW_IN)
[ "$n" -ge 3 ] && [ "$n" -le 6 ] || fail "SLOW_IN @2 over ~2 s: $n shares ($(vals SLOW_IN))"
ok "SLOW@2: $n shares of 20 values over 2 s ($(vals SLOW_IN))"
# the pokes run as separate processes 0.1 s apart: a loaded host may start one late, so the
# order they posted in is FAST_IN's (every value shared, same route), not necessarily 1..20
order=$(vals FAST_IN)
read -ra ord <<< "$order"
few_want="${ord[0]} ${ord[1]} ${ord[2]} ${ord[19]} "
[ "$(vals FEW)" = "$few_want" ] || fail "FEW max_shares=3 then duration=0: '$(vals FEW)', wanted '$few_want' (posting order: $order)"
ok "FEW: max_shares = 3, then duration = 0 restated: the latest value once ($few_want)"
b=$(vals BRIEF)
case "$b" in *99*) fail "BRIEF shared after its 3 s duration: $b" ;; esac
n=$(count BRIEF)
[ "$n" -ge 1 ] && [ "$n" -le 19 ] || fail "BRIEF: $n shares; wanted the first ones only, until 3 s after the start ($b)"
brief_want=$(echo "${ord[@]:0:$n}" | tr -s ' ')" "
[ "$(vals BRIEF)" = "$brief_want" ] || fail "BRIEF: not the first $n values in posting order: $b (posting order: $order)"
ok "BRIEF: the first $n values (until 3 s after the start), none after"
[ "$(vals OTHER)" = "42 " ] || fail "OTHER over 239.1.2.3:30004: '$(vals OTHER)'"
ok "multicast_address / multicast_base_port: OTHER over 239.1.2.3:30004"
grep -q 'PSHARE_INPUT_SUMMARY' shore.txt || fail "no PSHARE_INPUT_SUMMARY"
