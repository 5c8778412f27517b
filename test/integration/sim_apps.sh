# uSimMarine + pNodeReporter through kelp-launch under MOOSTimeWarp, driven by poked
# DESIRED_* values, checked from an lcm-logger log against the model's closed forms; the node
# report's LAT/LON against the MOOS local-grid formula; bad configuration; kelp-plot on the
# run, on a log of every VIEW_* kind, and on bad files.
. "$(dirname "$0")/lib.sh"
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cd $T
cat > sim.moos <<'M'
ServerHost = localhost
ServerPort = 9000
Community  = alpha
MOOSTimeWarp = 10
LatOrigin  = 43.825300
LongOrigin = -70.330400

ProcessConfig = ANTLER
{
  MSBetweenLaunches = 100
  Run = MOOSDB        @ NewConsole = false
  Run = uSimMarine    @ NewConsole = false
  Run = pNodeReporter @ NewConsole = false
}

ProcessConfig = uSimMarine
{
  AppTick   = 10
  CommsTick = 10
  START_POS = x=0, y=0, heading=90, speed=0
  TURN_RATE = 10
  TURN_SPEED = 0
  MAX_ACCELERATION = 0.5
}

ProcessConfig = pNodeReporter
{
  AppTick   = 4
  CommsTick = 4
  PLATFORM_TYPE   = kayak
  PLATFORM_LENGTH = 3.8
}
M
# one warped clock for the launcher, its apps and our pokes
export KELP_WARP_EPOCH=$(date +%s.%N)
$BIN/kelp-record --lcm-url="$KELP_LCM_URL" -f -q run.lcm > logger.out 2>&1 & LG=$!; PIDS+=($LG)
# a second log with the simulator's NAV_* only: kelp-plot must fall back to NAV_X/NAV_Y
$BIN/kelp-record --lcm-url="$KELP_LCM_URL" -c 'NAV_.*' -f -q nav.lcm > logger_nav.out 2>&1 & LGN=$!; PIDS+=($LGN)
sleep 0.4
$BIN/kelp-launch --run-seconds 8 --log-dir logs sim.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 1.2
$BIN/kelp-poke sim.moos DESIRED_SPEED=2 DESIRED_HEADING=90 > poke1.out || fail "poke"
sleep 3
$BIN/kelp-poke sim.moos DESIRED_HEADING=180 > poke2.out || fail "poke"
wait $LP || { cat launch.out; fail "launcher exit non-zero"; }
kill -INT $LG $LGN; wait $LG $LGN 2>/dev/null || true
$BIN/kelp-logcheck run.lcm --print > log.txt || fail "log does not decode"
for v in NAV_X NAV_Y NAV_HEADING NAV_SPEED NAV_DEPTH NAV_LAT NAV_LONG; do
  grep -qE "^[0-9.]+ uSimMarine $v " log.txt || fail "uSimMarine did not publish $v"
done
# before the poke: at rest at the start pose
awk '$2=="uSimMarine" && $3=="NAV_X"{print $4; exit}' log.txt | grep -qx 0 || fail "first NAV_X is not the start x 0"
# straight east at 2 m/s after 4 s of acceleration: x(t) = 2 (t - tp) - 4 (y stays 0), until the turn
tp=$(awk '$2=="kelp-poke" && $3=="DESIRED_SPEED"{print $1; exit}' log.txt)
th=$(awk '$2=="kelp-poke" && $3=="DESIRED_HEADING" && $4=="180"{print $1; exit}' log.txt)
[ -n "$tp" ] && [ -n "$th" ] || fail "pokes not in the log"
awk -v tp="$tp" -v th="$th" '
  $2=="uSimMarine" && $3=="NAV_X" {x=$4; t=$1}
  $2=="uSimMarine" && $3=="NAV_Y" && t > tp + 4.5 && t < th {
    n++; e = x - (2*(t-tp) - 4); if (e<0) e=-e; if (e>me) me=e; if ($4 > 1e-9 || $4 < -1e-9) bady=1 }
  END { printf "straight leg: %d fixes, max |x - (2(t-tp)-4)| = %.3f m\n", n, me;
        exit !(n > 20 && me < 0.6 && !bady) }' log.txt || fail "straight leg does not follow x = 2(t-tp) - 4, y = 0"
