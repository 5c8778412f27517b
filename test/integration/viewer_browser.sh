# kelp-viewer in a real browser (headless Chromium driven by test/integration/viewer_browser.py):
# during a running fleet mission (scripts/demo-fleet.sh with two vehicles, MOOSTimeWarp 20, the
# DEPLOY poke left to the page) (a) the page's own state (window.kelpViewer) places each vehicle
# where the shoreside log's NODE_REPORT with that TIME puts it, within a metre, and that report
# is the latest; (b) a VIEW_POLYGON poked on the shoreside bus appears in it; (c) a real click on
# the configured DEPLOY button makes the helms deploy (the vehicles move; DEPLOY=true reaches
# the vehicles' buses through the bridge); (d) a screenshot is saved (build/viewer-shot.png).
# Then the recorded shoreside log is replayed (kelp-viewer --log) and the page's slider seeks.
. "$(dirname "$0")/lib.sh"
PY=/usr/bin/python3
unset KELP_LCM_URL   # the demo's communities have their own URLs (kelp-poke must use the shoreside's)
if [ ! -x /usr/bin/chromium ] || [ ! -x /usr/bin/chromedriver ] || ! $PY -c 'import selenium' 2>/dev/null; then
  echo "SKIP: chromium, chromium-driver or python3-selenium missing (scripts/deps.sh test)"; exit 0
fi
[ -x "$BIN/pHelmIvP" ] && [ -x "$BIN/kelp-viewer" ] || fail "pHelmIvP or kelp-viewer not built"
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cd $T
start=$(date +%s)
cat > fleet.conf <<'CONF'
alpha   | 7681 | 9201 |   0,0,180   | 3.0 | 60,-40:160,-40:160,-110    | 230,-120,25 | true  | 60
bravo   | 7682 | 9202 |  15,10,0    | 3.0 | 60,60:160,60:160,120       | 230,130,25  | false | 60
CONF
PORT=18080
DEMO_DIR=$T/demo DEMO_FLEET=$T/fleet.conf DEMO_WARP=20 DEMO_TIMEOUT=45 DEMO_NO_DEPLOY=1 DEMO_VIEWER_PORT=$PORT \
  KELP_DEMO_HEADLESS=1 "$KELP_ROOT/scripts/demo-fleet.sh" "$BUILD" > demo.out 2>&1 &
DEMO=$!; PIDS+=($DEMO)
wait_for demo.out "^== DEPLOY: waiting for the page" 30 || { cat demo.out; fail "the fleet did not come up"; }
echo "fleet up after $(( $(date +%s) - start )) s"
grep -q "^== kelp-viewer (pMarineViewer role): http://127.0.0.1:$PORT/" demo.out || fail "demo did not print the viewer URL"
export KELP_WARP_EPOCH=$(cat demo/warp_epoch)   # the demo's warped clock, for kelp-poke
shot=$BUILD/viewer-shot.png
rm -f "$shot"
$PY "$KELP_ROOT/test/integration/viewer_browser.py" live "http://127.0.0.1:$PORT/" live.json "$shot" \
  "$BIN/kelp-poke" "$T/demo/shoreside.moos" "VIEW_POLYGON=pts={-50,-50:50,-50:50,50:-50,50},label=viewer_test,edge_color=light_green,fill=0.2" \
  > live.out 2>&1 || { cat live.out; tail -20 demo.out; fail "the live page"; }
cat live.out
echo "live page checked after $(( $(date +%s) - start )) s"
# the rest needs only the logs: stop the mission (its trap stops the launchers and the recorders)
kill -TERM $DEMO 2>/dev/null || true
wait $DEMO || true
echo "mission stopped after $(( $(date +%s) - start )) s"
# the replay starts now (it reads the log once) while the live state is checked against the log
bg "$BIN/kelp-viewer" --log demo/shoreside.lcm --port 0 demo/shoreside.moos > replay.out 2>&1
"$BIN/kelp-logcheck" demo/shoreside.lcm --print > shore.txt 2>/dev/null || true
$PY "$KELP_ROOT/test/integration/viewer_browser.py" check live.json shore.txt 20 || fail "page positions against the log"
# (c) on the bus: the button's pokes left the viewer, crossed the bridge and reached the helms
grep -q 'button "DEPLOY" pressed in the page' demo/logs_shoreside/pMarineViewer* 2>/dev/null ||
  grep -rq 'button "DEPLOY" pressed in the page' demo/logs_shoreside || fail "the viewer did not report the press"
awk '$3=="DEPLOY_ALL" && $4=="true" {f=1} END{exit !f}' shore.txt || fail "no DEPLOY_ALL=true on the shoreside bus"
for v in alpha bravo; do
  "$BIN/kelp-logcheck" demo/$v.lcm --print > $v.txt 2>/dev/null || true
  awk '$3=="DEPLOY" && $4=="true" {f=1} END{exit !f}' $v.txt || fail "$v: DEPLOY=true never reached its bus"
  ! grep -q "kelp-poke DEPLOY" $v.txt || fail "$v: DEPLOY came from kelp-poke, not the page"
  awk '$3=="IVPHELM_STATE" && $4=="DRIVE" {f=1} END{exit !f}' $v.txt || fail "$v: the helm never drove"
done
# (d) the screenshot: a PNG of the page, not blank
head -c 8 "$shot" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "no PNG screenshot"
sz=$(stat -c %s "$shot"); [ "$sz" -gt 20000 ] || fail "screenshot only $sz bytes"
ncol=$($PY -c 'import json,sys; print(json.load(open(sys.argv[1]))["colours"])' live.json)
[ "$ncol" -ge 8 ] || fail "the map has only $ncol colours"
ok "screenshot $shot ($sz bytes, $ncol colours in the map)"
# ---- replay of the recorded shoreside log in the same page
wait_for replay.out "^kelp-viewer: replaying .*http://127.0.0.1:[0-9]+/" 10 || { cat replay.out; fail "replay did not start"; }
url=$(grep -o 'http://127.0.0.1:[0-9]*/' replay.out | head -1)
$PY "$KELP_ROOT/test/integration/viewer_browser.py" replay "$url" replay.json live.json > rp.out 2>&1 || { cat rp.out; fail "replay page"; }
cat rp.out
el=$(( $(date +%s) - start ))
ok "kelp-viewer in Chromium: positions match the log, polygon shown, DEPLOY clicked and the helms drove, screenshot saved, replay seeks (${el}s)"
