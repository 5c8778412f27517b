#!/usr/bin/env bash
# uFldNodeComms on a real bus: two vehicles' reports 50 m apart are relayed to each other
# (NODE_REPORT_<V> re-written as MOOS-IvP 24.8's node record, with a VIEW_COMMS_PULSE), a third
# 500 m away gets nothing, and a node message reaches its addressee as NODE_MESSAGE_<V>
# (src_app added) with a white pulse.
. "$(dirname "$0")/lib.sh"
cd "$T"
cat > n.moos <<'M'
Community = shoreside
ServerPort = 9000
LatOrigin = 42.358456
LongOrigin = -71.087589
ProcessConfig = uFldNodeComms
{
  AppTick = 4
  comms_range = 100
  critical_range = 30
  stale_time = 5
  PULSE_DURATION = 10;
}
M
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f n.lcmlog
sleep 0.5
bg "$BIN/uFldNodeComms" n.moos > app.out 2>&1
sleep 1
# the reports' TIME (a message goes only to a vehicle whose report is recent), in hundredths so
# the relayed TIME (two decimals) is the same number with no rounding tie to decide
t=$(date +%s.%N | cut -c1-13)
"$BIN/kelp-poke" n.moos "NODE_REPORT=NAME=alpha,TYPE=kayak,X=0,Y=0,SPD=1,HDG=90,DEP=0,TIME=$t" \
  "NODE_REPORT=NAME=bravo,TYPE=uuv,X=50,Y=0,SPD=1,HDG=90,DEPTH=2,TIME=$t,LENGTH=4" \
  "NODE_REPORT=NAME=charlie,TYPE=uuv,X=500,Y=0,SPD=1,HDG=90,DEP=0,TIME=$t" \
  "NODE_REPORT=NAME=delta,TYPE=kayak,X=10,Y=0,SPD=1,HDG=90" > poke.out 2>&1 || fail "poke: $(cat poke.out)"
sleep 0.6
"$BIN/kelp-poke" n.moos "NODE_MESSAGE=src_node=alpha,dest_node=bravo,var_name=FOOBAR,string_val=hello" > /dev/null
sleep 1
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print n.lcmlog > n.txt || fail "log undecodable"
val() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print; exit}' n.txt; }
tt=$(echo "$t" | sed 's/0*$//; s/\.$//')
[ "$(val NODE_REPORT_BRAVO)" = "NAME=alpha,X=0,Y=0,SPD=1,HDG=90,COG=90,DEP=0,LAT=42.358456,LON=-71.087589,TYPE=kayak,TIME=$tt,LENGTH=3" ] ||
  fail "NODE_REPORT_BRAVO: $(val NODE_REPORT_BRAVO)"
val NODE_REPORT_ALPHA | grep -qE "^NAME=bravo,X=50,Y=0,SPD=1,HDG=90,COG=90,DEP=2,LAT=42\.358[0-9]*,LON=-71\.08[0-9]*,TYPE=auv,TIME=$tt,LENGTH=4$" ||
  fail "NODE_REPORT_ALPHA: $(val NODE_REPORT_ALPHA)"
grep -q ' NODE_REPORT_CHARLIE ' n.txt && fail "charlie (500 m) got a report"
grep -q 'NAME=delta' n.txt && grep 'NAME=delta' n.txt | grep -qv ' NODE_REPORT ' && fail "delta (no TIME) was relayed"
ok "reports relayed within range only, as 24.8's node record (COG, LAT/LON, type uuv -> auv, a report without TIME refused)"
val NODE_MESSAGE_BRAVO | grep -qE '^src_node=alpha,dest_node=bravo,src_app=[^,]+,var_name=FOOBAR,string_val=hello$' ||
  fail "NODE_MESSAGE_BRAVO: $(val NODE_MESSAGE_BRAVO)"
grep ' VIEW_COMMS_PULSE ' n.txt | grep -q 'sx=0,sy=0,tx=50,ty=0,beam_width=5,fill=0.6,ptype=msg,label=alpha2bravowhite,fill_color=white,' ||
  fail "no white message pulse"
grep ' VIEW_COMMS_PULSE ' n.txt | grep -q 'beam_width=5,fill=0.35,ptype=nrep,label=alpha2bravo,fill_color=orange,time=' || fail "no report pulse"
ok "message delivered (src_app added) with a white pulse"
# the app never reads back its own posts (ignore_own_posts: a kernel filter on its socket):
# it reads fewer datagrams than the others and it wrote together (reading its own posts back
# would make it at least their sum)
own=$(awk '$2=="uFldNodeComms"' n.txt | grep -c . || true)
others=$(awk '$2!="uFldNodeComms"' n.txt | grep -c . || true)
read_dg=$(sed -n 's/^Transport: \([0-9]*\) datagrams.*/\1/p' app.out | tail -1)
[ -n "$read_dg" ] && [ "$own" -ge 6 ] && [ "$read_dg" -lt $((own + others)) ] ||
  fail "uFldNodeComms read $read_dg datagrams; the others wrote $others, it wrote $own"
ok "its own $own posts were not read back ($read_dg datagrams read, $others from the others)"
# VERBOSE = false: no summary in the status report (ufield.md 5.6.19); true: the summary
sed 's/^{$/{\n  VERBOSE = false/' n.moos > q.moos
rc=0; timeout -s INT 1.5 "$BIN/uFldNodeComms" q.moos > q.out 2>&1 || rc=$?
[ $rc -eq 0 ] || [ $rc -eq 124 ] || fail "uFldNodeComms exited $rc with VERBOSE = false"
grep -q 'Configuration warnings: 0' q.out || fail "configuration warnings: $(grep -A3 'Configuration warnings' q.out)"
grep -q 'Node Report Summary' q.out && fail "VERBOSE = false printed the summary"
rc=0; timeout -s INT 1.5 "$BIN/uFldNodeComms" n.moos > v.out 2>&1 || rc=$?
grep -q 'Total Blocked Msgs: 0' v.out || fail "no summary with VERBOSE = true"
ok "VERBOSE = false hides the summary"
