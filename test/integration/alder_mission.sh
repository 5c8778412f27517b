# The Alder mission of seed 004 (missions/alder) through kelp-launch under MOOSTimeWarp, with
# lcm-logger recording: DEPLOY=true (and MOOS_MANUAL_OVERIDE=false, as pMarineViewer's DEPLOY
# button pokes), RETURN=true once the first waypoint is reached (the RETURN button; the
# endflag has set it already). From the log: the vehicle comes within the capture radius (8 m)
# of (60,-40), then back within 8 m of (0,0); the helm posted the endflag and completed both
# behaviours; kelp-plot draws the run.
. "$(dirname "$0")/lib.sh"
if [ ! -x "$BIN/pHelmIvP" ]; then echo "SKIP: pHelmIvP not built (the helm is on branch helm)"; exit 0; fi
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cd $T
cp $KELP_ROOT/missions/alder/alder.moos $KELP_ROOT/missions/alder/alder.bhv .
WARP=10
sed -i "s/^MOOSTimeWarp *= *1 *$/MOOSTimeWarp = $WARP/" alder.moos
grep -q "^MOOSTimeWarp = $WARP" alder.moos || fail "could not set MOOSTimeWarp"
# one warped clock for the launcher, its apps and our pokes
export KELP_WARP_EPOCH=$(date +%s.%N)
$BIN/kelp-record --lcm-url="$KELP_LCM_URL" -f -q run.lcm > logger.out 2>&1 & LG=$!; PIDS+=($LG)
sleep 1   # the logger must be listening before anything starts
$BIN/kelp-launch --run-seconds 45 --log-dir logs alder.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 1.5
$BIN/kelp-poke alder.moos DEPLOY:=true MOOS_MANUAL_OVERIDE:=false > poke_deploy.out || fail "poke DEPLOY failed"

# distances from the simulator's NAV_X/NAV_Y pairs: reached = first fix within 8 m of (60,-40);
# home = closest approach to (0,0) after that
track() {
  $BIN/kelp-logcheck run.lcm --print 2>/dev/null | awk '
    $2=="uSimMarine" && $3=="NAV_X" {x=$4; hx=1; next}
    $2=="uSimMarine" && $3=="NAV_Y" && hx {
      y=$4; d=sqrt((x-60)^2+(y+40)^2); if (mind=="" || d<mind) mind=d
      if (!reached && d<=8) {reached=1; tr=$1}
      if (reached) {h=sqrt(x^2+y^2); if (minh=="" || h<minh) {minh=h; th=$1}}
      if (t0=="") t0=$1; last=$1; lx=x; ly=y }
    END {printf "%d %.2f %.2f %.2f %.2f %.2f %.2f %.2f\n", reached, mind, (minh==""?-1:minh), (tr==""?0:tr-t0), (th==""?0:th-t0), last-t0, lx, ly}'
}
reached=0
for i in $(seq 1 200); do
  read reached mind minh tr th tl lx ly < <(track)
  [ "$reached" = 1 ] && break
  sleep 0.1
done
[ "$reached" = 1 ] || { tail -30 logs/pHelmIvP.log; fail "never within 8 m of (60,-40) (closest $mind m, at ($lx,$ly))"; }
echo "reached (60,-40) within 8 m after $tr s of MOOS time"
$BIN/kelp-poke alder.moos RETURN:=true > poke_return.out || fail "poke RETURN failed"
for i in $(seq 1 300); do
  read reached mind minh tr th tl lx ly < <(track)
  awk -v h="$minh" 'BEGIN{exit !(h >= 0 && h <= 8)}' && break
  sleep 0.1
done
# let it settle: the helm completes waypt_return and has nothing left to do (the summary is the
# IVPHELM_SUMMARY variable's, not PHELMIVP_STATUS's list of names that mentions it)
# (24.8's summary writes a field when it changes: the last completed_bhvs= written, entries
# "name$time$updates" joined with ':')
last_completed() {
  awk '$3=="IVPHELM_SUMMARY"' "$@" | grep -o "completed_bhvs=[^,]*" | tail -1
}
done_both() {
  c=$($BIN/kelp-logcheck run.lcm --print 2>/dev/null | last_completed)
  echo "$c" | grep -q 'transit_to_point\$' && echo "$c" | grep -q 'waypt_return\$'
}
for i in $(seq 1 150); do done_both && break; sleep 0.1; done
sleep 0.5
kill -TERM $LP; wait $LP || { cat launch.out; fail "launcher did not end cleanly"; }
kill -INT $LG; wait $LG 2>/dev/null || true
read reached mind minh tr th tl lx ly < <(track)
echo "closest to (60,-40): $mind m; home: closest to (0,0) $minh m at $th s; last fix ($lx,$ly) at $tl s"
awk -v d="$mind" 'BEGIN{exit !(d <= 8)}' || fail "closest approach to (60,-40) is $mind m > 8"
awk -v h="$minh" 'BEGIN{exit !(h >= 0 && h <= 8)}' || fail "did not return within 8 m of (0,0) (closest $minh m)"
$BIN/kelp-logcheck run.lcm --print > log.txt || fail "log does not decode"
grep -qE "^[0-9.]+ pHelmIvP RETURN true$" log.txt || fail "the endflag RETURN=true was not posted by the helm"
grep -qE "^[0-9.]+ kelp-poke DEPLOY true$" log.txt || fail "DEPLOY poke not in the log"
grep -qE "pHelmIvP IVPHELM_BHV_ACTIVE transit_to_point" log.txt || fail "transit_to_point never active"
grep -qE "pHelmIvP IVPHELM_BHV_ACTIVE waypt_return" log.txt || fail "waypt_return never active"
c=$(last_completed log.txt)
{ echo "$c" | grep -q 'transit_to_point\$' && echo "$c" | grep -q 'waypt_return\$'; } ||
  { echo "last: $c"; fail "both behaviours should be completed at the end"; }
grep -qE "pNodeReporter NODE_REPORT_LOCAL NAME=alder,X=-?[0-9.]+,Y=-?[0-9.]+,SPD=[0-9.]+,HDG=[0-9.]+,DEP=[0-9.]+,LAT=43\.82[0-9]+,LON=-70\.3[0-9]+,TYPE=UUV," log.txt ||
  fail "no NODE_REPORT_LOCAL in MOOS-IvP 24.8's format"
# the picture
$BIN/kelp-plot run.lcm -o alder.png -o alder.svg --title "Alder (seed 004, 5.3)" > plot.out || { cat plot.out; fail "kelp-plot failed"; }
cat plot.out
grep -qE "^alder +report +[0-9]+ +[0-9.]+" plot.out || fail "no alder track in the plot summary"
dist=$(awk '$1=="alder"{print $4}' plot.out)
awk -v d="$dist" 'BEGIN{exit !(d > 130 && d < 220)}' || fail "track length $dist m not about 2 x 72 m"
[ -s alder.png ] && [ -s alder.svg ] || fail "no picture"
if [ -n "${ALDER_PNG:-}" ]; then cp alder.png "$ALDER_PNG"; fi
ok "Alder: (60,-40) reached within $mind m after $tr s, home within $minh m after $th s (warp $WARP), track $dist m"
