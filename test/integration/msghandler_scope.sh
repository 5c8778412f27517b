#!/usr/bin/env bash
# uFldMessageHandler and uFldScope on real buses (ufield.md 6 and 7):
#  - vehicle alpha posts NODE_MESSAGE_LOCAL; kelp-bridge carries it to vehicle bravo's
#    community as NODE_MESSAGE; bravo's uFldMessageHandler posts the carried variable (a
#    double, and a string with commas), with its msg_flag; messages poked straight into
#    bravo: for charlie (rejected), without var_name (invalid), both counted in
#    UMH_SUMMARY_MSGS; the rejected one is followed by bad_msg_flag with $[BAD_CTR] (24.8);
#  - uFldScope, stdout a file and keys from a FIFO, prints the table of the reports poked
#    into its community (rows in name order, alias headers), and switches to layout (1) on 'l';
#  - uFldScope in a tmux terminal draws the same table in place with ncurses and follows keys.
. "$(dirname "$0")/lib.sh"
cd "$T"
URL_B=$KELP_LCM_URL
URL_A="udpm://239.255.76.67:$((TEST_PORT + 1))?ttl=0"
PORT_B=$((20000 + TEST_PORT))

cat > alpha.moos <<M
Community = alpha
ProcessConfig = pMOOSBridge
{
  UDPListen = $((PORT_B + 1))
  UDPSHARE = [NODE_MESSAGE_LOCAL] -> bravo @ 127.0.0.1:$PORT_B [NODE_MESSAGE]
}
M
cat > bravo.moos <<M
Community = bravo
ProcessConfig = pMOOSBridge
{
  UDPListen = $PORT_B
  ALLOW = NODE_MESSAGE
}
ProcessConfig = uFldMessageHandler
{
  AppTick = 4
  msg_flag = GOT=n\$[GOOD_CTR]
  bad_msg_flag = TOTAL_BAD=\$[BAD_CTR]
}
ProcessConfig = uFldScope
{
  AppTick = 4
  SCOPE = var=NODE_REPORT,key=NAME,fld=TIME,alias=Time
  SCOPE = var=NODE_REPORT,key=NAME,fld=MODE
  SCOPE = var=SPEED_REPORT,key=vname,fld=avg_speed,alias=speed
  SCOPE = var=ODOMETRY_REPORT,key=vname,fld=trip_dist
  LAYOUT = trip_dist
  LAYOUT = MODE, speed, Time
}
M

bg "$BIN/kelp-record" --lcm-url="$URL_B" -f b.lcmlog
bg "$BIN/kelp-bridge" bravo.moos pMOOSBridge > bridge_b.out
KELP_LCM_URL=$URL_A bg "$BIN/kelp-bridge" alpha.moos pMOOSBridge > bridge_a.out
bg "$BIN/uFldMessageHandler" bravo.moos > umh.out
mkfifo keys
exec 3<>keys
# (not through bg: a background command without its own redirection reads /dev/null)
"$BIN/uFldScope" bravo.moos < keys > scope.out &
PIDS+=($!)
sleep 1.5

# alpha -> bravo through the bridge
KELP_LCM_URL=$URL_A "$BIN/kelp-poke" alpha.moos \
  'NODE_MESSAGE_LOCAL:=src_node=alpha,dest_node=bravo,var_name=SPEED,double_val=2.5' > poke1.out 2>&1 ||
  fail "poke alpha: $(cat poke1.out)"
KELP_LCM_URL=$URL_A "$BIN/kelp-poke" alpha.moos \
  'NODE_MESSAGE_LOCAL:=src_node=alpha,dest_group=red,src_var=PLAN,string_val="points=0,0:5,5"' > poke2.out 2>&1 ||
  fail "poke alpha: $(cat poke2.out)"
# straight into bravo: rejected, invalid, and an outgoing NODE_MESSAGE_LOCAL (not handled)
"$BIN/kelp-poke" bravo.moos 'NODE_MESSAGE:=src_node=alpha,dest_node=charlie,var_name=NOT_MINE,double_val=1' > /dev/null
"$BIN/kelp-poke" bravo.moos 'NODE_MESSAGE:=src_node=alpha,dest_node=bravo,string_val=lost' > /dev/null
"$BIN/kelp-poke" bravo.moos 'NODE_MESSAGE_LOCAL:=src_node=bravo,dest_node=alpha,var_name=OUTGOING,double_val=1' > /dev/null
# reports for the scope, rows arriving out of name order
"$BIN/kelp-poke" bravo.moos 'NODE_REPORT:=NAME=charlie,TYPE=UUV,TIME=2651922526.73,X=1,Y=2,MODE=RETURNING' \
  'NODE_REPORT:=NAME=alpha,TYPE=UUV,TIME=2651922526.54,X=3,Y=4,MODE=MODE@ACTIVE:LOITERING' \
  'SPEED_REPORT:=vname=alpha,avg_speed=1.96' 'ODOMETRY_REPORT:=vname=charlie,trip_dist=1466.3' > /dev/null
