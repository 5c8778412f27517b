# The uField comms toolbox on four hosts (network namespaces joined by a bridge): a shoreside
# and three vehicles, each host's community started by kelp-launch on its own bus.
#  - the vehicles know only TRY_SHORE_HOST: uFldNodeBroker pings, uFldShoreBroker acks, and
#    the brokers' PMB_REGISTERs build the kelp-bridge routes both ways;
#  - node reports reach the shore, and uFldNodeComms relays each to the vehicles in comms
#    range only: ben (0,0) and cal (60,0) hear each other, deb (400,0) hears nobody;
#  - node messages reach their addressee and nobody else (ben -> cal delivered, ben -> deb
#    blocked by range, ben -> all reaches cal only), posted by uFldMessageHandler;
#  - uFldScope on the shore prints the vehicle table;
#  - the shoreside is killed and started again: the vehicles' pings find it, the bridges are
#    registered again, and a message sent after the restart arrives exactly once.
# KELP_FLEET_RUNS=N repeats the whole scenario N times (the issue asks for 5 in a row).
set -euo pipefail
[ "$(id -u)" -eq 0 ] || { echo "SKIP-needs-root"; exit 1; }
KELP_ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}
BIN=${BUILD:-$KELP_ROOT/build}/bin
unset KELP_LCM_URL
P=uf$$
T=$(mktemp -d /tmp/kelp-ufield.XXXXXX)
PIDS=()
HOSTS="sh ben cal deb"
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill -INT "$p" 2>/dev/null || true; done
  sleep 0.5
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  for h in $HOSTS br; do ip netns del ${P}$h 2>/dev/null || true; done
  [ -n "${KEEP_T:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for f in $T/*/logs*/*.log; do echo "--- $f"; tail -25 "$f"; done 2>/dev/null
  echo "FAIL: $*"   # again, last: the runner shows the end of the output
  exit 1
}
wait_for() { # FILE PATTERN SECONDS
  local i=0
  while [ $i -lt $(($3 * 10)) ]; do grep -qE "$2" "$1" 2>/dev/null && return 0; sleep 0.1; i=$((i + 1)); done
  return 1
}

# ---- four hosts on one link
ip netns add ${P}br
ip -n ${P}br link set lo up
ip -n ${P}br link add br0 type bridge
ip -n ${P}br link set br0 up
i=10
for h in $HOSTS; do
  ns=${P}$h
  ip netns add $ns
  ip -n $ns link set lo up
  ip -n $ns link set lo multicast on
  ip -n $ns link add eth0 type veth peer name ${P}v$i
  ip -n $ns link set ${P}v$i netns ${P}br
  ip -n ${P}br link set ${P}v$i master br0
  ip -n ${P}br link set ${P}v$i up
  ip -n $ns addr add 198.51.100.$i/24 dev eth0
  ip -n $ns link set eth0 up
  ip -n $ns route add 224.0.0.0/4 dev lo src 127.0.0.1   # each community's bus stays home
  i=$((i + 1))
done
SHORE_IP=198.51.100.10

# ---- missions
mkdir -p $T/sh
cat > $T/sh/shoreside.moos <<M
ServerHost = localhost
ServerPort = 9000
Community  = shoreside
MOOSTimeWarp = 1
LCM_URL    = udpm://239.255.76.67:7760?ttl=0
LatOrigin  = 43.825300
LongOrigin = -70.330400

