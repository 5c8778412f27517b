# uFldNodeBroker and uFldShoreBroker on two hosts (network namespaces joined by a bridge),
# one community each on its own LCM URL, each with kelp-bridge + pHostInfo + its broker.
# The vehicle finds the shore from TRY_SHORE_HOST alone; the brokers' PMB_REGISTERs build
# the bridges both ways: NODE_REPORT_LOCAL posted on the vehicle arrives on the shore as
# NODE_REPORT, DEPLOY_ALL (QBRIDGE) and RETURN_ALPHA ($V) posted on the shore arrive on the
# vehicle as DEPLOY and RETURN. Then the shore's broker and bridge are restarted: the
# vehicle's pings find the new shore, which registers the bridges again (once each), and a
# second DEPLOY_ALL arrives.
#
# The ALLOW lines a mission needs: the shore's kelp-bridge lets in NODE_BROKER_PING and the
# aliases of the vehicles' BRIDGE lines; a vehicle's lets in NODE_BROKER_ACK and the aliases
# of the shore's BRIDGE / QBRIDGE lines.
set -euo pipefail
[ "$(id -u)" -eq 0 ] || { echo "SKIP-needs-root"; exit 1; }
KELP_ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}
BIN=${BUILD:-$KELP_ROOT/build}/bin
unset KELP_LCM_URL
P=kf$$
T=$(mktemp -d /tmp/kelp-brokers.XXXXXX)
PIDS=()
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  for ns in ${P}h1 ${P}h2 ${P}br; do ip netns del $ns 2>/dev/null || true; done
  [ -n "${KEEP_T:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; for f in $T/*.log; do echo "--- $f"; tail -40 $f; done 2>/dev/null; exit 1; }
wait_for() { # FILE PATTERN SECONDS
  local i=0
  while [ $i -lt $(($3 * 10)) ]; do grep -qE "$2" "$1" 2>/dev/null && return 0; sleep 0.1; i=$((i + 1)); done
  return 1
}
ip netns add ${P}br
ip -n ${P}br link set lo up
ip -n ${P}br link add br0 type bridge
ip -n ${P}br link set br0 up
for i in 1 2; do
  ns=${P}h$i
  ip netns add $ns
  ip -n $ns link set lo up
  ip -n $ns link set lo multicast on
  ip -n $ns link add eth0 type veth peer name ${P}v$i
  ip -n $ns link set ${P}v$i netns ${P}br
  ip -n ${P}br link set ${P}v$i master br0
  ip -n ${P}br link set ${P}v$i up
  ip -n $ns addr add 198.51.100.$i/24 dev eth0
  ip -n $ns link set eth0 up
  # each community's bus stays on its host's loopback
  ip -n $ns route add 224.0.0.0/4 dev lo src 127.0.0.1
done
US='udpm://239.255.76.67:7681?ttl=0'
UV='udpm://239.255.76.67:7682?ttl=0'
cat > $T/shore.moos <<M
Community = shoreside
ServerPort = 9000
MOOSTimeWarp = 2
LCM_URL = $US
ProcessConfig = pMOOSBridge
{
  UDPListen = 9300
  KEY = sea-secret
  ALLOW = NODE_BROKER_PING, NODE_REPORT
}
ProcessConfig = pHostInfo
{
  AppTick = 4
}
ProcessConfig = uFldShoreBroker
{
  AppTick = 4
  KEYWORD = lemon
  QBRIDGE = DEPLOY
  BRIDGE  = src=RETURN_\$V, alias=RETURN
  BRIDGE  = src=LOITER_\$N, alias=LOITER
}
ProcessConfig = scope
{
  VAR = NODE_REPORT
}
M
cat > $T/alpha.moos <<M
Community = alpha
ServerPort = 9001
MOOSTimeWarp = 2
LCM_URL = $UV
ProcessConfig = pMOOSBridge
{
  UDPListen = 9301
  KEY = sea-secret
  ALLOW = NODE_BROKER_ACK, DEPLOY, RETURN, LOITER
}
ProcessConfig = pHostInfo
{
  AppTick = 4
}
ProcessConfig = uFldNodeBroker
{
  AppTick = 4
  KEYWORD = lemon
  TRY_SHORE_HOST = host_ip=198.51.100.1, port_udp=9300, community=shoreside
  TRY_SHORE_HOST = pshare_route=198.51.100.77:9300
  BRIDGE = src=NODE_REPORT_LOCAL, alias=NODE_REPORT
  RETRY_INTERVAL = 4
}
ProcessConfig = scope
{
  VAR = DEPLOY, RETURN, LOITER
}
M
cd $T
H1="ip netns exec ${P}h1"
H2="ip netns exec ${P}h2"
$H1 $BIN/kelp-record --lcm-url="$US" -f shore.lcmlog > rec1.log 2>&1 & PIDS+=($!)
$H2 $BIN/kelp-record --lcm-url="$UV" -f alpha.lcmlog > rec2.log 2>&1 & PIDS+=($!)
sleep 0.3
$H1 $BIN/kelp-bridge shore.moos > shore_bridge.log 2>&1 & SB=$!; PIDS+=($SB)
$H2 $BIN/kelp-bridge alpha.moos > alpha_bridge.log 2>&1 & PIDS+=($!)
$H1 $BIN/pHostInfo shore.moos > shore_phi.log 2>&1 & PIDS+=($!)
$H2 $BIN/pHostInfo alpha.moos > alpha_phi.log 2>&1 & PIDS+=($!)
$H1 $BIN/uFldShoreBroker shore.moos > shore_broker.log 2>&1 & SBR=$!; PIDS+=($SBR)
$H2 $BIN/uFldNodeBroker alpha.moos > alpha_broker.log 2>&1 & PIDS+=($!)
wait_for alpha_broker.log 'Total OK NODE_BROKER_ACK received: [1-9]' 20 || fail "the vehicle never got an ack"
wait_for shore_broker.log '^alpha +198\.51\.100\.2 +ok ' 5 || fail "the shore does not list alpha as ok"
grep -q 'Total PMB_REGISTER        posted: 3' alpha_broker.log || fail "vehicle: not 2 ping routes + 1 bridge"
sleep 1
$H2 $BIN/kelp-poke alpha.moos "NODE_REPORT_LOCAL:=NAME=alpha,TYPE=UUV,X=12.5,Y=-3,SPD=1,HDG=90" > poke1.out
$H1 $BIN/kelp-poke shore.moos DEPLOY_ALL:=true RETURN_ALPHA:=home > poke2.out
sleep 1
# the shore restarts (broker and bridge): the vehicle's pings bring the bridges back
kill -INT $SBR $SB; wait $SBR $SB 2>/dev/null || true
cp shore_broker.log shore_broker1.log
$H1 $BIN/kelp-bridge shore.moos > shore_bridge2.log 2>&1 & PIDS+=($!)
$H1 $BIN/uFldShoreBroker shore.moos > shore_broker2.log 2>&1 & PIDS+=($!)
$H1 $BIN/kelp-poke shore.moos HOST_INFO_REQUEST:=true > poke3.out
wait_for shore_broker2.log 'Total NODE_BROKER_ACK    posted: [1-9]' 20 || fail "restarted shore never acked"
sleep 1.5
$H1 $BIN/kelp-poke shore.moos DEPLOY_ALL:=again > poke4.out
sleep 1
timeout 2 $H1 $BIN/kelp-scope shore.moos scope > shore_scope.out 2>&1 || true
timeout 2 $H2 $BIN/kelp-scope alpha.moos scope > alpha_scope.out 2>&1 || true
for p in "${PIDS[@]}"; do kill -INT $p 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
$BIN/kelp-logcheck shore.lcmlog --print > shore_events.txt || fail "shore log undecodable"
$BIN/kelp-logcheck alpha.lcmlog --print > alpha_events.txt || fail "alpha log undecodable"
val() { awk -v v="$2" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print}' "$1"; }
# the vehicle's requests: a ping route per try host, then its bridge to the shore it found
val alpha_events.txt PMB_REGISTER | sort -u > alpha_regs.txt
grep -qx 'src_var=NODE_BROKER_PING,dest_community=shoreside,dest_host=198.51.100.1,dest_port=9300,dest_alias=NODE_BROKER_PING' alpha_regs.txt || fail "no ping route: $(cat alpha_regs.txt)"
grep -qx 'src_var=NODE_REPORT_LOCAL,dest_community=shoreside,dest_host=198.51.100.1,dest_port=9300,dest_alias=NODE_REPORT' alpha_regs.txt || fail "no NODE_REPORT bridge: $(cat alpha_regs.txt)"
ping=$(val alpha_events.txt NODE_BROKER_PING | sed -n 1p)
[[ "$ping" =~ ^community=alpha,host=198\.51\.100\.2,port=9001,port_udp=9301,keyword=lemon,time_warp=2,time=[0-9.]+$ ]] || fail "ping: $ping"
# the shore's requests, per run: the ack bridge, DEPLOY_ALL, DEPLOY_ALPHA, RETURN_ALPHA, LOITER_1, once each
want='src_var=NODE_BROKER_ACK_ALPHA,dest_community=alpha,dest_host=198.51.100.2,dest_port=9301,dest_alias=NODE_BROKER_ACK
src_var=DEPLOY_ALL,dest_community=alpha,dest_host=198.51.100.2,dest_port=9301,dest_alias=DEPLOY
src_var=DEPLOY_ALPHA,dest_community=alpha,dest_host=198.51.100.2,dest_port=9301,dest_alias=DEPLOY
src_var=RETURN_ALPHA,dest_community=alpha,dest_host=198.51.100.2,dest_port=9301,dest_alias=RETURN
src_var=LOITER_1,dest_community=alpha,dest_host=198.51.100.2,dest_port=9301,dest_alias=LOITER'
got=$(val shore_events.txt PMB_REGISTER)
[ "$got" = "$want"$'\n'"$want" ] || fail "shore PMB_REGISTERs (two runs, 5 each):
$got"
# the data: vehicle -> shore and shore -> vehicle, through the brokered bridges
[ "$(val shore_events.txt NODE_REPORT)" = 'NAME=alpha,TYPE=UUV,X=12.5,Y=-3,SPD=1,HDG=90' ] || fail "NODE_REPORT did not reach the shore once"
[ "$(val alpha_events.txt DEPLOY | sed -n 1p)" = true ] || fail "DEPLOY_ALL did not reach the vehicle as DEPLOY"
[ "$(val alpha_events.txt RETURN)" = home ] || fail "RETURN_ALPHA did not reach the vehicle as RETURN"
[ "$(val alpha_events.txt DEPLOY | sed -n '$p')" = again ] || fail "DEPLOY_ALL after the shore restart did not arrive"
[ "$(val alpha_events.txt DEPLOY | wc -l)" -eq 2 ] || fail "DEPLOY arrived $(val alpha_events.txt DEPLOY | wc -l) times (2 posts)"
grep -q 'Total BAD NODE_BROKER_ACK received: 0' alpha_broker.log || fail "bad acks on the vehicle"
n_ack=$(awk '$3=="NODE_BROKER_ACK"' alpha_events.txt | wc -l)
echo "ok: vehicle found the shore ($n_ack acks), NODE_REPORT_LOCAL -> NODE_REPORT, DEPLOY_ALL -> DEPLOY, RETURN_ALPHA -> RETURN, shore restart re-registered 5 bridges once"