sleep 1.5
printf 'l' >&3
sleep 1

# the tmux terminal: ncurses in place, keys acted on at once
if [ -z "${NO_TMUX:-}" ] && command -v tmux > /dev/null; then
  TM="tmux -L kelp-it-$$"
  $TM -f /dev/null new-session -d -s ufs -x 120 -y 20 "$BIN/uFldScope $T/bravo.moos; sleep 30" ||
    fail "tmux would not start"
  # the first table: up to 10 s on a loaded machine
  for _ in $(seq 50); do
    sleep 0.2
    $TM capture-pane -p -t ufs > pane1.txt
    grep -q '^VName    Time           MODE                   speed  trip_dist  STREAMING(A)' pane1.txt && break
  done
  $TM send-keys -t ufs l
  sleep 1
  $TM capture-pane -p -t ufs > pane2.txt
  $TM send-keys -t ufs p
  sleep 1
  $TM capture-pane -p -t ufs > pane3.txt
  $TM kill-server 2>/dev/null || true
  grep -q '^VName    Time           MODE                   speed  trip_dist  STREAMING(A)' pane1.txt ||
    { cat pane1.txt; fail "tmux: no table (A)"; }
  grep -q '^alpha    2651922526.54  MODE@ACTIVE:LOITERING  1.96 *$' pane1.txt || { cat pane1.txt; fail "tmux: alpha row"; }
  [ "$(grep -c 'VName' pane1.txt)" -eq 1 ] || { cat pane1.txt; fail "tmux: the table is not drawn in place"; }
  grep -q '^VName    Time           MODE                   speed  STREAMING(1)' pane2.txt || { cat pane2.txt; fail "tmux: 'l' did not switch to (1)"; }
  grep -q 'PAUSED(1)' pane3.txt || { cat pane3.txt; fail "tmux: 'p' did not pause"; }
  ok "uFldScope in a tmux terminal: ncurses table drawn in place, 'l' -> (1), 'p' -> PAUSED"
else
  echo "skip: tmux is not installed (the ncurses check)"
fi

for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print b.lcmlog > b.txt || fail "log undecodable"
first() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print; exit}' b.txt; }
last() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); x=$0} END{print x}' b.txt; }
[ "$(first SPEED)" = 2.5 ] || { cat umh.out; fail "SPEED $(first SPEED), expected 2.5 carried from alpha"; }
grep -E ' SPEED 2.5' b.txt | grep -q uFldMessageHandler || fail "SPEED not written by uFldMessageHandler: $(grep ' SPEED ' b.txt)"
[ "$(first PLAN)" = "points=0,0:5,5" ] || fail "PLAN '$(first PLAN)', expected the quoted string without quotes"
[ -z "$(first NOT_MINE)" ] || fail "a message for charlie was posted"
[ -z "$(first OUTGOING)" ] || fail "NODE_MESSAGE_LOCAL was handled"
[ "$(last GOT)" = n2 ] || fail "msg_flag GOT '$(last GOT)', expected n2"
[ "$(last TOTAL_BAD)" = 1 ] || fail "bad_msg_flag TOTAL_BAD '$(last TOTAL_BAD)', expected 1 (the rejected message)"
[ "$(last UMH_SUMMARY_MSGS)" = "total=4,valid=3,rejected=1" ] || fail "summary '$(last UMH_SUMMARY_MSGS)'"
grep -q "Total Received Valid: 4" umh.out || fail "no report: $(tail -30 umh.out)"
grep -q '^  src_node=alpha,dest_node=charlie,var_name=NOT_MINE,double_val=1$' umh.out || fail "rejected list"
grep -q '^  src_node=alpha,dest_node=bravo,string_val=lost$' umh.out || fail "invalid list"
ok "uFldMessageHandler: SPEED=2.5 and PLAN carried alpha -> bravo through kelp-bridge; $(last UMH_SUMMARY_MSGS); TOTAL_BAD=1"

# the scope's plain output: the full table, then layout (1) after 'l'
grep -qx 'VName    Time           MODE                   speed  trip_dist  STREAMING(A)' scope.out ||
  { tail -20 scope.out; fail "no full table header"; }
grep -qx 'alpha    2651922526.54  MODE@ACTIVE:LOITERING  1.96' scope.out || { tail -20 scope.out; fail "alpha row"; }
grep -qx 'charlie  2651922526.73  RETURNING                     1466.3' scope.out || { tail -20 scope.out; fail "charlie row"; }
a=$(grep -n '^alpha ' scope.out | tail -1 | cut -d: -f1); c=$(grep -n '^charlie ' scope.out | tail -1 | cut -d: -f1)
[ "$a" -lt "$c" ] || fail "rows not in name order"
grep -qx 'VName    Time           MODE                   speed  STREAMING(1)' scope.out || { tail -20 scope.out; fail "no layout (1) after 'l'"; }
grep -q 'Configuration warnings: 0' scope.out || fail "uFldScope configuration warnings"
ok "uFldScope (plain output): rows alpha, charlie; 'l' switched to layout (1)"