ProcessConfig = ANTLER
{
  Run = pMOOSBridge      @ NewConsole = false
  Run = pHostInfo        @ NewConsole = false
  Run = uFldShoreBroker  @ NewConsole = false
  Run = uFldNodeComms    @ NewConsole = false
  Run = uFldScope        @ NewConsole = false
}
ProcessConfig = pMOOSBridge
{
  UDPListen = 9200
  ALLOW = NODE_BROKER_PING, NODE_REPORT, NODE_MESSAGE
}
ProcessConfig = pHostInfo
{
  AppTick = 4
}
ProcessConfig = uFldShoreBroker
{
  AppTick = 4
  QBRIDGE = DEPLOY, NODE_REPORT, NODE_MESSAGE
}
ProcessConfig = uFldNodeComms
{
  AppTick          = 4
  COMMS_RANGE      = 100
  CRITICAL_RANGE   = 30
  STALE_TIME       = 5
  MIN_MSG_INTERVAL = 0
  MAX_MSG_LENGTH   = 1000
  VERBOSE          = true
}
ProcessConfig = uFldScope
{
  AppTick = 2
  SCOPE = var=NODE_REPORT, key=NAME, fld=X, alias=x
  SCOPE = var=NODE_REPORT, key=NAME, fld=Y, alias=y
  SCOPE = var=NODE_REPORT, key=NAME, fld=TYPE
}
M
vehicle() { # NAME X Y
  mkdir -p $T/$1
  cat > $T/$1/$1.moos <<M
ServerHost = localhost
ServerPort = 9001
Community  = $1
MOOSTimeWarp = 1
LCM_URL    = udpm://239.255.76.67:7761?ttl=0
LatOrigin  = 43.825300
LongOrigin = -70.330400

ProcessConfig = ANTLER
{
  Run = pMOOSBridge        @ NewConsole = false
  Run = pHostInfo          @ NewConsole = false
  Run = uFldNodeBroker     @ NewConsole = false
  Run = uFldMessageHandler @ NewConsole = false
  Run = uSimMarine         @ NewConsole = false
  Run = pNodeReporter      @ NewConsole = false
}
ProcessConfig = pMOOSBridge
{
  UDPListen = 9200
  ALLOW = NODE_BROKER_ACK, NODE_REPORT, NODE_MESSAGE, DEPLOY
}
ProcessConfig = pHostInfo
{
  AppTick = 4
}
ProcessConfig = uFldNodeBroker
{
  AppTick = 4
  TRY_SHORE_HOST = pshare_route=$SHORE_IP:9200
  BRIDGE = src=NODE_REPORT_LOCAL, alias=NODE_REPORT
  BRIDGE = src=NODE_MESSAGE_LOCAL, alias=NODE_MESSAGE
  RETRY_INTERVAL = 3
}
ProcessConfig = uFldMessageHandler
{
  AppTick = 4
  STRICT_ADDRESSING = false   // dest_node=all is refused under strict addressing
}
ProcessConfig = uSimMarine
{
  AppTick   = 4
  START_POS = x=$2, y=$3, heading=0, speed=0
}
ProcessConfig = pNodeReporter
{
  AppTick = 2
  PLATFORM_TYPE = UUV
}
M
}
vehicle ben 0 0
vehicle cal 60 0
vehicle deb 400 0

in_ns() { local h=$1; shift; ip netns exec ${P}$h "$@"; }
moos_of() { [ "$1" = sh ] && echo shoreside.moos || echo "$1.moos"; }
url_of() { [ "$1" = sh ] && echo 'udpm://239.255.76.67:7760?ttl=0' || echo 'udpm://239.255.76.67:7761?ttl=0'; }
declare -A LAUNCH REC
start_host() { # HOST [log suffix]
  local h=$1 s=${2:-}
  ( cd $T/$h && exec ip netns exec ${P}$h $BIN/kelp-launch --log-dir logs$s "$(moos_of $h)" > launch$s.out 2>&1 ) &
  LAUNCH[$h]=$!; PIDS+=($!)
}
start_rec() { # HOST FILE
  ( cd $T/$1 && exec ip netns exec ${P}$1 $BIN/kelp-record --lcm-url="$(url_of $1)" -f "$2" > rec_$2.out 2>&1 ) &
  REC[$1]=$!; PIDS+=($!)
}
stop_pid() { kill -INT "$1" 2>/dev/null || true; for _ in $(seq 50); do kill -0 "$1" 2>/dev/null || return 0; sleep 0.1; done; kill -9 "$1" 2>/dev/null || true; }
poke() { local h=$1; shift; (cd $T/$h && in_ns $h $BIN/kelp-poke "$(moos_of $h)" "$@" > /dev/null); }
events() { $BIN/kelp-logcheck "$1" --print; }
val() { awk -v v="$2" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print}' "$1"; }