# the turn to 180 at 10 deg/s takes 9 s; by the end the heading is 180 and y is falling
last_h=$(awk '$2=="uSimMarine" && $3=="NAV_HEADING"{h=$4} END{print h}' log.txt)
end_t=$(awk '$2=="uSimMarine" && $3=="NAV_HEADING"{t=$1} END{print t}' log.txt)
awk -v a="$end_t" -v b="$th" 'BEGIN{exit !(a - b > 10)}' || fail "run too short after the turn poke"
[ "$last_h" = "180" ] || fail "final heading $last_h, expected 180"
# mid-turn: the sample nearest 4.5 s into the turn (a loaded host may leave a gap of a few
# tenths between iterations), against 90 + 10 deg/s x its own time into the turn
mid=$(awk -v th="$th" '$2=="uSimMarine" && $3=="NAV_HEADING" && $1 > th + 4.0 && $1 < th + 5.0 {
        d = $1 - th - 4.5; if (d < 0) d = -d; if (best == "" || d < best) { best = d; out = $4 " " ($1 - th) } }
      END { print out }' log.txt)
read -r mid_h mid_t <<< "$mid"
[ -n "$mid_h" ] && awk -v h="$mid_h" -v t="$mid_t" 'BEGIN{e = 90 + 10 * t; exit !(h > e - 7 && h < e + 7)}' ||
  fail "heading ${mid_t:-?} s into the turn is '$mid_h', expected about 90 + 10 deg/s x that"
# node reports: the uField format, LAT/LON from X/Y by UTM as MOOS-IvP 24.8 (kelp/geo.h): the
# reported LAT/LON taken back to UTM metres from the datum by the USGS series (zone 19) must be
# the reported X/Y (MOOS's inverse places a point within a metre; at these distances, a cm)
grep -E "^[0-9.]+ pNodeReporter NODE_REPORT_LOCAL " log.txt | tail -1 > rep.txt
[ -s rep.txt ] || fail "no NODE_REPORT_LOCAL"
# (MOOS-IvP 24.8's NodeRecord layout: DEP=, trailing zeros trimmed, LAT/LON to 8 decimals,
# ALLSTOP=unknown without a helm)
N='-?[0-9]+(\.[0-9]{1,2})?'
grep -qE "NODE_REPORT_LOCAL NAME=alpha,X=$N,Y=$N,SPD=2,HDG=180,DEP=0,LAT=43\.[0-9]{1,8},LON=-70\.[0-9]{1,8},TYPE=kayak,MODE=NOHELM-EVER,ALLSTOP=unknown,INDEX=[1-9][0-9]*,YAW=-1\.5707963,TIME=[0-9]+(\.[0-9]{1,2})?,LENGTH=3\.8$" rep.txt ||
  { cat rep.txt; fail "NODE_REPORT_LOCAL not in the expected format"; }
awk 'function utm(lat, lon, o,   e2, ep, p, s, c, t, N, T, C, A, M) {
         e2 = 0.00669438; ep = e2/(1-e2); p = lat*pi/180; s = sin(p); c = cos(p); t = s/c
         N = 6378137/sqrt(1-e2*s*s); T = t*t; C = ep*c*c; A = c*(lon+69)*pi/180
         M = 6378137*((1-e2/4-3*e2^2/64-5*e2^3/256)*p - (3*e2/8+3*e2^2/32+45*e2^3/1024)*sin(2*p) \
             + (15*e2^2/256+45*e2^3/1024)*sin(4*p) - (35*e2^3/3072)*sin(6*p))
         o[1] = 0.9996*N*(A+(1-T+C)*A^3/6+(5-18*T+T*T+72*C-58*ep)*A^5/120)
         o[2] = 0.9996*(M+N*t*(A*A/2+(5-T+9*C+4*C*C)*A^4/24+(61-58*T+T*T+600*C-330*ep)*A^6/720)) }
     { split($4, f, ","); for (i in f) { split(f[i], kv, "="); v[kv[1]] = kv[2] }
       pi = atan2(0, -1); utm(43.8253, -70.3304, o0); utm(v["LAT"], v["LON"], o)
       dx = o[1] - o0[1] - v["X"]; dy = o[2] - o0[2] - v["Y"]
       printf "report X=%s Y=%s LAT=%s LON=%s (back to UTM: %.3f %.3f)\n", v["X"], v["Y"], v["LAT"], v["LON"], o[1]-o0[1], o[2]-o0[2]
       exit !(sqrt(dx*dx + dy*dy) < 0.15) }' rep.txt || fail "LAT/LON are not X/Y by UTM"
