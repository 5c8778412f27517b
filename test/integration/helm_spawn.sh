# pHelmIvP with a BHV_AvoidCollision template on a real bus: at start the template posts its
# BCM_ALERT_REQUEST; a contact manager style alert (CONTACT_INFO=name=bob # contact=bob) spawns
# avd_bob, which steers off the head-on course (DESIRED_HEADING not 90) beside a waypoint
# behaviour; when bob's report puts it past 1.1 x completed_dist the instance dies.
. "$(dirname "$0")/lib.sh"
cd $T
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cat > alder.bhv <<'B'
Behavior = BHV_Waypoint
{
    name   = transit
    pwt    = 100
    speed  = 2
    points = 400,0
}
Behavior = BHV_AvoidCollision
{
    name              = avd_
    pwt               = 300
    updates           = CONTACT_INFO
    templating        = spawn
    contact           = to-be-set
    on_no_contact_ok  = true
    extrapolate       = false
    pwt_outer_dist    = 150
    pwt_inner_dist    = 50
    completed_dist    = 160
    min_util_cpa_dist = 10
    max_util_cpa_dist = 40
}
B
cat > alder.moos <<'M'
ServerHost = localhost
ServerPort = 9000
Community  = alder
MOOSTimeWarp = 1

ProcessConfig = pHelmIvP
{
  AppTick    = 10
  CommsTick  = 10
  Behaviors  = alder.bhv
  start_engaged = true   // drive from the start (24.8 parks until MOOS_MANUAL_OVERRIDE = false)
  Verbose    = quiet
  Domain     = course:0:359:360
  Domain     = speed:0:4:21
}
M
$BIN/kelp-record --lcm-url="$KELP_LCM_URL" -f run.lcmlog > logger.out 2>&1 & LG=$!
PIDS+=($LG)
sleep 1
bg $BIN/pHelmIvP alder.moos > helm.out 2>&1
sleep 1.0
$BIN/kelp-poke alder.moos NAV_X=0 NAV_Y=0 NAV_HEADING=90 NAV_SPEED=2 > /dev/null
$BIN/kelp-poke alder.moos "NODE_REPORT:=NAME=bob,TYPE=kayak,X=60,Y=0,SPD=2,HDG=270" > /dev/null
sleep 0.5
$BIN/kelp-poke alder.moos "CONTACT_INFO:=name=bob # contact=bob" > /dev/null
sleep 1.0
$BIN/kelp-poke alder.moos "NODE_REPORT:=NAME=bob,TYPE=kayak,X=250,Y=0,SPD=2,HDG=90" > /dev/null
sleep 1.0
kill -INT $LG; wait $LG 2>/dev/null || true
$BIN/kelp-logcheck run.lcmlog --print > log.txt || { tail helm.out; fail "log does not decode"; }
grep -q "BCM_ALERT_REQUEST id=avd_, on_flag=CONTACT_INFO=name=\$\[VNAME\] # contact=\$\[VNAME\],alert_range=150, cpa_range=160" log.txt \
  || { grep BCM log.txt; fail "no alert request from the template"; }
grep -q "IVPHELM_LIFE_EVENT .*bname=avd_bob, btype=BHV_AvoidCollision, event=spawn" log.txt \
  || { grep LIFE log.txt; tail helm.out; fail "avd_bob not spawned"; }
grep -qE "IVPHELM_BHV_ACTIVE .*avd_bob" log.txt || fail "avd_bob never active"
# while bob closes head-on, the decision leaves course 90
awk '$3=="DESIRED_HEADING" && $4!=90 && $4!=0 {f=1} END{exit !f}' log.txt \
  || { grep DESIRED_HEADING log.txt | sort | uniq -c | head; fail "no avoiding heading"; }
grep -q "IVPHELM_LIFE_EVENT .*bname=avd_bob, btype=BHV_AvoidCollision, event=death" log.txt \
  || { grep LIFE log.txt; fail "avd_bob not removed after bob opened past completed_dist"; }
ok "alert request, spawn on CONTACT_INFO, avoiding heading, death past completed_dist"
