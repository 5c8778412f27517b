# pAcommsPoller: the poll list from the mission (MOOS "poll =" lines and a Goby "slot { }" block)
# goes out as a MACUpdate REPLACE on ACOMMS_MAC_CYCLE_UPDATE; POLLER_COMMAND changes it at run
# time (add, remove, pause, resume); bad commands are refused and change nothing.
. "$(dirname "$0")/lib.sh"
cd $T
cat > topside.moos <<'EOF'
Community = topside
ProcessConfig = pAcommsPoller
{
  AppTick = 10
  modem_id = 1
  slot_seconds = 12
  max_range = 3000
  poll = src=2,dest=1,rate=0,type=data
  poll = src=1,dest=2,rate=0,slot_seconds=15
  slot { src: 3 dest: -1 rate: 0 type: SLOT_PING slot_seconds: 5 }
  legacy_update = true
}
EOF
bg $BIN/kelp-record --lcm-url="$KELP_LCM_URL" -f log.lcm -q
sleep 0.3
bg $BIN/pAcommsPoller topside.moos > poller.out 2>&1
sleep 1.5
$BIN/kelp-poke topside.moos 'POLLER_COMMAND:=add src=3,dest=1,rate=2,slot_seconds=8' > /dev/null
sleep 0.5
$BIN/kelp-poke topside.moos 'POLLER_COMMAND:=remove src=1,dest=2,rate=0,slot_seconds=15' > /dev/null
sleep 0.5
$BIN/kelp-poke topside.moos 'POLLER_COMMAND:=add src=40,dest=1' > /dev/null
sleep 0.5
$BIN/kelp-poke topside.moos 'POLLER_COMMAND:=pause' > /dev/null
sleep 0.5
$BIN/kelp-poke topside.moos 'POLLER_COMMAND:=resume' > /dev/null
# until the logger has written the resumed list (a loaded host may take a while), at most 15 s
for _ in $(seq 75); do
  [ "$($BIN/kelp-logcheck log.lcm --print 2>/dev/null | grep -c ' POLLER_STATUS state=active,slots=3,cycle_seconds=25,updates=5')" -ge 1 ] && break
  sleep 0.2
done
sleep 0.3
kill ${PIDS[1]} ${PIDS[0]}
wait ${PIDS[1]} 2>/dev/null || true
sleep 0.3
$BIN/kelp-logcheck log.lcm --print > log.txt || { cat log.txt; fail "kelp-logcheck"; }
grep -E ' ACOMMS_MAC_CYCLE_UPDATE ' log.txt | sed 's/^.* ACOMMS_MAC_CYCLE_UPDATE //' > updates.txt
S2='slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 12 }'
S1='slot { src: 1 dest: 2 rate: 0 type: SLOT_DATA slot_seconds: 15 }'
S3='slot { src: 3 dest: -1 rate: 0 type: SLOT_PING slot_seconds: 5 }'
S4='slot { src: 3 dest: 1 rate: 2 type: SLOT_DATA slot_seconds: 8 }'
cat > want.txt <<EOF
dest: 1 update_type: REPLACE $S2 $S1 $S3
dest: 1 update_type: REPLACE $S2 $S1 $S3 $S4
dest: 1 update_type: REPLACE $S2 $S3 $S4
dest: 1 update_type: REPLACE
dest: 1 update_type: REPLACE $S2 $S3 $S4
EOF
diff want.txt updates.txt || { cat log.txt; fail "ACOMMS_MAC_CYCLE_UPDATE sequence differs"; }
# the legacy alias carries the same text, POLLER_STATUS the state
[ "$(grep -c ' ACOMMS_POLLER_UPDATE ' log.txt)" = 5 ] || fail "legacy ACOMMS_POLLER_UPDATE not written 5 times"
grep -q ' POLLER_STATUS state=paused,slots=3,cycle_seconds=25,updates=4' log.txt || fail "no paused POLLER_STATUS"
grep -q ' POLLER_CYCLE src=2,dest=1,rate=0,type=data,slot_seconds=12;src=3,dest=-1,rate=0,type=ping,slot_seconds=5;src=3,dest=1,rate=2,type=data,slot_seconds=8' log.txt ||
  fail "POLLER_CYCLE"
# warnings: a rate-2 slot at 3000 m needs 1 + 3.072 + 0.5 + 2*0.25 + 3*2 = 11.07 s, so 8 s is short;
# the 12 s rate-0 slots (11.2 s needed) are not; the bad src=40 is refused
grep -q "slot src=3 dest=1 rate 2: 8 s is short for 3000 m (a full packet with its ack needs 11.1 s)" poller.out ||
  { cat poller.out; fail "no short-slot warning"; }
[ "$(grep -c "is short for" poller.out | head -1)" -ge 1 ] && ! grep -q "rate 0: 12 s is short" poller.out || fail "wrong short-slot warnings"
grep -q "POLLER_COMMAND 'add src=40,dest=1' refused (src)" poller.out || { cat poller.out; fail "bad command not reported"; }
grep -q "5 commands (1 bad)" poller.out || { tail -20 poller.out; fail "command counts"; }
# a configuration error is reported with file:line and a non-zero exit
cat > bad.moos <<'EOF'
ProcessConfig = pAcommsPoller
{
  modem_id = 1
  poll = src=2,rate=9
}
EOF
if $BIN/pAcommsPoller bad.moos > bad.out 2>&1; then fail "bad config accepted"; fi
grep -q "bad.moos:4" bad.out && grep -q "rate" bad.out || { cat bad.out; fail "config error not located"; }
ok "pAcommsPoller: $(wc -l < updates.txt) updates"
