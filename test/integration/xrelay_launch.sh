# The pXRelay mission of seed 004 through kelp-launch, seeded by kelp-poke: the relay
# counters advance, uXMS shows them, and the launcher exits 0 within its bound.
. "$(dirname "$0")/lib.sh"
cd $T
cp $KELP_ROOT/missions/xrelay/xrelay.moos .
start=$(date +%s)
$BIN/kelp-launch --run-seconds 5 --log-dir logs --report xrelay.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 1
$BIN/kelp-poke xrelay.moos APPLES=1 > poke.out
grep -qE "APPLES +kelp-poke .* 1\.00000" poke.out || { cat poke.out; fail "poke not echoed"; }
wait $LP || { cat launch.out; fail "launcher exit non-zero"; }
el=$(( $(date +%s) - start ))
[ $el -le 12 ] || fail "launcher took ${el}s for a 5 s run"
cat launch.out
a=$(awk '$1=="APPLES"{print $2}' launch.out); p=$(awk '$1=="PEARS"{print $2}' launch.out)
[ "${a:-0}" -gt 20 ] && [ "${p:-0}" -gt 20 ] || fail "relay counters did not advance (APPLES=$a PEARS=$p)"
grep -q "APPLES_ITER_HZ" launch.out || fail "no ITER_HZ"
grep -q "APPLES_POST_HZ" launch.out || fail "no POST_HZ"
# uXMS (kelp-scope) saw the relay with source and community columns
grep -E "^APPLES +pXRelay_APPLES +[0-9.]+ +xrelay +[0-9]+$" logs/uXMS.log | tail -1 | grep -q . || { tail -20 logs/uXMS.log; fail "scope did not show APPLES"; }
ok "APPLES=$a PEARS=$p in ${el}s"
