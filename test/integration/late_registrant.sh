# A value poked before an app starts is delivered to it on registration (as the MOOSDB
# does), held by the launcher's retainer after the poker has exited; a value the app never
# saw a writer for stays n/a.
. "$(dirname "$0")/lib.sh"
cd $T
cat > m.moos <<'M'
Community = late
ProcessConfig = ANTLER
{
  Run = uXMS ~ scope_all
}
ProcessConfig = scope_all
{
  VAR = DEPLOY
}
ProcessConfig = relay
{
  AppTick = 20
  INCOMING_VAR = DEPLOY
  OUTGOING_VAR = DEPLOYED_COUNT
}
ProcessConfig = scope2
{
  AppTick = 10
  DISPLAY_SOURCE = true
  DISPLAY_TIME = true
  DISPLAY_COMMUNITY = true
  VAR = DEPLOY, NEVER_WRITTEN, DEPLOYED_COUNT
}
M
$BIN/kelp-launch --run-seconds 8 --log-dir logs m.moos > launch.out 2>&1 & LP=$!; PIDS+=($LP)
sleep 1
$BIN/kelp-poke m.moos DEPLOY=true > poke.out
sleep 0.5
# the poker has exited; now the late apps start
timeout 3 $BIN/pXRelay m.moos relay > relay.out 2>&1 || true
timeout 2 $BIN/kelp-scope m.moos scope2 > scope2.out 2>&1 || true
kill $LP; wait $LP || true
grep -q "DEPLOY -> DEPLOYED_COUNT   received 1 " relay.out || { tail -12 relay.out; fail "relay did not get DEPLOY on registration"; }
grep -E '^DEPLOY +kelp-poke .* "true"$' scope2.out | tail -1 | grep -q . || { tail -12 scope2.out; fail "scope2 did not show DEPLOY from kelp-poke"; }
grep -E '^NEVER_WRITTEN +n/a +n/a +n/a$' scope2.out | tail -1 | grep -q . || fail "NEVER_WRITTEN should be n/a"
grep -E '^DEPLOYED_COUNT +relay .* 1$' scope2.out | tail -1 | grep -q . || { tail -12 scope2.out; fail "scope2 did not get the relay's retained DEPLOYED_COUNT"; }
ok "late registrants got DEPLOY=true (from kelp-poke, retained by the launcher) and DEPLOYED_COUNT=1"
