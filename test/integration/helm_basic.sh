# pHelmIvP on a real bus with the seed's Alder behaviour file (two BHV_SimpleWaypoint):
# nothing to do before DEPLOY (all-stop zeros), then with NAV_X/NAV_Y poked at (0,0) and
# DEPLOY=true it steers toward (60,-40) at 2 m/s (relAng 123.69 -> course 124 on the 1-degree
# grid); at (58,-38) it arrives, posts its endflag RETURN=true, and waypt_return (the
# Reflector) turns the vehicle home (bearing from (58,-38) to (0,0) is 303.2 degrees).
. "$(dirname "$0")/lib.sh"
cd $T
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cat > alder.bhv <<'B'
//----- FILE: alder.bhv -----
initialize  DEPLOY = false
initialize  RETURN = false

Behavior = BHV_SimpleWaypoint
{
    name      = transit_to_point
    pwt       = 100
    condition = RETURN = false
    condition = DEPLOY = true
    endflag   = RETURN = true

    speed = 2.0 // meters per second
    radius = 8.0
    ptx = 60
    pty = -40
    ipf_type = zaic
}

Behavior = BHV_SimpleWaypoint
{
    name      = waypt_return
    pwt       = 100
    condition = RETURN = true
    condition = DEPLOY = true
    speed = 2.0
    radius = 8.0
    ptx = 0
    pty = 0
    ipf_type = reflector
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
sleep 1   # the logger must be listening before anything starts
bg $BIN/pHelmIvP alder.moos > helm.out 2>&1
sleep 1.0
$BIN/kelp-poke alder.moos NAV_X=0 NAV_Y=0 > /dev/null
sleep 0.5
$BIN/kelp-poke alder.moos DEPLOY:=true > /dev/null
sleep 1.0
$BIN/kelp-poke alder.moos NAV_X=58 NAV_Y=-38 > /dev/null
sleep 1.0
# a loaded host may take longer than a second for the arrival's iteration: up to 10 s more
for _ in $(seq 1 20); do
  $BIN/kelp-logcheck run.lcmlog --print 2>/dev/null | grep -q " pHelmIvP RETURN true" && break
  sleep 0.5
done
kill -INT $LG; wait $LG 2>/dev/null || true
$BIN/kelp-logcheck run.lcmlog --print > log.txt || { tail helm.out; fail "log does not decode"; }
grep -q " pHelmIvP DEPLOY false" log.txt || { grep DEPLOY log.txt; fail "initialize DEPLOY = false not published"; }
grep -q " pHelmIvP IVPHELM_ALLSTOP NothingToDo" log.txt || fail "no NothingToDo all-stop before DEPLOY"
grep -q " pHelmIvP DESIRED_SPEED 0" log.txt || fail "no all-stop zero speed"
# after DEPLOY: heading toward the waypoint at 2 m/s
awk '$3=="DESIRED_HEADING"{print $4}' log.txt | grep -qx "124" || { grep DESIRED log.txt | tail; fail "no DESIRED_HEADING 124 toward (60,-40)"; }
awk '$3=="DESIRED_SPEED"{print $4}' log.txt | grep -qx "2" || fail "no DESIRED_SPEED 2"
grep -q "VIEW_POINT .*x=60,y=-40,active=true" log.txt || fail "no VIEW_POINT for the waypoint"
grep -qE " pHelmIvP IVPHELM_BHV_ACTIVE transit_to_point" log.txt || fail "transit_to_point never active"
# arrival: endflag, then the return leg
grep -q " pHelmIvP RETURN true" log.txt || fail "endflag RETURN=true not posted"
grep -qE " pHelmIvP IVPHELM_BHV_ACTIVE waypt_return" log.txt || fail "waypt_return never active"
last=$(awk '$3=="DESIRED_HEADING"{h=$4} END{print h}' log.txt)
awk -v h="$last" 'BEGIN{exit !(h > 290 && h < 316)}' || fail "return heading $last not toward (0,0) (303.2)"
ok "deploy -> heading 124 speed 2, arrival -> RETURN=true, return heading $last"
