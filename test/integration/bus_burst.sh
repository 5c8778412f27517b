# A burst of 10,000 messages between two processes arrives complete (kelp bus and raw LCM).
. "$(dirname "$0")/lib.sh"
$BIN/kelp-busperf sub 10000 30 > $T/sub.out 2>&1 & SP=$!; PIDS+=($SP)
wait_for $T/sub.out ready 5 || fail "subscriber not ready"
$BIN/kelp-busperf pub 10000 32
wait $SP || { cat $T/sub.out; fail "burst incomplete"; }
cat $T/sub.out
grep -q "received 10000/10000" $T/sub.out || fail "expected 10000/10000"
grep -q "bad datagrams 0" $T/sub.out || fail "bad datagrams in a clean burst"
ok "10000/10000"
