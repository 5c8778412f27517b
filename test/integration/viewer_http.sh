# kelp-viewer's server without a browser (its own block, ProcessConfig = kelp-viewer): the page's files and nothing else (no path leaves the
# document root), the token (refused without it; ?token= sets a cookie that then suffices), a
# bind address other than loopback refused without a token, POST /cmd needing the X-Kelp header
# and a configured index, a button's pokes on the bus (numbers as doubles, quoted values as
# strings), the event stream's snapshot with the background image's georeference and /image
# serving the .png beside the tiff_file; an APPCAST in the snapshot, APPCAST_REQ on the bus.
. "$(dirname "$0")/lib.sh"
command -v curl >/dev/null || { echo "SKIP: curl missing"; exit 0; }
cd $T
printf '\x89PNG\r\n\x1a\nfake' > map.png
cat > map.info <<'INFO'
// pMarineViewer's info file
lat_north = 43.8269
lat_south = 43.8230
lon_east  = -70.3270
lon_west  = -70.3340
INFO
cat > v.moos <<M
Community  = shoreside
LatOrigin  = 43.825300
LongOrigin = -70.330400
ProcessConfig = kelp-viewer
{
  AppTick    = 10
  port       = 0
  token      = s3cret
  tiff_file  = map.tif
  button_one = DEPLOY # DEPLOY_ALL=true # DEPTH=12.5 # NAME="3"
  action     = menu_key=return # RETURN_ALL=true
}
M
bg "$BIN/kelp-record" -q -f bus.lcm
bg "$BIN/kelp-viewer" v.moos > app.out 2>&1
wait_for app.out '^kelp-viewer: http://127.0.0.1:[0-9]+/\?token=s3cret' 10 || { cat app.out; fail "no URL printed"; }
U=$(grep -o 'http://127.0.0.1:[0-9]*' app.out | head -1)
code() { curl -s -o /dev/null -w '%{http_code}' "$@"; }
[ "$(code "$U/")" = 403 ] || fail "the page without the token"
[ "$(code "$U/?token=wrong")" = 403 ] || fail "a wrong token accepted"
[ "$(code -H 'X-Kelp-Token: s3cret' "$U/viewer.js")" = 200 ] || fail "the token header refused"
curl -s -D hdr.txt -o index.html "$U/?token=s3cret"
grep -qi '^Set-Cookie: kelp_token=s3cret; Path=/; HttpOnly; SameSite=Strict' hdr.txt || fail "no cookie: $(cat hdr.txt)"
grep -q 'viewer.js' index.html || fail "index.html not served"
C=(-b kelp_token=s3cret)
[ "$(code "${C[@]}" "$U/viewer.css")" = 200 ] || fail "the cookie refused"
for bad in /../v.moos /%2e%2e/v.moos /v.moos /etc/passwd /viewer.js/.. /index.html~; do
  [ "$(code "${C[@]}" --path-as-is "$U$bad")" = 404 ] || fail "$bad served"
done
ok "token, cookie and the fixed list of files"
# the background image: the .png beside map.tif, and its box in the snapshot
curl -s "${C[@]}" "$U/image" | head -c 8 | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "/image is not the png"
"$BIN/kelp-poke" v.moos 'NODE_REPORT=NAME=zed,TYPE=ship,X=12.5,Y=-7,HDG=45,SPD=1' > /dev/null
"$BIN/kelp-poke" v.moos 'APPCAST=proc=pFake!@#node=alpha!@#iter=7!@#messages=hello!@#run_warning_total=0' > /dev/null
timeout 3 curl -s -N "${C[@]}" "$U/events" > ev.txt || true
grep -q '"cast":\[.*{"node":"alpha","proc":"pFake","t":[0-9.]*,"text":"proc=pFake!@#node=alpha!@#iter=7!@#messages=hello!@#run_warning_total=0"}' ev.txt ||
  fail "the AppCast is not in the snapshot"