# kelp-plot on the run
$BIN/kelp-plot run.lcm -o run.png -o run.svg > plot.out || { cat plot.out; fail "kelp-plot failed"; }
grep -qE "^alpha +report " plot.out || { cat plot.out; fail "no alpha track"; }
$BIN/kelp-plot nav.lcm -o nav.png > navplot.out || { cat navplot.out; fail "kelp-plot failed on the NAV-only log"; }
grep -qE "^alpha +nav +[0-9]+ " navplot.out || { cat navplot.out; fail "no alpha track from NAV_X/NAV_Y"; }
rd=$(awk '$1=="alpha"{print $4}' plot.out); nd=$(awk '$1=="alpha"{print $4}' navplot.out)
awk -v a="$rd" -v b="$nd" 'BEGIN{d=a-b; if(d<0)d=-d; exit !(b > 50 && d < 3)}' || fail "report track $rd m and NAV track $nd m differ"
head -c 8 run.png | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "run.png is not a PNG"
grep -q "<svg" run.svg || fail "run.svg is not SVG"
ok "simulator follows DESIRED_* and the node reports match"

# ---- bad configuration: a clear file:line error and a non-zero exit
cat > bad.moos <<'M'
Community = alpha
ProcessConfig = uSimMarine
{
  START_POS = 1,2,three
}
ProcessConfig = pNodeReporter
{
  PLATFORM_TYPE = UUV,big
}
ProcessConfig = uSimTurn
{
  TURN_RATE = -5
}
M
timeout 5 $BIN/uSimMarine bad.moos > bad1.out 2>&1 && fail "uSimMarine accepted START_POS = 1,2,three"
grep -q "bad.moos:4: START_POS" bad1.out || { cat bad1.out; fail "no file:line for START_POS"; }
timeout 5 $BIN/pNodeReporter bad.moos > bad2.out 2>&1 && fail "pNodeReporter accepted PLATFORM_TYPE = UUV,big"
grep -q "bad.moos:8: PLATFORM_TYPE" bad2.out || { cat bad2.out; fail "no file:line for PLATFORM_TYPE"; }
timeout 5 $BIN/uSimMarine bad.moos uSimTurn > bad3.out 2>&1 && fail "uSimMarine accepted TURN_RATE = -5"
grep -q "bad.moos:12: TURN_RATE" bad3.out || { cat bad3.out; fail "no file:line for TURN_RATE"; }
ok "bad configuration rejected with file:line"

