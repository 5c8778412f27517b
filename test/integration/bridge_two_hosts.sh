# Two hosts (network namespaces joined by a bridge), one community each, joined by
# kelp-bridge over UDP: static UDPSHARE with renaming, run-time PMB_REGISTER, no loops,
# no duplicates, datagrams failing the shared-key HMAC are dropped, a captured datagram
# replayed 1000 times is delivered once, a name off the receiver's ALLOW list is not
# published, and a 60 KB datagram with a valid HMAC is read whole and counted as oversize.
set -euo pipefail
[ "$(id -u)" -eq 0 ] || { echo "SKIP-needs-root"; exit 1; }
KELP_ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}
BIN=${BUILD:-$KELP_ROOT/build}/bin
P=kb$$
T=$(mktemp -d /tmp/kelp-bridge.XXXXXX)
PIDS=()
cleanup() {
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  for ns in ${P}h1 ${P}h2 ${P}br; do ip netns del $ns 2>/dev/null || true; done
  [ -n "${KEEP_T:-}" ] || rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; for f in $T/*.log $T/*.out; do echo "--- $f"; tail -25 $f; done 2>/dev/null; exit 1; }
ip netns add ${P}br
ip -n ${P}br link set lo up
ip -n ${P}br link add br0 type bridge
ip -n ${P}br link set br0 type bridge mcast_snooping 0
ip -n ${P}br link set br0 up
for i in 1 2; do
  ns=${P}h$i
  ip netns add $ns
  ip -n $ns link set lo up
  ip -n $ns link add eth0 type veth peer name ${P}v$i
  ip -n $ns link set ${P}v$i netns ${P}br
  ip -n ${P}br link set ${P}v$i master br0
  ip -n ${P}br link set ${P}v$i up
  ip -n $ns addr add 198.51.100.$i/24 dev eth0
  ip -n $ns link set eth0 up
  ip -n $ns route add 224.0.0.0/4 dev eth0
done
U='udpm://239.255.76.67:7667?ttl=0'   # each community stays on its host
cat > $T/shore.moos <<M
Community = shoreside
LCM_URL = $U
ProcessConfig = pMOOSBridge
{
  UDPListen = 9300
  KEY = sea-secret
  ALLOW = NAV_X_ALPHA, NAV_X_TAP, STATE
  ALLOW = NAV_Y
  // a deliberate loop back to the vehicle: must not echo forever
  UDPSHARE = [STATE] -> alpha @ 198.51.100.2:9301
}
ProcessConfig = scope
{
  VAR = NAV_X_ALPHA, STATE, NAV_Y, EVIL
  DISPLAY_SOURCE = true
  DISPLAY_TIME = true
  DISPLAY_COMMUNITY = true
}
M
cat > $T/alpha.moos <<M
Community = alpha
LCM_URL = $U
ProcessConfig = pMOOSBridge
{
  UDPListen = 9301
  KEY = sea-secret
  UDPSHARE = [NAV_X, STATE] -> shoreside @ 198.51.100.1:9300 [NAV_X_ALPHA, STATE]
  // a tap on the shore host captures one signed datagram for the replay attack
  UDPSHARE = [NAV_X] -> shoreside @ 198.51.100.1:9399 [NAV_X_TAP]
  ALLOW = DEPLOY, STATE
}
ProcessConfig = rogue
{
  UDPListen = 9302
  KEY = wrong-key
  UDPSHARE = [NAV_Y] -> shoreside @ 198.51.100.1:9300
}
ProcessConfig = scope
{
  VAR = DEPLOY, STATE
  DISPLAY_SOURCE = true
  DISPLAY_TIME = true
  DISPLAY_COMMUNITY = true
}
M
cat > $T/tap.py <<'PY'
# capture one datagram; replay it N times; then send a 60 KB re-signed copy
import hashlib, hmac, socket, struct, sys
cap = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
cap.bind(("0.0.0.0", 9399))
cap.settimeout(10)
d, _ = cap.recvfrom(65536)
open("captured.bin", "wb").write(d)
out = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
out.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 22)
import time
for i in range(int(sys.argv[1])):
    out.sendto(d, ("127.0.0.1", 9300))
    if i % 100 == 99: time.sleep(0.01)
# rebuild the var with a 60,000-byte string, next sequence number, valid HMAC
assert d[:4] == b"KBR2" and d[4] == 1
body = d[21:-32]
o = 16                                            # fingerprint, time
for _ in range(4):                                # name, source, source_aux, community
    (n,) = struct.unpack(">i", body[o:o + 4]); o += 4 + n
o += 1 + 8                                        # kind, dval
big = b"x" * 60000 + b"\0"
nb = body[:o] + struct.pack(">i", len(big)) + big + body[o + 4 + struct.unpack(">i", body[o:o + 4])[0]:]
nb = nb[:o - 9] + b"\x01" + nb[o - 8:]           # kind = STRING
seq = struct.unpack(">Q", d[13:21])[0] + 1000
head = d[:13] + struct.pack(">Q", seq)
msg = head + nb
msg += hmac.new(b"sea-secret", msg, hashlib.sha256).digest()
out.sendto(msg, ("127.0.0.1", 9300))
print("sent", len(msg))
PY
cd $T
ip netns exec ${P}h1 python3 tap.py 1000 > tap.out 2>&1 & TAP=$!
ip netns exec ${P}h1 lcm-logger --lcm-url="$U" -f shore.lcmlog > logger1.out 2>&1 & PIDS+=($!)
ip netns exec ${P}h2 lcm-logger --lcm-url="$U" -f alpha.lcmlog > logger2.out 2>&1 & PIDS+=($!)
ip netns exec ${P}h1 $BIN/kelp-bridge shore.moos > shore_bridge.log 2>&1 & PIDS+=($!)
ip netns exec ${P}h2 $BIN/kelp-bridge alpha.moos > alpha_bridge.log 2>&1 & PIDS+=($!)
ip netns exec ${P}h2 $BIN/kelp-bridge alpha.moos rogue > rogue_bridge.log 2>&1 & PIDS+=($!)
# wait until the three bridges listen (a bridge subscribes before it binds)
for i in $(seq 100); do
  n=$( (ip netns exec ${P}h1 ss -Huln; ip netns exec ${P}h2 ss -Huln) | grep -cE ':(9300|9301|9302|9399) ' || true)
  [ "$n" -ge 4 ] && break; sleep 0.1
done
[ "$n" -ge 4 ] || fail "bridges did not start"
sleep 0.3
# static share with renaming, host 2 -> host 1
ip netns exec ${P}h2 $BIN/kelp-poke alpha.moos NAV_X=12.5 NAV_Y=3 > poke1.out
wait $TAP || fail "tap/replay failed"
# a PMB_REGISTER poked on the vehicle asks for a name the shore does not allow
ip netns exec ${P}h2 $BIN/kelp-poke alpha.moos "PMB_REGISTER:=src_var=NAV_X,dest_community=shoreside,dest_host=198.51.100.1,dest_port=9300,dest_alias=EVIL" > poke5.out
sleep 0.3
ip netns exec ${P}h2 $BIN/kelp-poke alpha.moos NAV_X=13.5 > poke6.out
# run-time bridge from the shore to the vehicle (what uFldShoreBroker asks for)
ip netns exec ${P}h1 $BIN/kelp-poke shore.moos "PMB_REGISTER:=src_var=DEPLOY_ALL,dest_community=alpha,dest_host=198.51.100.2,dest_port=9301,dest_alias=DEPLOY" > poke2.out
sleep 0.5
ip netns exec ${P}h1 $BIN/kelp-poke shore.moos DEPLOY_ALL:=true > poke3.out
# a shared variable bridged both ways: one write on alpha must arrive once on shore and not come back
ip netns exec ${P}h2 $BIN/kelp-poke alpha.moos STATE:=go > poke4.out
sleep 1
timeout 2 ip netns exec ${P}h1 $BIN/kelp-scope shore.moos scope > shore_scope.out 2>&1 || true
timeout 2 ip netns exec ${P}h2 $BIN/kelp-scope alpha.moos scope > alpha_scope.out 2>&1 || true
for p in "${PIDS[@]}"; do kill -INT $p 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
grep -E '^NAV_X_ALPHA +kelp-poke .* alpha +13.5$' shore_scope.out | tail -1 | grep -q . || fail "NAV_X did not reach the shore as NAV_X_ALPHA"
grep -E '^DEPLOY +kelp-poke .* shoreside +"true"$' alpha_scope.out | tail -1 | grep -q . || fail "PMB_REGISTER bridge DEPLOY_ALL -> DEPLOY failed"
grep -E '^NAV_Y +n/a +n/a +n/a$' shore_scope.out | tail -1 | grep -q . || fail "NAV_Y from the wrong key was accepted"
grep -qE "auth failures [1-9]" shore_bridge.log || fail "shore did not count the auth failure"
grep -qE "replays 999 " shore_bridge.log || fail "shore did not refuse the 999 replays: $(grep -E 'replays' shore_bridge.log | tail -1)"
grep -qE "not allowed [1-9]" shore_bridge.log || fail "shore did not refuse EVIL"
grep -qE "received [0-9]+ .* oversize 1 " shore_bridge.log || fail "60 KB datagram not counted as oversize"
grep -qE "sent 60[0-9]{3}" tap.out || fail "tap did not send the big datagram: $(cat tap.out)"
grep -E '^EVIL +n/a +n/a +n/a$' shore_scope.out | tail -1 | grep -q . || fail "a name off the ALLOW list reached the shore"
$BIN/kelp-logcheck shore.lcmlog --print > shore_events.txt || fail "shore log undecodable"
$BIN/kelp-logcheck alpha.lcmlog --print > alpha_events.txt || fail "alpha log undecodable"
n_state_alpha=$(awk '$3=="STATE"' alpha_events.txt | wc -l)
n_state_shore=$(awk '$3=="STATE"' shore_events.txt | wc -l)
n_navx=$(awk '$3=="NAV_X_ALPHA"' shore_events.txt | wc -l)
n_tap=$(awk '$3=="NAV_X_TAP"' shore_events.txt | wc -l)
n_evil=$(awk '$3=="EVIL"' shore_events.txt | wc -l)
[ "$n_tap" -eq 1 ] || fail "captured datagram delivered $n_tap times (replays accepted?)"
[ "$n_evil" -eq 0 ] || fail "EVIL published $n_evil times"
[ "$n_state_alpha" -eq 1 ] || fail "STATE written $n_state_alpha times on alpha (loop?)"
[ "$n_state_shore" -eq 1 ] || fail "STATE arrived $n_state_shore times on shore (duplicate?)"
[ "$n_navx" -eq 2 ] || fail "NAV_X_ALPHA arrived $n_navx times (2 writes)"
# negative control: ttl=0 multicast does not cross between the hosts
grep -q "NAV_X " shore_events.txt && fail "alpha's multicast leaked to the shore host"
echo "ok: renamed share, PMB_REGISTER, no loop (STATE 1/1), no duplicate, wrong key dropped, replay 1 of 1000, EVIL refused, 60 KB oversize"
