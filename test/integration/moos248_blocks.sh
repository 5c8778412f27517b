#!/usr/bin/env bash
# MOOS-IvP 24.8 mission blocks, written from the apps' own --example output
# (test/data/moos-24.8/*.moos), load in kelp's apps with no configuration warning, and the
# app runs on them.
. "$(dirname "$0")/lib.sh"
cd "$T"
D="$KELP_ROOT/test/data/moos-24.8"
for f in "$D"/*.moos; do
  app=$(basename "$f" .moos)
  prog=${app%V22}   # pMarinePIDV22 and uSimMarineV22 are kelp's pMarinePID and uSimMarine
  [ "$app" = pShare ] && prog=kelp-bridge   # pShare is kelp-bridge running as pShare
  [ -x "$BIN/$prog" ] || fail "no kelp program $prog for $f"
  rc=0
  timeout -s INT 2 "$BIN/$prog" "$f" --alias "$app" > "$app.out" 2>&1 || rc=$?
  [ $rc -eq 0 ] || [ $rc -eq 124 ] || { cat "$app.out"; fail "$app exited $rc on its 24.8 block"; }
  grep -q "Configuration warnings: 0" "$app.out" || { grep -A8 "Configuration warnings" "$app.out"; fail "$app: configuration warnings on its 24.8 block"; }
  ok "$app loads MOOS-IvP 24.8's example block with no configuration warning"
done
# and pNodeReporter runs on it: JSON reports (json_report = true) with the block's fields
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f n.lcmlog
sleep 0.5
bg "$BIN/pNodeReporter" "$D/pNodeReporter.moos"
sleep 0.5
"$BIN/kelp-poke" "$D/pNodeReporter.moos" NAV_X=10 NAV_Y=20 NAV_SPEED=1.5 NAV_HEADING=90 NAV_DEPTH=3 DB_UPTIME=7.25 > /dev/null
sleep 1.5
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print n.lcmlog > n.txt || fail "log undecodable"
line=$(grep ' NODE_REPORT_LOCAL ' n.txt | tail -1)
echo "$line" | grep -q '{"NAME":"alpha","X":' || fail "not the JSON report (24.8's order): $line"
for k in '"TYPE":"glider"' '"COLOR":"green"' '"GROUP":"tango"' '"ID":439' '"FUEL_TYPE":"diesel"' '"upt":7.250' '"LENGTH":8' '"HDG":95,' '"DEP":3,'; do
  echo "$line" | grep -qF "$k" || fail "no $k in $line"
done
ok "pNodeReporter on the 24.8 block: $line"

# pHelmIvP on its block: hold_on_apps holds the helm until both apps have reported
rm -f h.lcmlog
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f h.lcmlog
sleep 0.5
bg "$BIN/pHelmIvP" "$D/pHelmIvP.moos"
sleep 1.5
"$BIN/kelp-poke" "$D/pHelmIvP.moos" PBASICCONTACTMGR_STATUS:=up > /dev/null
sleep 1
"$BIN/kelp-poke" "$D/pHelmIvP.moos" PTASKMANAGER_STATUS:=up > /dev/null
sleep 1.5
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print h.lcmlog > h.txt || fail "helm log undecodable"
t_first=$(awk '$3=="IVPHELM_STATE"{print $1; exit}' h.txt)
t_hold=$(awk '$3=="PTASKMANAGER_STATUS"{print $1; exit}' h.txt)
[ -n "$t_first" ] && [ -n "$t_hold" ] || fail "no IVPHELM_STATE ($t_first) or no poke ($t_hold)"
awk -v a="$t_first" -v b="$t_hold" 'BEGIN{exit !(a >= b)}' || fail "the helm ran at $t_first before the last held app reported at $t_hold"
grep -q ' IVPHELM_STATE PARK' h.txt || fail "start_engaged = false: the helm should start parked"
ok "pHelmIvP: held until $t_hold, then IVPHELM_STATE at $t_first, parked (start_engaged = false)"