# ---- every VIEW_* kind (pokes in small groups: lcm-logger queues at most 30 per burst)
printf 'Community = shoreside\n' > shore.moos
$BIN/kelp-record --lcm-url="$KELP_LCM_URL" -f -q views.lcm > logger2.out 2>&1 & LG=$!; PIDS+=($LG)
sleep 0.4
a=(); for i in $(seq 0 14); do a+=("NODE_REPORT:=NAME=alpha,TYPE=UUV,TIME=$((1000+i*10)),X=$((i*10)),Y=0,SPD=1.00,HDG=90.00,DEPTH=0.00"); done
$BIN/kelp-poke shore.moos "${a[@]}" > /dev/null || fail poke
a=(); n=0; for p in "0,0" "0,30" "40,30" "40,0"; do a+=("NODE_REPORT_LOCAL:=NAME=bravo,TIME=$((2000+n)),X=${p%,*},Y=${p#*,}"); n=$((n+1)); done
a+=("VIEW_POINT:=x=140,y=0,label=alpha's next waypoint,type=waypoint,source=survey,active=true")
a+=("VIEW_POINT:=active,false:label,bravo's next waypoint:type,waypoint:source,ret:0,0,0")
a+=("VIEW_POLYGON:=pts={80,30:120,30:130,60:90,70},label=loiter_box,edge_color=dark_green,fill_color=green,fill=0.15")
a+=("VIEW_SEGLIST:=pts={0,0:0,30:40,30:40,0},label=bravo_path,edge_color=gray")
$BIN/kelp-poke shore.moos "${a[@]}" > /dev/null || fail poke
a=("VIEW_CIRCLE:=x=100,y=-30,radius=12,label=hazard_1,edge_color=yellow,fill_color=yellow,fill=0.3"
   "VIEW_MARKER:=x=20,y=-40,label=03,color=orange,type=circle,width=4"
   "VIEW_MARKER:=x=40,y=-40,label=02,color=dodger_blue,type=square,width=4"
   "VIEW_COMMS_PULSE:=sx=40,sy=0,tx=140,ty=0,beam_width=7,duration=10,fill=0.35,label=BRAVO2ALPHA,edge_color=green,fill_color=purple"
   "VIEW_RANGE_PULSE:=x=20,y=-40,radius=25,duration=15,fill=0.25,label=03_reply"
   "NODE_REPORT:=NAME=zulu,X=1"
   "VIEW_POINT:=label=no_position")
$BIN/kelp-poke shore.moos "${a[@]}" > /dev/null || fail poke
sleep 0.5
kill -INT $LG; wait $LG 2>/dev/null || true
$BIN/kelp-plot views.lcm -o views.png > vplot.out || { cat vplot.out; fail "kelp-plot failed on the VIEW_* log"; }
cat vplot.out
grep -qE "^alpha +report +15 +140\.0 +140\.0 +\(0\.0,0\.0\) +\(140\.0,0\.0\)" vplot.out || fail "alpha: 15 fixes, 140 m, 140 s"
grep -qE "^bravo +report +4 +100\.0 " vplot.out || fail "bravo: 4 fixes, 100 m"
grep -q "artifacts: VIEW_POINT=2 VIEW_CIRCLE=1 VIEW_POLYGON=1 VIEW_SEGLIST=1 VIEW_MARKER=2 VIEW_COMMS_PULSE=1 VIEW_RANGE_PULSE=1" vplot.out ||
  fail "artifact counts"
grep -q "rejected: 1 node reports, 1 VIEW_\* postings" vplot.out || fail "bad postings not counted"
if [ -n "${VIEWS_PNG:-}" ]; then cp views.png "$VIEWS_PNG"; fi
ok "kelp-plot draws every VIEW_* kind and counts bad postings"

# ---- kelp-plot on bad files: an error, never a crash
rc=0; $BIN/kelp-plot nosuch.lcm -o x.png > e1.out 2>&1 || rc=$?
[ $rc -eq 1 ] && grep -q "nosuch.lcm" e1.out || { cat e1.out; fail "missing file: rc $rc"; }
head -c 5000 /dev/urandom > junk.lcm
rc=0; $BIN/kelp-plot junk.lcm -o y.png > e2.out 2>&1 || rc=$?
[ $rc -eq 1 ] || { cat e2.out; fail "junk file: rc $rc (expected 1)"; }
head -c $(( $(stat -c %s views.lcm) * 2 / 3 )) views.lcm > cut.lcm
rc=0; $BIN/kelp-plot cut.lcm -o cut.png > e3.out 2>&1 || rc=$?
[ $rc -eq 0 ] && [ -s cut.png ] || { cat e3.out; fail "truncated log: rc $rc"; }
ok "kelp-plot: missing, junk and truncated logs handled"