grep -q '"image":{"url":"/image","n":43.8269,"s":43.823,"e":-70.327,"w":-70.334}' ev.txt || fail "image box: $(head -c 600 ev.txt)"
grep -q '"label":"DEPLOY","pokes":\["DEPLOY_ALL=true","DEPTH=12.5","NAME=3"\]' ev.txt || fail "button in the snapshot"
ok "image and buttons in the snapshot"
# commands: the header, a configured index, and the pokes on the bus
[ "$(code "${C[@]}" -X POST "$U/cmd?i=0")" = 403 ] || fail "POST without X-Kelp accepted"
[ "$(code "${C[@]}" -H 'X-Kelp: 1' "$U/cmd?i=0")" = 404 ] || fail "GET /cmd accepted"
[ "$(code "${C[@]}" -X POST -H 'X-Kelp: 1' "$U/cmd?i=x")" = 400 ] || fail "a bad index accepted"
[ "$(code "${C[@]}" -X POST -H 'X-Kelp: 1' "$U/cmd?i=7")" = 200 ] || fail "an index refused at the door"
[ "$(code "${C[@]}" -X POST -H 'X-Kelp: 1' "$U/cmd?i=0")" = 200 ] || fail "the button refused"
[ "$(code "${C[@]}" -X POST -H 'X-Kelp: 1' "$U/cmd?i=1")" = 200 ] || fail "the action refused"
sleep 1.5
kill -INT "${PIDS[0]}"; wait "${PIDS[0]}" 2>/dev/null || true
"$BIN/kelp-logcheck" bus.lcm --print > bus.txt 2>/dev/null || true
grep -qE ' kelp-viewer DEPLOY_ALL true$' bus.txt || fail "DEPLOY_ALL: $(grep -v _STATUS bus.txt | tail -5)"
grep -qE ' kelp-viewer DEPTH 12.5$' bus.txt || fail "DEPTH"
grep -qE ' kelp-viewer NAME 3$' bus.txt || fail "NAME"
grep -qE ' kelp-viewer RETURN_ALL true$' bus.txt || fail "RETURN_ALL"
[ "$(grep -cE ' kelp-viewer (DEPLOY_ALL|DEPTH|NAME|RETURN_ALL) ' bus.txt)" = 4 ] || fail "more pokes than pressed"
wait_for app.out 'command 7, which is not configured' 15 || fail "index 7 not reported"
grep -qE ' kelp-viewer APPCAST_REQ node=all,app=all,duration=5,key=kelp-viewer,thresh=any$' bus.txt || fail "no APPCAST_REQ"
ok "button and action pokes on the bus; an unconfigured index posts nothing"
# another address without a token
sed '/token/d' v.moos > notoken.moos
"$BIN/kelp-viewer" --bind 0.0.0.0 --port 0 notoken.moos > nobind.out 2>&1 && fail "0.0.0.0 without a token started"
grep -q 'needs a token' nobind.out || fail "no reason: $(cat nobind.out)"
"$BIN/kelp-viewer" --bind 127.0.0.2 --port 0 notoken.moos > nobind2.out 2>&1 && fail "127.0.0.2 without a token started"
grep -q 'needs a token' nobind2.out || fail "no reason: $(cat nobind2.out)"
ok "a non-loopback bind needs a token"
# replay of the recorded bus as an .alog (kelp-alog), without a browser: the vehicle, the replay state
"$BIN/kelp-alog" to-alog bus.lcm bus.alog > /dev/null || fail "kelp-alog to-alog"
bg "$BIN/kelp-viewer" --log bus.alog --port 0 --paused > replay.out 2>&1
wait_for replay.out '^kelp-viewer: replaying bus.alog \([0-9]+ postings' 10 || { cat replay.out; fail "replay of the .alog"; }
R=$(grep -o 'http://127.0.0.1:[0-9]*' replay.out | head -1)
curl -s -X POST -H 'X-Kelp: 1' "$R/replay?op=seek&v=1000" > /dev/null   # past the end: the whole log
timeout 3 curl -s -N "$R/events" > rev.txt || true
grep -q '"name":"zed","type":"ship","x":12.5,"y":-7,"hdg":45' rev.txt || fail "replayed vehicle: $(head -c 400 rev.txt)"
grep -q '^event: replay' rev.txt && grep -q '"playing":0,"speed":1' rev.txt || fail "replay state: $(grep -A1 'event: replay' rev.txt | head -2)"
grep -q '"proc":"pFake"' rev.txt || fail "replayed AppCast"
ok "the .alog replayed: vehicle, AppCast and the replay state in the stream"