run_once() {
  local run=$1
  for h in $HOSTS; do rm -rf $T/$h/logs* $T/$h/*.lcmlog $T/$h/*.out; start_rec $h bus.lcmlog; done
  sleep 0.3
  for h in $HOSTS; do start_host $h; done
  # every vehicle acked by the shore, and the shore lists three vehicles
  for v in ben cal deb; do
    wait_for $T/$v/logs/uFldNodeBroker.log 'Total OK NODE_BROKER_ACK received: [1-9]' 25 || fail "run $run: $v never got an ack"
  done
  wait_for $T/sh/logs/uFldShoreBroker.log '^deb +198\.51\.100\.13 +ok ' 10 || fail "run $run: shore does not list deb ok"
  # reports relayed by range (reports come every 0.5 s; give the relays a few seconds)
  sleep 4
  poke ben "NODE_MESSAGE_LOCAL:=src_node=ben,dest_node=cal,var_name=HELLO,string_val=from_ben_$run"
  poke ben "NODE_MESSAGE_LOCAL:=src_node=ben,dest_node=deb,var_name=HELLO,string_val=to_deb_$run"
  poke ben "NODE_MESSAGE_LOCAL:=src_node=ben,dest_node=all,var_name=GREET,double_val=7"
  sleep 3
  wait_for $T/sh/logs/uFldScope.log '^ben +0(\.0+)? +0(\.0+)? +UUV' 5 || fail "run $run: uFldScope shows no row for ben"
  grep -qE '^cal +60(\.0+)? +0(\.0+)? +UUV' $T/sh/logs/uFldScope.log || fail "run $run: uFldScope shows no row for cal"
  grep -qE '^deb +400(\.0+)? +0(\.0+)? +UUV' $T/sh/logs/uFldScope.log || fail "run $run: uFldScope shows no row for deb"

  # ---- the shoreside goes away and comes back
  stop_pid ${LAUNCH[sh]}
  stop_pid ${REC[sh]}
  start_rec sh bus2.lcmlog
  sleep 2
  start_host sh 2
  wait_for $T/sh/logs2/uFldShoreBroker.log '^deb +198\.51\.100\.13 +ok ' 25 || fail "run $run: restarted shore never re-acked deb"
  wait_for $T/sh/logs2/uFldShoreBroker.log '^ben +198\.51\.100\.11 +ok ' 10 || fail "run $run: restarted shore never re-acked ben"
  wait_for $T/sh/logs2/uFldShoreBroker.log '^cal +198\.51\.100\.12 +ok ' 10 || fail "run $run: restarted shore never re-acked cal"
  sleep 3
  poke ben "NODE_MESSAGE_LOCAL:=src_node=ben,dest_node=cal,var_name=HELLO2,string_val=after_restart_$run"
  sleep 3
  for h in $HOSTS; do stop_pid ${LAUNCH[$h]}; done
  sleep 0.5
  for h in $HOSTS; do stop_pid ${REC[$h]}; done
  PIDS=()

  for h in $HOSTS; do events $T/$h/bus.lcmlog > $T/$h/ev.txt || fail "run $run: $h log undecodable"; done
  events $T/sh/bus2.lcmlog > $T/sh/ev2.txt || fail "run $run: shore log 2 undecodable"
  # relays by range: ben hears cal, cal hears ben, deb hears nobody; nobody hears itself
  local names
  names=$(val $T/ben/ev.txt NODE_REPORT | sed -n 's/.*NAME=\([a-z]*\).*/\1/p' | sort -u | tr '\n' ' ')
  [ "$names" = "cal " ] || fail "run $run: ben heard reports of '$names' (want cal)"
  names=$(val $T/cal/ev.txt NODE_REPORT | sed -n 's/.*NAME=\([a-z]*\).*/\1/p' | sort -u | tr '\n' ' ')
  [ "$names" = "ben " ] || fail "run $run: cal heard reports of '$names' (want ben)"
  [ "$(val $T/deb/ev.txt NODE_REPORT | wc -l)" -eq 0 ] || fail "run $run: deb (400 m away) heard reports"
  # the shore got every vehicle's report
  for v in ben cal deb; do
    grep -q "NAME=$v" <<<"$(val $T/sh/ev.txt NODE_REPORT)" || fail "run $run: no report of $v on the shore"
  done
  # messages: delivered to the addressee only
  [ "$(val $T/cal/ev.txt HELLO)" = "from_ben_$run" ] || fail "run $run: cal HELLO = '$(val $T/cal/ev.txt HELLO)'"
  [ "$(val $T/deb/ev.txt HELLO | wc -l)" -eq 0 ] || fail "run $run: deb got a HELLO (out of range)"
  [ "$(val $T/ben/ev.txt HELLO | wc -l)" -eq 0 ] || fail "run $run: ben got its own HELLO"
  [ "$(val $T/cal/ev.txt GREET)" = 7 ] || fail "run $run: cal GREET = '$(val $T/cal/ev.txt GREET)'"
  [ "$(val $T/deb/ev.txt GREET | wc -l)" -eq 0 ] || fail "run $run: deb got GREET (out of range)"
  [ "$(val $T/ben/ev.txt GREET | wc -l)" -eq 0 ] || fail "run $run: ben got its own GREET"
  grep -qE 'Range.*: *[1-9]|range.*[1-9]' $T/sh/logs/uFldNodeComms.log || true
  # after the restart: exactly once, and the relays came back
  [ "$(val $T/cal/ev.txt HELLO2)" = "after_restart_$run" ] || fail "run $run: after the restart cal HELLO2 = '$(val $T/cal/ev.txt HELLO2 | tr '\n' ' ')'"
  grep -q "NAME=deb" <<<"$(val $T/sh/ev2.txt NODE_REPORT)" || fail "run $run: no report of deb after the restart"
  local relays
  relays=$(val $T/sh/ev2.txt NODE_REPORT_BEN | wc -l)
  [ "$relays" -gt 0 ] || fail "run $run: no relays to ben after the restart"
  local acks
  acks=$(val $T/sh/ev2.txt PMB_REGISTER | grep -c 'dest_alias=NODE_BROKER_ACK' || true)
  [ "$acks" -eq 3 ] || fail "run $run: restarted shore registered $acks ack routes (want 3, one per vehicle)"
  echo "ok: run $run: 3 vehicles found the shore; relays ben<->cal only; HELLO ben->cal once, ben->deb blocked; GREET ->all reached cal only; shore restarted, $relays relays to ben after, HELLO2 once"
}

for r in $(seq ${KELP_FLEET_RUNS:-1}); do run_once $r; done
