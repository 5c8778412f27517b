# Two missions with different communities on one host do not hear each other:
#  1. each community's URL comes from its ServerPort (one port per community), so a value
#     poked into one mission never reaches the other;
#  2. even on one shared LCM_URL, writes of the other community are dropped and counted.
. "$(dirname "$0")/lib.sh"
unset KELP_LCM_URL   # the missions' own URLs are under test
cd $T
mission() { # NAME COMMUNITY URL-LINE
  cat > $1.moos <<EOF2
Community = $2
$3
ProcessConfig = relay
{
  AppTick = 20
  INCOMING_VAR = PING_IN
  OUTGOING_VAR = PING_OUT
}
EOF2
}
relay_count() { grep -o 'PING_IN -> PING_OUT .*received [0-9]*' $1 | tail -1 | awk '{print $NF}'; }
run_pair() { # label
  $BIN/pXRelay a.moos relay > a.out 2>&1 & local ra=$!; PIDS+=($ra)
  $BIN/pXRelay b.moos relay > b.out 2>&1 & local rb=$!; PIDS+=($rb)
  sleep 0.8
  $BIN/kelp-poke a.moos PING_IN=1 > pa.out 2>&1 || fail "poke a"
  $BIN/kelp-poke a.moos PING_IN=2 > pa.out 2>&1 || fail "poke a"
  $BIN/kelp-poke b.moos PING_IN=3 > pb.out 2>&1 || fail "poke b"
  sleep 0.5
  kill -INT $ra $rb; wait $ra || fail "a exit"; wait $rb || fail "b exit"
  [ "$(relay_count a.out)" = 2 ] || { tail -20 a.out; fail "$1: mission a relayed $(relay_count a.out), want its own 2"; }
  [ "$(relay_count b.out)" = 1 ] || { tail -20 b.out; fail "$1: mission b relayed $(relay_count b.out), want its own 1"; }
}
# 1. ServerPort -> port
mission a alpha "ServerPort = 9101"
mission b bravo "ServerPort = 9102"
run_pair "ServerPort"
grep -q "dropped 0 of another community" b.out || fail "separate ports should not even see the other community"
ok "ServerPort 9101 / 9102: each mission heard only itself"
# 2. one shared URL: the community filter drops the other's writes
mission a alpha "LCM_URL = udpm://239.255.76.67:$TEST_PORT?ttl=0"
mission b bravo "LCM_URL = udpm://239.255.76.67:$TEST_PORT?ttl=0"
run_pair "shared URL"
n=$(grep -o 'dropped [0-9]* of another community' b.out | tail -1 | awk '{print $2}')
[ "${n:-0}" -ge 2 ] || { tail -20 b.out; fail "b did not count alpha's writes (${n:-0})"; }
ok "shared URL: bravo dropped and counted $n writes of alpha"
# a bad ServerPort is a start-up error with file:line
mission c charlie "ServerPort = 70000"
if $BIN/pXRelay c.moos relay > c.out 2>&1; then fail "ServerPort 70000 accepted"; fi
grep -q "c.moos:2:" c.out || { cat c.out; fail "no file:line for a bad ServerPort"; }
ok "ServerPort 70000 rejected with file:line"
