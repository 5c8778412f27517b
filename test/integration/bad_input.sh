# Malformed datagrams are rejected, counted in the status report, and the app goes on.
# A bad mission file stops an app with a non-zero exit and file:line; an unknown parameter
# is a warning in the status report.
. "$(dirname "$0")/lib.sh"
cd $T
cat > m.moos <<'M'
Community = bad
ProcessConfig = relay
{
  AppTick = 20
  INCOMING_VAR = PING_IN
  OUTGOING_VAR = PING_OUT
  NO_SUCH_PARAM = 3
}
M
$BIN/pXRelay m.moos relay > relay.out 2>&1 & RP=$!; PIDS+=($RP)
sleep 0.7
$BIN/kelp-busperf junk PING_IN 200
$BIN/kelp-busperf junk KELP_SYNC_REQ 50
$BIN/kelp-poke m.moos PING_IN=1 > /dev/null
sleep 0.5
kill -INT $RP; wait $RP || fail "relay did not exit cleanly after SIGINT"
tail -14 relay.out
grep -q "PING_IN -> PING_OUT   received 1 " relay.out || fail "relay stopped relaying after junk"
grep -qE "\[bad\] 250 malformed datagrams rejected" relay.out || fail "bad datagrams not counted"
grep -q "unknown parameter NO_SUCH_PARAM" relay.out || fail "unknown parameter not warned"
grep -q "line 7: unknown parameter" relay.out || fail "warning lacks the line"
# a broken mission file: non-zero exit with file:line
printf 'Community = x\nProcessConfig = relay\n{\n  INCOMING_VAR = A\n' > broken.moos
if $BIN/pXRelay broken.moos relay > b.out 2>&1; then fail "broken mission accepted"; fi
grep -q "broken.moos:2: block not closed" b.out || { cat b.out; fail "no file:line"; }
printf 'Community = x\nx: 3\n' > broken2.moos
if $BIN/kelp-launch broken2.moos > b2.out 2>&1; then fail "broken mission accepted by the launcher"; fi
grep -q "broken2.moos:2:" b2.out || { cat b2.out; fail "no file:line from launcher"; }
# a missing required parameter is a configuration error
printf 'Community = x\nProcessConfig = relay\n{\n  INCOMING_VAR = A\n}\n' > miss.moos
if $BIN/pXRelay miss.moos relay > c.out 2>&1; then fail "missing OUTGOING_VAR accepted"; fi
grep -q "needs OUTGOING_VAR" c.out || fail "no reason for the missing parameter"
ok "junk counted, relay alive, bad missions rejected with file:line"
