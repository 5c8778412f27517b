#!/usr/bin/env bash
# pContactMgrV20 on the bus: a mission alert and a helm-style BCM_ALERT_REQUEST; ownship by
# NAV_*, two contacts by NODE_REPORT (kelp-poke). The near one (15 m) raises both alerts'
# on_flags with macros expanded; CONTACTS_LIST is both names in order; a custom range report
# lists the near one; the PID is posted; -e/-h/-i/-v print and exit 0.
. "$(dirname "$0")/lib.sh"
cd "$T"
for o in -e -h -i -v; do "$BIN/pContactMgrV20" $o > opt.out 2>&1 || fail "pContactMgrV20 $o exited non-zero"; done
"$BIN/pContactMgrV20" -h | grep -q "contact manager" || fail "-h text"
cat > c.moos <<'M'
Community = abe
ProcessConfig = cmgr_abe
{
  AppTick = 4
  CommsTick = 4
  alert = id=avd, on_flag=CONTACT_INFO="name=avd_$[VNAME] # contact=$[VNAME]"
  alert = id=avd, off_flag=CONTACT_DONE=$[VNAME]
  alert = id=avd, alert_range=20, cpa_range=30
  post_closest_range = true
}
M
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f c.lcmlog
sleep 0.5
bg "$BIN/pContactMgrV20" c.moos cmgr_abe
sleep 1
"$BIN/kelp-poke" c.moos NAV_X=0 NAV_Y=0 NAV_HEADING=0 NAV_SPEED=0 > poke1.out 2>&1 || fail "poke: $(cat poke1.out)"
"$BIN/kelp-poke" c.moos "BCM_ALERT_REQUEST:=id=k8, on_flag=SAY_MOOS=alert_\$[VNAME]_\$[SPD], alert_range=20, cpa_range=40" \
  "BCM_REPORT_REQUEST:=var=CONTACTS_050, range=50" > poke2.out 2>&1 || fail "poke: $(cat poke2.out)"
sleep 0.5
"$BIN/kelp-poke" c.moos "NODE_REPORT:=NAME=gus,TYPE=kayak,X=0,Y=15,SPD=1.5,HDG=0" \
  "NODE_REPORT:=NAME=ben,TYPE=kayak,X=60,Y=80,SPD=0,HDG=0" "NODE_REPORT:=NAME=abe,X=0,Y=1" > poke3.out 2>&1 || fail "poke: $(cat poke3.out)"
sleep 1.5
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print c.lcmlog > c.txt || fail "log undecodable"
last() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); x=$0} END{print x}' c.txt; }
[ "$(last CONTACT_INFO)" = "name=avd_gus # contact=gus" ] || fail "CONTACT_INFO '$(last CONTACT_INFO)'"
# MOOS-IvP 24.8 never expands $[SPD] in a flag (its postAlert looks for "$[SPD}")
[ "$(last SAY_MOOS)" = 'alert_gus_$[SPD]' ] || fail "SAY_MOOS '$(last SAY_MOOS)'"
[ "$(last CONTACTS_LIST)" = "ben,gus" ] || fail "CONTACTS_LIST '$(last CONTACTS_LIST)'"
[ "$(last CONTACTS_ALERTED)" = "(gus,avd)(gus,k8)" ] || fail "CONTACTS_ALERTED '$(last CONTACTS_ALERTED)'"
[ "$(last CONTACTS_COUNT)" = 2 ] || fail "CONTACTS_COUNT '$(last CONTACTS_COUNT)'"
[ "$(last CONTACTS_050)" = gus ] || fail "CONTACTS_050 '$(last CONTACTS_050)'"
[ "$(last CONTACT_CLOSEST)" = gus ] || fail "CONTACT_CLOSEST '$(last CONTACT_CLOSEST)'"
[ "$(last CONTACT_CLOSEST_RANGE)" = 15 ] || fail "CONTACT_CLOSEST_RANGE '$(last CONTACT_CLOSEST_RANGE)'"
last CONTACTS_RECAP | grep -q "^vname=ben,range=100.00,age=" || fail "CONTACTS_RECAP '$(last CONTACTS_RECAP)'"
[ -n "$(last PCONTACTMGRV20_PID)" ] || fail "no PID posted"
[ -z "$(last PCONTACTMGR_PID)" ] || fail "PCONTACTMGR_PID is not 24.8's"
grep -q ' CONTACT_INFO ' c.txt && [ "$(grep -c ' CONTACT_INFO ' c.txt)" = 1 ] || fail "CONTACT_INFO posted $(grep -c ' CONTACT_INFO ' c.txt) times"
ok "CONTACT_INFO=$(last CONTACT_INFO); SAY_MOOS=$(last SAY_MOOS); CONTACTS_LIST=$(last CONTACTS_LIST); CONTACTS_ALERTED=$(last CONTACTS_ALERTED)"
