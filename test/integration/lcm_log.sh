# lcm-logger records a demo run; every channel in the log decodes with kelp's types
# (kelp's decoder and lcm-gen's, field for field).
. "$(dirname "$0")/lib.sh"
cd $T
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cp $KELP_ROOT/missions/xrelay/xrelay.moos .
lcm-logger --lcm-url="$KELP_LCM_URL" -f run.lcmlog > logger.out 2>&1 & LG=$!; PIDS+=($LG)
sleep 0.5
$BIN/kelp-launch --run-seconds 3 --log-dir logs xrelay.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 0.8
$BIN/kelp-poke xrelay.moos APPLES=1 > /dev/null
wait $LP || fail "launcher failed"
sleep 0.3
kill -INT $LG; wait $LG || true
$BIN/kelp-logcheck run.lcmlog | tee check.out || fail "log has undecodable events"
grep -qE "^  APPLES +var_t +[0-9]+ events" check.out || fail "APPLES not in log"
grep -qE "^  KELP_SYNC_REQ +sync_req_t" check.out || fail "sync requests not in log"
n=$(awk '/kelp-logcheck:/{print $2}' check.out); [ "$n" -gt 100 ] || fail "too few events ($n)"
ok "$n events decoded"
