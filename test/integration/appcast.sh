#!/usr/bin/env bash
# AppCasting: every app of the Alder mission (kelp-launch under MOOSTimeWarp) answers
# APPCAST_REQ with an APPCAST in MOOS-IvP's format, and kelp-mac (the uMAC role) shows them:
#  - kelp-mac in a tmux terminal lists each app of the community (node, app, iteration, warning
#    counts), refreshed in place; key 2..: that app's cast; 'l' back to the list;
#  - a configuration warning of one app (an unknown parameter) reaches its cast;
#  - the casts on the bus parse (kelp-mac's list is built from parsed casts only, and the
#    logged APPCAST strings are checked field by field).
. "$(dirname "$0")/lib.sh"
cd "$T"
cp "$KELP_ROOT"/missions/alder/alder.moos "$KELP_ROOT"/missions/alder/alder.bhv .
sed -i "s/^MOOSTimeWarp *= *1 *$/MOOSTimeWarp = 5/" alder.moos
# an unknown parameter in pNodeReporter's block: a configuration warning in its cast
sed -i '/^ProcessConfig = pNodeReporter/,/^}/ s/^{$/{\n  NOT_A_PARAMETER = 1/' alder.moos
grep -q NOT_A_PARAMETER alder.moos || fail "could not add the bad parameter"
apps=$(sed -n 's/^ *Run *= *\([A-Za-z0-9_-]*\).*/\1/p' alder.moos | grep -v MOOSDB)
export KELP_WARP_EPOCH=$(date +%s.%N)
"$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f -q run.lcm > logger.out 2>&1 & PIDS+=($!)
sleep 0.5
"$BIN/kelp-launch" --run-seconds 40 --log-dir logs alder.moos > launch.out 2>&1 & PIDS+=($!)
sleep 1.5
command -v tmux > /dev/null || fail "tmux missing"
TM="tmux -L kelp-it-$$"
$TM -f /dev/null new-session -d -s mac -x 110 -y 45 "$BIN/kelp-mac $T/alder.moos; sleep 30" || fail "tmux would not start"
sleep 5
$TM capture-pane -p -t mac > pane1.txt
sleep 2
$TM capture-pane -p -t mac > pane2.txt
n=$(grep -nE '^[0-9]+ +alder +pNodeReporter ' pane1.txt | cut -d: -f2 | awk '{print $1}')
[ -n "$n" ] || { cat pane1.txt; fail "kelp-mac: no pNodeReporter row"; }
$TM send-keys -t mac "$n"
sleep 2
$TM capture-pane -p -t mac > pane3.txt
$TM send-keys -t mac l
sleep 2
$TM capture-pane -p -t mac > pane4.txt
$TM kill-server 2>/dev/null || true
for a in $apps; do
  grep -qE "^[0-9]+ +alder +$a +[1-9][0-9]* " pane1.txt || { cat pane1.txt; fail "kelp-mac: no cast from $a"; }
done
ok "kelp-mac lists every app of the mission: $(echo $apps)"
[ "$(grep -c '^# *node *app' pane1.txt)" -eq 1 ] || { cat pane1.txt; fail "the list is not drawn in place"; }
i1=$(awk '$3=="pHelmIvP" {print $4}' pane1.txt); i2=$(awk '$3=="pHelmIvP" {print $4}' pane2.txt)
[ -n "$i1" ] && [ -n "$i2" ] && [ "$i2" -gt "$i1" ] || { cat pane1.txt pane2.txt; fail "the list does not refresh ($i1 -> $i2)"; }
ok "refreshed in place (pHelmIvP iteration $i1 -> $i2)"
grep -qE '^pNodeReporter alder +1/[0-9]+\([0-9]+\)$' pane3.txt || { cat pane3.txt; fail "key $n: no pNodeReporter cast header"; }
grep -q 'Configuration Warnings: 1' pane3.txt && grep -q 'unknown parameter NOT_A_PARAMETER' pane3.txt ||
  { cat pane3.txt; fail "the configuration warning is not in the cast"; }
grep -qE '^[0-9]+ +alder +uSimMarine ' pane4.txt || { cat pane4.txt; fail "'l' did not go back to the list"; }
ok "key $n shows pNodeReporter's cast with its configuration warning; 'l' the list again"
sleep 1
kill -INT ${PIDS[0]} 2>/dev/null || true
sleep 0.5
"$BIN/kelp-logcheck" run.lcm --print > bus.txt 2> logcheck.err || true
for a in $apps; do
  line=$(grep -E "^[0-9.]+ +$a +APPCAST " bus.txt | tail -1)
  [ -n "$line" ] || fail "no APPCAST from $a on the bus"
  echo "$line" | grep -qE " APPCAST proc=$a!@#iter=[0-9]+!@#node=alder!@#iter=[0-9]+!@#messages=.*!@#events_total=[0-9]+!@#.*run_warning_total=[0-9]+!@#" ||
    fail "APPCAST of $a: $line"
done
grep -qE "^[0-9.]+ +uMAC +APPCAST_REQ +node=all,app=all,duration=3,key=kelp-mac_[0-9]+,thresh=any$" bus.txt || fail "no APPCAST_REQ from kelp-mac"
ok "APPCAST of every app in MOOS-IvP's format; kelp-mac's APPCAST_REQ"
