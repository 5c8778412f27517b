# kelp-viewer in a real browser (headless Chromium driven by test/integration/viewer_browser.py),
# met as a user of `make demo` meets it: scripts/demo-fleet.sh (two vehicles, MOOSTimeWarp 20,
# the DEPLOY poke left to the page, not headless) runs the fleet in its own private network
# namespace and prints a URL; the browser, outside that namespace, opens the printed URL
# (this namespace's 127.0.0.1, forwarded into the demo's). During the run (a) the page's own
# state (window.kelpViewer) places each vehicle where the shoreside log's NODE_REPORT with that
# TIME puts it, within a metre, and that report is the latest; (b) a VIEW_POLYGON poked on the
# shoreside bus appears in it; (c) a real click on the configured DEPLOY button makes the helms
# deploy (the vehicles move; DEPLOY=true reaches the vehicles' buses through the bridge); (d) a
# screenshot is saved (build/viewer-shot.png). After the run the demo serves the run's log
# (kelp-viewer --log) at the URL it prints: the page's slider seeks; a Ctrl-C (SIGINT) ends the
# demo, its forwarder and its viewer.
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
# the demo makes its own network namespace (as `make demo` does on a user's machine)
# (its own process group, SIGINT not ignored: a Ctrl-C is a SIGINT to that group)
setsid env --default-signal=INT -u KELP_IN_NETNS DEMO_DIR=$T/demo DEMO_FLEET=$T/fleet.conf DEMO_WARP=20 DEMO_TIMEOUT=30 DEMO_NO_DEPLOY=1 \
  DEMO_VIEWER_PORT=$PORT KELP_DEMO_HEADLESS=0 "$KELP_ROOT/scripts/demo-fleet.sh" "$BUILD" > demo.out 2>&1 &
DEMO=$!; PIDS+=($DEMO)
wait_for demo.out "^== DEPLOY: waiting for the page" 30 || { cat demo.out; fail "the fleet did not come up"; }
echo "fleet up after $(( $(date +%s) - start )) s"
url=$(sed -n 's|^== kelp-viewer (pMarineViewer role): \(http://127\.0\.0\.1:[0-9]*/\) .*|\1|p' demo.out)
[ -n "$url" ] || { cat demo.out; fail "demo did not print the viewer URL"; }
# the demo's processes live in their own namespace; here only its forwarder listens on the port
me=$(readlink /proc/self/ns/net)
inner=
for c in $(pgrep -P $DEMO); do
  [ "$(readlink /proc/$c/ns/net 2>/dev/null)" != "$me" ] && inner=$c
done
[ -n "$inner" ] || fail "the demo is not in a network namespace of its own"
port=$(sed 's|.*:\([0-9]*\)/$|\1|' <<< "$url")
listeners=$(ss -Hltnp "sport = :$port")
grep -q '"socat"' <<< "$listeners" && ! grep -q 'kelp-viewer' <<< "$listeners" ||
  fail "here $url should be the demo's forwarder, not a viewer: $listeners"
INNER_NS=(nsenter --net=/proc/$inner/ns/net)
export KELP_WARP_EPOCH=$(cat demo/warp_epoch)   # the demo's warped clock, for kelp-poke
shot=$BUILD/viewer-shot.png
rm -f "$shot"
$PY "$KELP_ROOT/test/integration/viewer_browser.py" live "$url" live.json "$shot" \
  "${INNER_NS[@]}" "$BIN/kelp-poke" "$T/demo/shoreside.moos" "VIEW_POLYGON=pts={-50,-50:50,-50:50,50:-50,50},label=viewer_test,edge_color=light_green,fill=0.2" \
  > live.out 2>&1 || { cat live.out; tail -20 demo.out; fail "the live page at $url (outside the demo's namespace)"; }
cat live.out
echo "live page checked through $url after $(( $(date +%s) - start )) s"
# after the run: the demo says where the replay is (the same address) and serves it
wait_for demo.out "^== the run's replay .*: http://127\.0\.0\.1:[0-9]+/" 90 || { tail -30 demo.out; fail "no replay after the run"; }
echo "run over, replay served after $(( $(date +%s) - start )) s"
rurl=$(sed -n "s|^== the run's replay .*: \(http://127\.0\.0\.1:[0-9]*/\) .*|\1|p" demo.out)
[ "$rurl" = "$url" ] || fail "the replay is at $rurl, the live page was at $url"
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
# ---- the replay of the run's shoreside log, at the URL the demo printed (outside its namespace)
$PY "$KELP_ROOT/test/integration/viewer_browser.py" replay "$rurl" replay.json live.json > rp.out 2>&1 || { cat rp.out; fail "replay page"; }
cat rp.out
# Ctrl-C ends it: the demo, its viewer and the forwarder
kill -INT -- -$DEMO
for _ in $(seq 100); do kill -0 $DEMO 2>/dev/null || break; sleep 0.1; done
! kill -0 $DEMO 2>/dev/null || fail "the demo still runs 10 s after SIGINT"
grep -q "^== demo over" demo.out || { tail -5 demo.out; fail "the demo did not end through its Ctrl-C path"; }
! $PY -c 'import sys, urllib.request; urllib.request.urlopen(sys.argv[1], timeout=3)' "$url" 2>/dev/null ||
  fail "$url still answers after the demo ended"
el=$(( $(date +%s) - start ))
ok "the demo's page in Chromium from outside its namespace: positions match the log, polygon shown, DEPLOY clicked and the helms drove, screenshot saved; after the run the replay at the same URL seeks; Ctrl-C ends it (${el}s)"
