#!/usr/bin/env bash
# kelp-launch under faults: a signal in the middle of start-up stops it promptly with every
# started app reaped and none left running; --run-seconds holds during MSBetweenLaunches.
. "$(dirname "$0")/lib.sh"
cd "$T"
cat > m.moos <<MOOS
Community = faults
ProcessConfig = ANTLER
{
  MSBetweenLaunches = 2500
  Run = pXRelay ~ relay_a
  Run = pXRelay ~ relay_b
  Run = pXRelay ~ relay_c
}
ProcessConfig = relay_a
{
  INCOMING_VAR = A
  OUTGOING_VAR = B
}
ProcessConfig = relay_b
{
  INCOMING_VAR = B
  OUTGOING_VAR = C
}
ProcessConfig = relay_c
{
  INCOMING_VAR = C
  OUTGOING_VAR = D
}
MOOS
left() { pgrep -f "pXRelay m.moos relay_" | wc -l; }

# 1. SIGTERM while the second app waits its turn: stops within the grace period, nothing left
"$BIN/kelp-launch" --log-dir logs m.moos > l1.txt 2>&1 &
L=$!
wait_for l1.txt "started pXRelay +as relay_a" 5 || fail "first app not started"
sleep 0.5
t0=$(date +%s.%N)
kill -TERM $L
for i in $(seq 1 60); do kill -0 $L 2>/dev/null || break; sleep 0.1; done
kill -0 $L 2>/dev/null && { kill -KILL $L; fail "kelp-launch still running 6 s after SIGTERM during start-up"; }
wait $L || true
dt=$(awk -v a="$(date +%s.%N)" -v b="$t0" 'BEGIN { printf "%.2f", a - b }')
grep -q "relay_b" l1.txt && fail "an app was started after the stop request"
[ "$(left)" = 0 ] || fail "$(left) relays left running"
grep -q "start-up was interrupted" l1.txt || fail "summary does not say the start-up was interrupted"
ok "SIGTERM during start-up: stopped in ${dt}s, 1 app started and reaped, none left"

# 2. --run-seconds holds during MSBetweenLaunches
t0=$(date +%s.%N)
timeout 10 "$BIN/kelp-launch" --run-seconds 1 --log-dir logs m.moos > l2.txt 2>&1 || true
dt=$(awk -v a="$(date +%s.%N)" -v b="$t0" 'BEGIN { printf "%.2f", a - b }')
awk -v d="$dt" 'BEGIN { exit !(d < 4.5) }' || fail "--run-seconds 1 took ${dt}s (MSBetweenLaunches 2.5 s x 3)"
[ "$(left)" = 0 ] || fail "$(left) relays left running after --run-seconds"
ok "--run-seconds 1 with MSBetweenLaunches 2500: ended in ${dt}s, none left"

# 3. a bad ANTLER block is a start-up error with file:line
printf 'ProcessConfig = ANTLER\n{\n  MSBetweenLaunches = -5\n  Run = pXRelay\n}\n' > bad.moos
"$BIN/kelp-launch" bad.moos > l3.txt 2>&1 && fail "bad MSBetweenLaunches accepted"
grep -q "bad.moos:3: MSBetweenLaunches" l3.txt || fail "no file:line for MSBetweenLaunches: $(cat l3.txt)"
ok "bad MSBetweenLaunches refused with file:line"
