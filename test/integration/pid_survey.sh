#!/usr/bin/env bash
# missions/pid: helm + pMarinePID + uSimMarine (rudder/thrust model) under MOOSTimeWarp 10.
# From the log: the helm completes the survey (MISSION=complete), the track comes within
# the capture radius (5 m) of every waypoint, pMarinePID drove the rudder and thrust, and
# the vehicle slowed in its turns (NAV_SPEED well below the 2 m/s cruise while the rudder
# was hard over) and cruised at 2 m/s on the legs.
. "$(dirname "$0")/lib.sh"
[ -x "$BIN/kelp-record" ] || fail "kelp-record not built"
cd $T
cp $KELP_ROOT/missions/pid/pid.moos $KELP_ROOT/missions/pid/pid.bhv .
WARP=10
sed -i "s/^MOOSTimeWarp *= *1 *$/MOOSTimeWarp = $WARP/" pid.moos
export KELP_WARP_EPOCH=$(date +%s.%N)
"$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f -q run.lcm > logger.out 2>&1 & LG=$!; PIDS+=($LG)
sleep 1
$BIN/kelp-launch --run-seconds 40 --log-dir logs pid.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 1.5
$BIN/kelp-poke pid.moos DEPLOY:=true MOOS_MANUAL_OVERIDE:=false > poke.out || fail "poke failed"
sleep 24   # the survey takes about 135 s of MOOS time: 13.5 s at warp 10
kill -TERM $LP; wait $LP || { cat launch.out; fail "launcher did not end cleanly"; }
kill -INT $LG; wait $LG 2>/dev/null || true
$BIN/kelp-logcheck run.lcm --print > log.txt || fail "log does not decode"
grep -qE "^[0-9.]+ pHelmIvP MISSION complete$" log.txt ||
  { tail -20 logs/pHelmIvP.log; tail -12 logs/pMarinePID.log; tail -12 logs/uSimMarine.log; fail "survey not completed in 240 s of MOOS time"; }
grep -qE " pMarinePID DESIRED_RUDDER " log.txt || fail "pMarinePID posted no DESIRED_RUDDER"
grep -qE " pMarinePID DESIRED_THRUST 40$" log.txt || fail "pMarinePID posted no DESIRED_THRUST 40 (2 m/s x SPEED_FACTOR 20)"
# closest approach to each waypoint
closest uSimMarine "60,-40 60,-100 100,-100 100,-40 140,-40" log.txt > closest.txt
read -a C < closest.txt
for i in 0 1 2 3 4; do
  awk -v d="${C[$i]}" 'BEGIN{exit !(d <= 5)}' || fail "waypoint $((i+1)) missed: closest ${C[$i]} m > capture radius 5 (all: ${C[*]})"
done
# speed in turns: the lowest NAV_SPEED while |DESIRED_RUDDER| >= 60 once the vehicle has
# reached its cruise (not the start), until the survey is done; and the cruise
awk '$2=="pHelmIvP" && $3=="MISSION" && $4=="complete" {over=1}
     $2=="pMarinePID" && $3=="DESIRED_RUDDER" {r=$4; if (r<0) r=-r; next}
     $2=="uSimMarine" && $3=="NAV_SPEED" && !over { if ($4 >= 1.9) cruised=1
       if (cruised && r >= 60 && (tmin=="" || $4 < tmin)) tmin=$4; if ($4 > vmax) vmax=$4 }
     END { printf "%s %s\n", (tmin==""?-1:tmin), vmax }' log.txt > speeds.txt
read tmin vmax < speeds.txt
awk -v v="$vmax" 'BEGIN{exit !(v >= 1.95 && v <= 2.05)}' || fail "cruise speed $vmax, expected 2 m/s"
awk -v t="$tmin" 'BEGIN{exit !(t >= 0 && t <= 1.8)}' || fail "no slowing in turns: lowest speed under hard rudder $tmin m/s"
ok "survey complete; closest to the waypoints ${C[*]} m; cruise $vmax m/s, $tmin m/s in the turns"
