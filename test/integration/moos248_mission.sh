#!/usr/bin/env bash
# missions/moos248: a vehicle written as a stock MOOS-IvP 24.8 vehicle (uSimMarineV22,
# pMarinePIDV22, pHelmIvP, pNodeReporter, uTimerScript; 24.8's spellings and Run = names) runs
# unchanged on kelp: every app loads its block with no configuration warning, the helm stays
# parked until uTimerScript's DEPLOY / MOOS_MANUAL_OVERRIDE, the survey and the return complete
# (MISSION = complete), every waypoint is reached, and the variables 24.8 posts are there.
. "$(dirname "$0")/lib.sh"
[ -x "$BIN/kelp-record" ] || fail "kelp-record not built"
cd $T
cp $KELP_ROOT/missions/moos248/alpha.moos $KELP_ROOT/missions/moos248/alpha.bhv .
WARP=10   # the mission's 4, sped up for the test
sed -i "s/^MOOSTimeWarp *= *4 *$/MOOSTimeWarp = $WARP/" alpha.moos
grep -q "^MOOSTimeWarp = $WARP$" alpha.moos || fail "could not set the warp"
export KELP_WARP_EPOCH=$(date +%s.%N)
"$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f -q run.lcm > logger.out 2>&1 & LG=$!; PIDS+=($LG)
sleep 1
$BIN/kelp-launch --run-seconds 120 --log-dir logs alpha.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
# the survey and the return take about 180 s of MOOS time: 18 s at warp 10 (up to a minute on a
# loaded machine; the launcher's own limit is beyond that)
for i in $(seq 1 40); do
  sleep 2 # each look decodes the whole log: not too often
  $BIN/kelp-logcheck run.lcm --print 2>/dev/null | grep -qE " pHelmIvP MISSION complete$" && break
done
sleep 0.5
kill -TERM $LP 2>/dev/null || true
wait $LP || { cat launch.out; fail "launcher did not end cleanly"; }
kill -INT $LG; wait $LG 2>/dev/null || true
for app in uSimMarineV22 pMarinePIDV22 pHelmIvP pNodeReporter uTimerScript; do
  f=$(ls logs/$app*.log 2>/dev/null | head -1)
  [ -n "$f" ] || { ls logs; fail "no log of $app"; }
  grep -q "Configuration warnings: 0" "$f" || { grep -A8 "Configuration warnings" "$f"; fail "$app: configuration warnings"; }
done
$BIN/kelp-logcheck run.lcm --print > log.txt || fail "log does not decode"
grep -qE "^[0-9.]+ pHelmIvP MISSION complete$" log.txt ||
  { tail -20 logs/pHelmIvP*.log; tail -12 logs/pMarinePIDV22*.log; fail "the mission did not complete"; }
# parked until uTimerScript's override: PARK first, DRIVE later
awk '$2=="pHelmIvP" && $3=="IVPHELM_STATE" {print $4}' log.txt | uniq > states.txt
[ "$(head -1 states.txt)" = PARK ] && grep -qx DRIVE states.txt || { cat states.txt; fail "the helm should start parked, then drive"; }
# from DRIVE to MISSION = complete the helm never posts DESIRED_SPEED 0, not even in the iteration
# between the survey's end and the return (24.8's postAllStop holds one iteration)
awk '$2=="pHelmIvP" && $3=="IVPHELM_STATE" && $4=="DRIVE" && !done {d=1}
     $2=="pHelmIvP" && $3=="MISSION" {d=0; done=1}
     d && $2=="pHelmIvP" && $3=="DESIRED_SPEED" && $4==0 {z++}
     END {exit z > 0}' log.txt || fail "DESIRED_SPEED 0 posted while driving the survey"
# every survey point, then home
closest uSimMarineV22 "60,-40 60,-100 100,-100 100,-40 0,-20" log.txt > closest.txt
read -a C < closest.txt
for i in 0 1 2 3; do
  awk -v d="${C[$i]}" 'BEGIN{exit !(d <= 15)}' || fail "waypoint $((i+1)) missed: closest ${C[$i]} m (all: ${C[*]})"
done
awk -v d="${C[4]}" 'BEGIN{exit !(d <= 8)}' || fail "not home: closest ${C[4]} m to (0,-20)"
# variables MOOS-IvP 24.8 posts on this mission
for v in SIMULATION_MODE USM_DRIFT_SUMMARY PID_HAS_CONTROL IVPHELM_LEDGER_SUMMARY IVPHELM_COMPLETED_PENDING \
         IVPHELM_MODESET TURN_RATE PLOGGER_CMD MOOS_DEBUG PHELMIVP_PID PNODEREPORTER_PID WPT_ODO; do
  awk -v v=$v '$3==v {f=1} END{exit !f}' log.txt || fail "no $v posted"
done
grep -qE " pNodeReporter NODE_REPORT_LOCAL NAME=alpha,X=[-0-9.]+,Y=[-0-9.]+,SPD=[0-9.]+,HDG=[0-9.]+,DEP=" log.txt ||
  fail "no NODE_REPORT_LOCAL in 24.8's layout"
ok "24.8 vehicle: no configuration warning, parked until DEPLOY, survey closest ${C[*]} m, MISSION complete"
