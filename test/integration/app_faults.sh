#!/usr/bin/env bash
# The app runner under bad configuration and hostile text: non-finite or non-positive
# AppTick/CommsTick/MOOSTimeWarp, an over-long Community and a non-regular mission file are
# start-up errors with file:line; control bytes from the bus never reach the terminal raw;
# a full warning table keeps the newest distinct warnings and counts the dropped ones.
. "$(dirname "$0")/lib.sh"
cd "$T"
relay() { printf 'Community = %s\n%s\nProcessConfig = pXRelay\n{\n  %s\n  INCOMING_VAR = A\n  OUTGOING_VAR = B\n}\n' "$1" "$2" "$3" > m.moos; }
expect_refused() { # what pattern
  local rc=0
  timeout 5 "$BIN/pXRelay" m.moos > out.txt 2>&1 || rc=$?
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "$1: accepted (exit $rc)"
  grep -qE "$2" out.txt || fail "$1: no '$2' in: $(head -3 out.txt)"
  ok "$1 refused: $(grep -E "$2" out.txt | head -1)"
}
relay faults "" "AppTick = nan";          expect_refused "AppTick = nan" "m.moos:5: AppTick must be"
relay faults "" "AppTick = 0";            expect_refused "AppTick = 0" "m.moos:5: AppTick must be"
relay faults "" "CommsTick = -1";         expect_refused "CommsTick = -1" "m.moos:5: CommsTick must be"
relay faults "MOOSTimeWarp = inf" "AppTick = 4"; expect_refused "MOOSTimeWarp = inf" "m.moos:2: MOOSTimeWarp must be"
relay "$(printf 'c%.0s' $(seq 1 70))" "" "AppTick = 4"; expect_refused "a 70-character Community" "m.moos:1: Community must be"
mkfifo fifo.moos
rc=0; timeout 5 "$BIN/pXRelay" fifo.moos > out.txt 2>&1 || rc=$?
[ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "a FIFO as the mission file: exit $rc (124 = hung)"
grep -q "fifo.moos: not a regular file" out.txt || fail "FIFO: $(cat out.txt)"
ok "a FIFO mission file refused at once"

# control bytes in a refused POLLER_COMMAND, and more distinct warnings than the table holds
cat > p.moos <<'MOOS'
Community = faults
ProcessConfig = pAcommsPoller
{
  AppTick = 20
  modem_id = 1
  poll = src=2,dest=1
}
MOOS
bg "$BIN/pAcommsPoller" p.moos > poller.out 2>&1
sleep 1
"$BIN/kelp-poke" p.moos "$(printf 'POLLER_COMMAND:=frob\033[2J\033]0;owned\007')" > /dev/null
for i in $(seq 1 40); do "$BIN/kelp-poke" p.moos "POLLER_COMMAND:=bogus$i" > /dev/null; done
sleep 1
kill -INT ${PIDS[0]}; wait ${PIDS[0]} 2>/dev/null || true
grep -q $'\033' poller.out && fail "a raw escape byte reached the terminal report"
grep -q "frob.x1b\[2J" poller.out || fail "the escaped command is not shown: $(grep -m2 frob poller.out)"
grep -q "bogus40" poller.out || fail "the newest warning is missing"
grep -qE "\([0-9]+ older distinct warnings dropped\)" poller.out || fail "dropped warnings not counted"
ok "control bytes shown as \\xNN; newest warnings kept, $(grep -oE '[0-9]+ older distinct warnings dropped' poller.out | tail -1)"

# <NAME>_STATUS carries MOOS's keys (AppErrorFlag, Uptime, cpuload, memory_kb, memory_max_kb,
# MOOSName, Publishing, Subscribing) before kelp's own
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f status.lcmlog
sleep 0.5
bg "$BIN/pAcommsPoller" p.moos > poller2.out 2>&1
sleep 3
kill -INT ${PIDS[2]}; wait ${PIDS[2]} 2>/dev/null || true
kill -INT ${PIDS[1]}; wait ${PIDS[1]} 2>/dev/null || true
"$BIN/kelp-logcheck" --print status.lcmlog > status.txt || fail "status log undecodable"
line=$(grep ' PACOMMSPOLLER_STATUS ' status.txt | tail -1)
[ -n "$line" ] || fail "no PACOMMSPOLLER_STATUS: $(head -5 status.txt)"
echo "$line" | grep -qE 'PACOMMSPOLLER_STATUS AppErrorFlag=(true|false),Uptime=[0-9.]+,cpuload=[0-9.e+-]+,memory_kb=[1-9][0-9.e+]*,memory_max_kb=[1-9][0-9.e+]*,MOOSName=pAcommsPoller,Publishing="[^"]*PACOMMSPOLLER_STATUS[^"]*",Subscribing="[^"]*POLLER_COMMAND,[^"]*"$' ||
  fail "status lacks MOOS's keys: $line"
ok "status with MOOS keys: ${line:0:160}..."
