# missions/beacons (the seed's Indigo mission) through kelp-launch at MOOSTimeWarp 20, with
# kelp-record recording: indigo is deployed and its own uTimerScript makes the range requests
# (one every 25 to 35 s of MOOS time while NAV_SPEED > 0; seeded here so the run repeats).
# From the log:
#  - every BRS_RANGE_REQUEST comes from uTimerScript, name=indigo, 25 to 35 s after the one
#    before; none before indigo moves;
#  - three VIEW_MARKERs; every honoured request (its white pulse) brings exactly one report
#    from each beacon, in the order 03, 02, 01, with its ground truth; a request is honoured
#    when ping_wait (30 s) has passed since the last honoured one and denied otherwise (so
#    some are, with this seed);
#  - each ground-truth range is the distance from indigo's last node report to the beacon,
#    and each noisy range lies within 10 % (rn_algorithm = uniform,pct=0.1) of it.
. "$(dirname "$0")/lib.sh"
[ -x "$BIN/pHelmIvP" ] || { echo "SKIP: pHelmIvP not built"; exit 0; }
cd "$T"
cp "$KELP_ROOT"/missions/beacons/beacons.moos "$KELP_ROOT"/missions/beacons/beacons.bhv .
sed -i "s/^MOOSTimeWarp *= *1 *$/MOOSTimeWarp = 20/" beacons.moos
grep -q "^MOOSTimeWarp = 20" beacons.moos || fail "could not set MOOSTimeWarp"
sed -i "s/^  reset_time = all-posted$/&\n  seed       = ${KELP_BRS_SEED:-5}/" beacons.moos
grep -q "^  seed       = " beacons.moos || fail "could not seed uTimerScript"
sed -i "s|^  Run = MOOSDB .*||" beacons.moos
echo "LCM_URL = $KELP_LCM_URL" >> beacons.moos
export KELP_WARP_EPOCH=$(date +%s.%N)
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f run.lcmlog
sleep 0.5
"$BIN/kelp-launch" --run-seconds 17 --log-dir logs beacons.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 1.5
"$BIN/kelp-poke" beacons.moos DEPLOY:=true MOOS_MANUAL_OVERIDE:=false > /dev/null || fail "poke DEPLOY failed"
wait $LP 2>/dev/null || true
sleep 0.5
"$BIN/kelp-logcheck" --print run.lcmlog > log.txt || fail "log undecodable"
grep -q "Configuration warnings: 0" logs/uFldBeaconRangeSensor.log 2>/dev/null ||
  { tail -20 logs/uFldBeaconRangeSensor.log 2>/dev/null; echo "(no config-warning line in the sensor's log)"; }
grep -q "Configuration warnings: 0" logs/uTimerScript.log || { tail -20 logs/uTimerScript.log; fail "uTimerScript's block"; }
[ "$(grep -c ' uFldBeaconRangeSensor VIEW_MARKER ' log.txt)" -eq 3 ] || fail "not 3 VIEW_MARKERs"
grep -q ' uFldBeaconRangeSensor VIEW_MARKER x=0,y=-200,width=5,primary_color=red,type=triangle$' log.txt ||
  fail "beacon 03's marker: $(grep VIEW_MARKER log.txt | head -1)"
awk -v TOL=2 '
  function hyp(a, b) { return sqrt(a * a + b * b) }
  BEGIN { bx["01"] = 200; by["01"] = 0; bx["02"] = 400; by["02"] = -200; bx["03"] = 0; by["03"] = -200; order = "03 02 01" }
  $2 == "pNodeReporter" && $3 == "NODE_REPORT_LOCAL" {
    n = split($4, kv, ","); for (i = 1; i <= n; i++) { split(kv[i], p, "="); if (p[1] == "X") nx = p[2]; if (p[1] == "Y") ny = p[2] }
    have = 1 }
  # the requests: their MOOS times as posted and whether a white pulse answered
  function judge() {
    if (!req) return
    g = rt - lasth   # since the last honoured request (the sensor sees it a little later)
    if (honoured) { if (lasth != "" && g < 30 - TOL) { print "FAIL: request at " rt " honoured " g " s after the last honoured"; bad = 1 }
                    lasth = rt }
    else { den++; if (lasth == "" || g >= 30 + TOL) { print "FAIL: request at " rt " denied " g " s after the last honoured"; bad = 1 } } }
  $3 == "DEPLOY" && $4 == "true" && dep == "" { dep = $1 }
  $3 == "BRS_RANGE_REQUEST" {
    if ($2 != "uTimerScript" || $4 != "name=indigo") { print "FAIL: request " $4 " from " $2; bad = 1 }
    judge()
    if (req == 0 && (dep == "" || $1 - dep < 25 - 0.5)) { print "FAIL: first request at " $1 ", deployed at " dep; bad = 1 }
    if (req && ($1 - rt < 25 - 0.5 || $1 - rt > 35 + 5)) { print "FAIL: a request " $1 - rt " s after the one before"; bad = 1 }
    req++; rt = $1; honoured = 0 }
  $2 == "uFldBeaconRangeSensor" && $3 == "VIEW_RANGE_PULSE" && $4 ~ /label=indigo_range_req/ {
    if (seq != "" && seq != order) { print "FAIL: reports in order [" seq "]"; bad = 1 }
    if (!req || honoured) { print "FAIL: a white pulse with no request before it"; bad = 1 }
    seq = ""; acc++; honoured = 1
    match($4, /time=[0-9.]+/); t = substr($4, RSTART + 5, RLENGTH - 5)
    if (lastt != "" && t - lastt < 30 - 0.01) { print "FAIL: honoured " t - lastt " s after the last"; bad = 1 }
    lastt = t }
  $2 == "uFldBeaconRangeSensor" && ($3 == "BRS_RANGE_REPORT" || $3 == "BRS_RANGE_REPORT_GT") {
    n = split($4, kv, ","); for (i = 1; i <= n; i++) { split(kv[i], p, "="); f[p[1]] = p[2] }
    if (f["vname"] != "indigo") { print "FAIL: vname " f["vname"]; bad = 1 }
    if ($3 == "BRS_RANGE_REPORT") { rep++; seq = (seq == "" ? "" : seq " ") f["id"]; noisy[f["id"]] = f["range"]; next }
    gt++
    true_r = hyp(nx - bx[f["id"]], ny - by[f["id"]]); d = f["range"] - true_r; if (d < 0) d = -d
    if (!have || d > 3) { print "FAIL: GT " f["range"] " for " f["id"] " but " true_r " from the last node report"; bad = 1 }
    e = noisy[f["id"]] - f["range"]; if (e < 0) e = -e
    if (e > 0.1 * f["range"] + 0.001) { print "FAIL: noisy " noisy[f["id"]] " not within 10 % of " f["range"]; bad = 1 }
    if (f["range"] > 0 && e / f["range"] > maxe) maxe = e / f["range"] }
  END {
    judge()
    if (seq != "" && seq != order) { print "FAIL: reports in order [" seq "]"; bad = 1 }
    printf "requests %d (uTimerScript), honoured %d, denied %d, reports %d, ground truth %d, largest noise %.1f %%\n", req, acc, den, rep, gt, 100 * maxe
    if (acc < 3 || den < 1 || acc + den != req) { print "FAIL: honoured " acc ", denied " den " of " req; bad = 1 }
    if (rep != 3 * acc || gt != rep) { print "FAIL: " rep " reports, " gt " GT for " acc " honoured requests"; bad = 1 }
    exit bad }' log.txt > check.out || { cat check.out; fail "range reports wrong"; }
cat check.out
ok "beacons: $(cat check.out)"
