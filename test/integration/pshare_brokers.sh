# A MOOS-IvP 24.8-style broker mission on three hosts (network namespaces joined by a bridge):
# a shoreside and two vehicles, each its own community started by kelp-launch from a .moos
# written the 24.8 way -- Run = pShare (kelp-bridge as pShare) with `input = route=...`,
# pHostInfo, uFldNodeBroker / uFldShoreBroker, uFldNodeComms on the shore -- nothing kelp-only.
# It shows the 24.8 handshake: PSHARE_CMD for the ping bridge every iteration until the ack,
# the first NODE_BROKER_PING_0 about 5 s after the broker starts (pHostInfo's tenth iteration
# carries the pShare input route) and then one every 15 s (20 s while acks come, acks for 10 s
# after a ping), acks with 24.8's keys; and data both ways: a vehicle's NODE_REPORT_LOCAL
# reaches the shore as NODE_REPORT, the shore's NODE_MESSAGE_<V> and DEPLOY_ALL reach the
# vehicle as NODE_MESSAGE and DEPLOY. MOOSTimeWarp 4 keeps it short.
set -euo pipefail
[ "$(id -u)" -eq 0 ] || { echo "SKIP-needs-root"; exit 1; }
KELP_ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}
BIN=${BUILD:-$KELP_ROOT/build}/bin
unset KELP_LCM_URL
P=kp$$
T=$(mktemp -d /tmp/kelp-pshare.XXXXXX)
PIDS=()
HOSTS="sh alpha bravo"
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill -INT "$p" 2>/dev/null || true; done
  sleep 0.5
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill -9 "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  for ns in $HOSTS br; do ip netns del ${P}$ns 2>/dev/null || true; done
  [ -n "${KEEP_T:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; for f in $T/*/logs/*.log; do echo "--- $f"; tail -30 $f; done 2>/dev/null; exit 1; }
ok() { echo "ok: $*"; }
wait_for() { # FILE PATTERN SECONDS
  local i=0
  while [ $i -lt $(($3 * 10)) ]; do grep -qE "$2" "$1" 2>/dev/null && return 0; sleep 0.1; i=$((i + 1)); done
  return 1
}
ip netns add ${P}br
ip -n ${P}br link set lo up
ip -n ${P}br link add br0 type bridge
ip -n ${P}br link set br0 up
i=1
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

# ---- the missions, as a MOOS-IvP 24.8 user writes them (meta_shoreside / plug_pShare style)
mkdir -p $T/sh $T/alpha $T/bravo
cat > $T/sh/shoreside.moos <<'M'
ServerHost = localhost
ServerPort = 9000
Community  = shoreside
MOOSTimeWarp = 4
LCM_URL    = udpm://239.255.76.67:7770?ttl=0

ProcessConfig = ANTLER
{
  MSBetweenLaunches = 100
  Run = pShare          @ NewConsole = false
  Run = pHostInfo       @ NewConsole = false
  Run = uFldShoreBroker @ NewConsole = false
  Run = uFldNodeComms   @ NewConsole = false
}

ProcessConfig = pShare
{
  AppTick    = 2
  CommsTick  = 2

  input = route = localhost:9300 & multicast_9
}

ProcessConfig = pHostInfo
{
  AppTick    = 2
  CommsTick  = 2

  DEFAULT_HOSTIP = localhost
}

ProcessConfig = uFldShoreBroker
{
  AppTick   = 2
  CommsTick = 2

  qbridge = DEPLOY, NODE_REPORT, NODE_MESSAGE
  bridge  = src=RETURN_ALL, alias=RETURN
  bridge  = src=RETURN_$V,  alias=RETURN
}

ProcessConfig = uFldNodeComms
{
  AppTick   = 2
  CommsTick = 2

  comms_range      = 75
  critical_range   = 25
  min_msg_interval = 0
  max_msg_length   = 1000
}
M
vehicle() { # NAME PORT
  cat > $T/$1/$1.moos <<M
ServerHost = localhost
ServerPort = 900$2
Community  = $1
MOOSTimeWarp = 4
LCM_URL    = udpm://239.255.76.67:777$2?ttl=0

ProcessConfig = ANTLER
{
  MSBetweenLaunches = 100
  Run = pShare          @ NewConsole = false
  Run = pHostInfo       @ NewConsole = false
  Run = uFldNodeBroker  @ NewConsole = false
}

ProcessConfig = pShare
{
  AppTick    = 2
  CommsTick  = 2

  input = route = localhost:920$2
}

ProcessConfig = pHostInfo
{
  AppTick    = 2
  CommsTick  = 2

  DEFAULT_HOSTIP = localhost
}

ProcessConfig = uFldNodeBroker
{
  AppTick   = 2
  CommsTick = 2

  TRY_SHORE_HOST = pshare_route=198.51.100.1:9300

  BRIDGE = src=VIEW_POLYGON
  BRIDGE = src=NODE_REPORT_LOCAL,  alias=NODE_REPORT
  BRIDGE = src=NODE_MESSAGE_LOCAL, alias=NODE_MESSAGE
}
M
}
vehicle alpha 1
vehicle bravo 2
moos_of() { [ "$1" = sh ] && echo shoreside.moos || echo "$1.moos"; }
url_of() { sed -n 's/^LCM_URL *= *//p' $T/$1/$(moos_of $1); }
in_ns() { local h=$1; shift; ip netns exec ${P}$h "$@"; }
poke() { local h=$1; shift; (cd $T/$h && in_ns $h $BIN/kelp-poke "$(moos_of $h)" "$@" > /dev/null); }
for h in $HOSTS; do
  ( cd $T/$h && exec ip netns exec ${P}$h $BIN/kelp-record --lcm-url="$(url_of $h)" -f bus.lcmlog > rec.out 2>&1 ) &
  PIDS+=($!)
done
sleep 0.3
for h in $HOSTS; do
  ( cd $T/$h && exec ip netns exec ${P}$h $BIN/kelp-launch --log-dir logs "$(moos_of $h)" > launch.out 2>&1 ) &
  PIDS+=($!)
done
start=$(date +%s.%N)
# both vehicles acked, their bridges requested (24.8's phase 5), then the data
for v in alpha bravo; do
  wait_for $T/$v/logs/uFldNodeBroker.log 'Phase 5: \(Y\)' 20 || fail "$v never reached phase 5 (user bridges requested)"
done
sleep 1
poke alpha "NODE_REPORT_LOCAL:=NAME=alpha,TYPE=kayak,X=10,Y=-5,SPD=1,HDG=90,TIME=1"
poke bravo "NODE_REPORT_LOCAL:=NAME=bravo,TYPE=kayak,X=30,Y=-5,SPD=1,HDG=90,TIME=1"
poke sh "NODE_MESSAGE_ALPHA:=src_node=shoreside,dest_node=alpha,var_name=RETURN,string_val=true" DEPLOY_ALL:=true
# until each vehicle has pinged three times (5 s, 20 s, 35 s of MOOS time at warp 4: about 9 s
# from the brokers' start, later on a loaded host), then 1 s of acks; at most 20 s
pings() { $BIN/kelp-logcheck $T/$1/bus.lcmlog --print 2>/dev/null | awk '$3=="NODE_BROKER_PING_0"' | wc -l; }
while awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN{exit !(n - s < 20)}'; do
  [ "$(pings alpha)" -ge 3 ] && [ "$(pings bravo)" -ge 3 ] && break
  sleep 0.5
done
sleep 1
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
for h in $HOSTS; do $BIN/kelp-logcheck $T/$h/bus.lcmlog --print > $T/$h/ev.txt || fail "$h log undecodable"; done
val() { awk -v v="$2" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print}' "$1"; }
tim() { awk -v v="$2" '$3==v {print $1}' "$1"; }
val1() { awk -v v="$2" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print; exit}' "$1"; }   # the first (no SIGPIPE)
tim1() { awk -v v="$2" '$3==v {print $1; exit}' "$1"; }

# ---- pShare's summaries and pHostInfo's record on the shore
[ "$(val $T/sh/ev.txt PSHARE_INPUT_SUMMARY | tail -1)" = "224.1.1.11:24469:multicast_9,localhost:9300" ] || fail "shore PSHARE_INPUT_SUMMARY: $(val $T/sh/ev.txt PSHARE_INPUT_SUMMARY | tail -1)"
[ "$(val $T/sh/ev.txt PHI_HOST_INFO | tail -1)" = "community=shoreside,hostip=198.51.100.1,port_db=9000,port_udp=9300,pshare_iroutes=multicast_9&198.51.100.1:9300,hostip_alts=,timewarp=4" ] || fail "shore PHI_HOST_INFO: $(val $T/sh/ev.txt PHI_HOST_INFO | tail -1)"
ok "shore: PSHARE_INPUT_SUMMARY and PHI_HOST_INFO as 24.8 posts them"

for v in alpha bravo; do
  E=$T/$v/ev.txt
  n=$([ $v = alpha ] && echo 2 || echo 3); p=$([ $v = alpha ] && echo 1 || echo 2)
  # 24.8's uFldNodeBroker posts its process id at start-up
  grep -qE "^[0-9.]+ uFldNodeBroker UFLDNODEBROKER_PID [1-9][0-9]*$" $E || fail "$v: no UFLDNODEBROKER_PID"
  # the ping bridge, every iteration until the first ack, then never again
  t_ack=$(tim1 $E NODE_BROKER_ACK)
  [ -n "$t_ack" ] || fail "$v: no NODE_BROKER_ACK"
  cmd="cmd=output,src_name=NODE_BROKER_PING_0,dest_name=NODE_BROKER_PING,route=198.51.100.1:9300"
  n_before=$(awk -v a="$t_ack" '$3=="PSHARE_CMD" && $1 < a && $4 ~ /src_name=NODE_BROKER_PING_0,/' $E | wc -l)
  n_after=$(awk -v a="$t_ack" '$3=="PSHARE_CMD" && $1 > a + 1 && $4 ~ /src_name=NODE_BROKER_PING_0,/' $E | wc -l)
  [ "$n_before" -ge 6 ] && [ "$n_after" -eq 0 ] || fail "$v: ping bridge posted $n_before times before the ack, $n_after after"
  grep -q " PSHARE_CMD cmd=output,src_name=NODE_BROKER_PING_0,dest_name=NODE_BROKER_PING,route=198.51.100.1:9300$" $E || fail "$v: PSHARE_CMD form"
  # the pings: 24.8's keys, the first ~5 s after the broker's first PSHARE_CMD, then every ~15 s
  ping=$(val1 $E NODE_BROKER_PING_0)
  [[ "$ping" =~ ^community=$v,hostip=198\.51\.100\.$n,port_db=900$p,port_udp=920$p,pshare_iroutes=198\.51\.100\.$n:920$p,timewarp=4,time=[0-9]+\.[0-9][0-9],key=0$ ]] || fail "$v ping: $ping"
  [ "$(val $E NODE_BROKER_PING | wc -l)" -eq 0 ] || fail "$v posted the seed's NODE_BROKER_PING"
  t0=$(tim1 $E PSHARE_CMD)
  gaps=$( (echo "$t0"; tim $E NODE_BROKER_PING_0) | awk 'NR>1{printf "%.1f ", $1 - p} {p=$1}')
  echo "$v: first ping and the gaps between pings (MOOS s): $gaps"
  echo "$gaps" | awk '{ if (NF < 3) exit 1; if ($1 < 3.5 || $1 > 7.5) exit 1; for (i = 2; i <= NF; i++) if ($i < 13.5 || $i > 17) exit 1 }' || fail "$v: ping times $gaps (want ~5, then ~15 apart)"
  # the acks: 24.8's keys, every iteration while the last ping is fresh
  ack=$(val1 $E NODE_BROKER_ACK)
  [[ "$ack" =~ ^community=shoreside,hostip=198\.51\.100\.1,port_db=9000,port_udp=9300,pshare_iroutes=multicast_9\&198\.51\.100\.1:9300,timewarp=4,status=ok,key=0,id=[0-9]+$ ]] || fail "$v ack: $ack"
  n_ack=$(val $E NODE_BROKER_ACK | wc -l); n_ping=$(val $E NODE_BROKER_PING_0 | wc -l)
  [ "$n_ack" -ge $((n_ping * 10)) ] || fail "$v: $n_ack acks for $n_ping pings (want ~20 per ping)"
  # the user's bridges and the automatic ones, once, after the first ack
  for b in "src_name=NODE_REPORT_LOCAL,dest_name=NODE_REPORT" "src_name=NODE_MESSAGE_LOCAL,dest_name=NODE_MESSAGE" \
           "src_name=APPCAST,dest_name=APPCAST" "src_name=REALMCAST,dest_name=REALMCAST" "src_name=NODE_PSHARE_VARS,dest_name=NODE_PSHARE_VARS"; do
    [ "$(grep -c " PSHARE_CMD cmd=output,$b,route=198.51.100.1:9300$" $E)" -eq 1 ] || fail "$v: bridge $b not requested once"
  done
  ok "$v: $n_ping pings ($gaps), $n_ack acks, bridges requested after the first ack"
  # data, shore -> vehicle
  [ "$(val $E NODE_MESSAGE)" = "src_node=shoreside,dest_node=alpha,var_name=RETURN,string_val=true" ] || [ $v = bravo ] || fail "alpha: NODE_MESSAGE $(val $E NODE_MESSAGE)"
  [ $v = alpha ] || [ -z "$(val $E NODE_MESSAGE)" ] || fail "bravo got alpha's NODE_MESSAGE"
  [ "$(val $E DEPLOY)" = true ] || fail "$v: DEPLOY_ALL did not arrive as DEPLOY: $(val $E DEPLOY)"
done
# data, vehicle -> shore; the shore's requests and sets
S=$T/sh/ev.txt
val $S NODE_REPORT > $T/reports.txt
grep -qx "NAME=alpha,TYPE=kayak,X=10,Y=-5,SPD=1,HDG=90,TIME=1" $T/reports.txt || fail "alpha's NODE_REPORT_LOCAL did not reach the shore as NODE_REPORT"
grep -qx "NAME=bravo,TYPE=kayak,X=30,Y=-5,SPD=1,HDG=90,TIME=1" $T/reports.txt || fail "bravo's NODE_REPORT_LOCAL did not reach the shore as NODE_REPORT"
[ "$(val1 $S UFSB_QBRIDGE_VARS)" = "APPCAST_REQ,DEPLOY,NODE_MESSAGE,NODE_REPORT,REALMCAST_REQ" ] || fail "UFSB_QBRIDGE_VARS $(val $S UFSB_QBRIDGE_VARS)"
last_vars=$(val $S UFSB_BRIDGE_VARS | tail -1)
for w in APPCAST_REQ_ALL APPCAST_REQ_ALPHA APPCAST_REQ_BRAVO MISSION_HASH NODE_BROKER_ACK_ALPHA NODE_BROKER_ACK_BRAVO NODE_MESSAGE_ALPHA REALMCAST_REQ_BRAVO RETURN_ALL 'RETURN_$V'; do
  [[ ",$last_vars," == *",$w,"* ]] || fail "UFSB_BRIDGE_VARS lacks $w: $last_vars"
done
grep -q " PSHARE_CMD cmd=output,src_name=NODE_BROKER_ACK_ALPHA,dest_name=NODE_BROKER_ACK,route=198.51.100.2:9201$" $S || fail "no ack bridge to alpha"
grep -q " PSHARE_CMD cmd=output,src_name=DEPLOY_ALL,dest_name=DEPLOY,route=198.51.100.3:9202$" $S || fail "no DEPLOY_ALL bridge to bravo"
[ "$(val $S NODE_BROKER_VACK | sort -u | tr '\n' ' ')" = "alpha bravo " ] || fail "NODE_BROKER_VACK $(val $S NODE_BROKER_VACK | sort -u)"
summary=$(val $S PSHARE_OUTPUT_SUMMARY | tail -1)
[[ "$summary" == *"NODE_BROKER_ACK_ALPHA->NODE_BROKER_ACK:198.51.100.2:9201"* ]] || fail "PSHARE_OUTPUT_SUMMARY lacks the ack bridge"
grep -q "alpha  *198.51.100.2  *ok " $T/sh/logs/uFldShoreBroker.log || fail "the shore's report does not list alpha ok"
ok "the shore took both vehicles' pings, bridged its QBRIDGE/BRIDGE variables and acks to each; reports and messages went both ways"
