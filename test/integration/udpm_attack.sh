# A running mission under attack from a second host (network namespace): the issue's two
# crafted fragment datagrams (header shorter than 20 bytes; offset near 2^32) and 10,000
# random datagrams arrive while valid traffic flows. Every app survives and counts them,
# and the valid traffic (short and fragmented) arrives complete and intact.
set -euo pipefail
[ "$(id -u)" -eq 0 ] || { echo "SKIP-needs-root"; exit 1; }
KELP_ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}
BIN=${BUILD:-$KELP_ROOT/build}/bin
unset KELP_LCM_URL
P=ka$$
T=$(mktemp -d /tmp/kelp-attack.XXXXXX)
PIDS=()
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  for ns in ${P}m ${P}a; do ip netns del $ns 2>/dev/null || true; done
  [ -n "${KEEP_T:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; for f in $T/*.out; do echo "--- $f"; tail -20 $f; done 2>/dev/null; exit 1; }
ok() { echo "ok: $*"; }
ready() { for i in $(seq 50); do grep -q ready "$1" 2>/dev/null && return 0; sleep 0.1; done; return 1; }
# m: the mission's host; a: the attacker, one veth apart
for ns in ${P}m ${P}a; do ip netns add $ns; ip -n $ns link set lo up; done
ip -n ${P}m link add eth0 type veth peer name eth0 netns ${P}a
ip -n ${P}m addr add 198.51.100.1/24 dev eth0
ip -n ${P}a addr add 198.51.100.2/24 dev eth0
for ns in ${P}m ${P}a; do ip -n $ns link set eth0 up; ip -n $ns route add 224.0.0.0/4 dev eth0; done
M="ip netns exec ${P}m"
U='udpm://239.255.76.67:7733?ttl=0'
cat > $T/m.moos <<EOF2
Community = target
LCM_URL = $U
ProcessConfig = relay1
{
  AppTick = 20
  INCOMING_VAR = PING_IN
  OUTGOING_VAR = PING_MID
}
ProcessConfig = relay2
{
  AppTick = 20
  INCOMING_VAR = PING_MID
  OUTGOING_VAR = PING_OUT
}
EOF2
cd $T
$M $BIN/pXRelay m.moos relay1 > relay1.out 2>&1 & PIDS+=($!); R1=$!
$M $BIN/pXRelay m.moos relay2 > relay2.out 2>&1 & PIDS+=($!); R2=$!
$M $BIN/kelp-lcmprobe --lcm-url=$U recv kelp 3000 40 > short.out 2>&1 & PIDS+=($!); SR=$!
$M $BIN/kelp-lcmprobe --lcm-url=$U -c BIG recv kelp 30 40 > big.out 2>&1 & PIDS+=($!); BR=$!
ready short.out && ready big.out || fail "receivers not ready"
sleep 0.5
# valid traffic for about 3 s: 3000 short messages and 30 of 100 KB (2 fragments each)
$M $BIN/kelp-lcmprobe --lcm-url=$U send kelp 3000 100 1000 > shorts.out 2>&1 & SS=$!
$M $BIN/kelp-lcmprobe --lcm-url=$U -c BIG send kelp 30 100000 10 > bigs.out 2>&1 & BS=$!
sleep 0.3
ip netns exec ${P}a $BIN/kelp-lcmprobe --lcm-url='udpm://239.255.76.67:7733?ttl=1' attack 10000 > attack.out 2>&1 \
  || fail "attack tool"
grep -q "sent 10002 hostile" attack.out || fail "attack incomplete: $(cat attack.out)"
wait $SS && wait $BS || fail "valid senders failed"
wait $SR || fail "short valid traffic incomplete: $(cat short.out)"
wait $BR || fail "fragmented valid traffic incomplete: $(cat big.out)"
ok "valid traffic complete: $(grep -o 'received [0-9/]*' short.out), $(grep -o 'received [0-9/]*' big.out) of 100 KB"
$M $BIN/kelp-poke m.moos PING_IN=7 > poke.out 2>&1 || fail "poke"
sleep 0.5
for r in $R1 $R2; do kill -0 $r 2>/dev/null || fail "an app died"; kill -INT $r; done
wait $R1 || fail "relay1 did not exit cleanly"
wait $R2 || fail "relay2 did not exit cleanly"
grep -q "PING_IN -> PING_MID .*received 1 " relay1.out || fail "relay1 stopped relaying"
grep -q "PING_MID -> PING_OUT .*received 1 " relay2.out || fail "relay2 stopped relaying"
# every receiver counted the hostile datagrams (random ones with a bad magic alone are ~5000)
for f in relay1.out relay2.out; do
  n=$(grep -o 'datagrams, [0-9]* rejected' $f | tail -1 | awk '{print $2}')
  [ "${n:-0}" -ge 4000 ] || fail "$f counted ${n:-0} rejected datagrams"
  ok "$f: $(grep -o 'Transport: .*' $f)"
done
for f in short.out big.out; do
  n=$(grep -o ' bad [0-9]*' $f | tail -1 | awk '{print $2}')
  [ "${n:-0}" -ge 4000 ] || fail "$f counted ${n:-0} rejected datagrams"
done
ok "every app survived and counted the attack"
