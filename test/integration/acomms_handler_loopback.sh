#!/usr/bin/env bash
# pAcommsHandler with DRIVER_NONE, end to end in one process (missions/acomms/loopback.moos):
#  - GoToCommand triggered by OUTGOING_COMMAND (to modem 3): queued, handed out at our 2 s slot,
#    acknowledged by the ideal channel -> ACOMMS_ACK; LOOPBACK decodes it at once ->
#    INCOMING_COMMAND and SPECIAL_INSTRUCTIONS as <all/> and <format> give them
#  - SIMPLE_STATUS (time trigger 5 s, blackout 10 s, broadcast) comes back through the channel
#    -> STATUS_REPORT_IN and NODE_REPORT (lookup file: mm1 / topside)
#  - initializers, MODEM_ID, ACOMMS_MAC_CYCLE_UPDATE (good and bad), LCM structures
. "$(dirname "$0")/lib.sh"
cd "$T"
cp "$KELP_ROOT"/missions/acomms/{loopback.moos,example1.xml,simple_status.xml,modemidlookup.txt} .
"$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f "$T/bus.lcmlog" >/dev/null 2>&1 & PIDS+=($!)
# the handler's start-up writes (MODEM_ID, initializers) must not race the logger's start
sleep 1
"$BIN/pAcommsHandler" loopback.moos > h.out 2>&1 & H=$!; PIDS+=($H)
sleep 1.5
"$BIN/kelp-poke" loopback.moos "SPECIAL_INSTRUCTIONS:=make_toast" > /dev/null
sleep 0.3
"$BIN/kelp-poke" loopback.moos "OUTGOING_COMMAND:=Destination=3,CommandType=GoTo,goto_x=351,goto_y=294,lights_on=true,goto_speed=2.3" \
  "OUTGOING_COMMAND:=Destination=3,CommandType=Loiter,goto_x=1,goto_y=2" > /dev/null
"$BIN/kelp-poke" loopback.moos "ACOMMS_MAC_CYCLE_UPDATE:=dest: 1 update_type: ADD slot { src: 1 dest: 3 rate: 0 type: SLOT_DATA slot_seconds: 2 }" \
  "ACOMMS_MAC_CYCLE_UPDATE:=dest: 1 update_type: EXPLODE" > /dev/null
sleep 14.5
kill $H; wait $H 2>/dev/null || true
sleep 0.3
"$BIN/kelp-logcheck" bus.lcmlog --print > bus.txt 2> logcheck.err || true
val() { grep -E "^[0-9.]+ +pAcommsHandler +$1 " bus.txt | head -1 | sed -E "s/^[0-9.]+ +pAcommsHandler +$1 +//"; }
ic=$(val INCOMING_COMMAND)
[ "$ic" = 'Destination=3,type=goto,goto_x=351,goto_y=294,lights_on=true,new_instructions=make_toast,goto_speed=2.29' ] ||
  { grep pAcommsHandler bus.txt | head -30; fail "INCOMING_COMMAND: $ic"; }
[ "$(grep -cE 'pAcommsHandler +INCOMING_COMMAND ' bus.txt)" = 1 ] || fail "Loiter (not GoTo) must not trigger a GoToCommand"
grep -qE 'pAcommsHandler +SPECIAL_INSTRUCTIONS +special_instructions=make_toast,lights_on=true$' bus.txt || fail "SPECIAL_INSTRUCTIONS format"
grep -qE 'pAcommsHandler +ACOMMS_ACK +base \{ src: 3 dest: 1 time: "[^"]+" \} frame: 0 orig_msg \{ base \{ src: 1 dest: 3 ' bus.txt || { grep ACOMMS_ACK bus.txt; fail "ACOMMS_ACK"; }
# Goby 1.1 strips trailing zero bytes of the received (encrypted) message, so when the
# ciphertext ends in 0x00 the last field decodes wrong (about 1 in 256, goby-wire.md 6): kelp
# does the same. A status whose received data ends in \000 may then carry another Depth (in
# STATUS_REPORT_IN and in the NODE_REPORT made from the same message).
depth='111\.0'
if ! grep -qE 'pAcommsHandler +STATUS_REPORT_IN +Timestamp=[0-9]+,Node=1,MessageType=LAMSS_STATUS,nav_x=123,nav_y=321,Speed=1.2,Heading=45.00,Depth=111.0$' bus.txt; then
  grep -qE 'pAcommsHandler +STATUS_REPORT_IN +Timestamp=[0-9]+,Node=1,MessageType=LAMSS_STATUS,nav_x=123,nav_y=321,Speed=1.2,Heading=45.00,Depth=[0-9.]+$' bus.txt &&
    grep -m1 -E 'pAcommsHandler +IN_SIMPLE_STATUS_HEX_32B ' bus.txt | grep -q '\\000" frame: ' ||
    { grep -E 'STATUS|QSIZE' bus.txt | tail; fail "STATUS_REPORT_IN"; }
  echo "note: the status ciphertext ended in 0x00: Depth decoded as Goby 1.1 would (trailing zeros stripped)"
  depth='[0-9.]+'
fi
grep -qE 'pAcommsHandler +NODE_REPORT +NAME=mm1,TYPE=topside,UTC_TIME=[0-9]+,X=123,Y=321,LAT=42.35[0-9]*,LON=-70.94[0-9]*,SPD=1.2,HDG=45.00,DEPTH='"$depth"'$' bus.txt || { grep NODE_REPORT bus.txt; fail "NODE_REPORT"; }
grep -qE 'pAcommsHandler +ACOMMS_QSIZE +key \{ type: QUEUE_DCCL id: 1 \} size: 1$' bus.txt || fail "ACOMMS_QSIZE"
grep -qE 'pAcommsHandler +OUT_GOTOCOMMAND_HEX_32B +base \{ src: 1 dest: 3' bus.txt || fail "OUT_<NAME>_HEX_32B"
grep -qE 'pAcommsHandler +MODEM_ID +1' bus.txt || fail "MODEM_ID"
grep -qE 'pAcommsHandler +LAT_ORIGIN +42.35' bus.txt || fail "LAT_ORIGIN initializer (global_cfg_var)"
grep -q 'MAC cycle updated: 1 slot(s), cycle 4 s' h.out || { tail -30 h.out; fail "MAC update not applied"; }
grep -q 'bad ACOMMS_MAC_CYCLE_UPDATE' h.out || fail "bad MAC update not reported"
for ch in ACOMMS_INCOMING_DATA_LCM ACOMMS_OUTGOING_DATA_LCM ACOMMS_ACK_LCM ACOMMS_QSIZE_LCM ACOMMS_STATUS_LCM; do
  grep -qa "$ch" bus.lcmlog || fail "no $ch in the log"
done
ok "INCOMING_COMMAND, SPECIAL_INSTRUCTIONS, ACOMMS_ACK, STATUS_REPORT_IN, NODE_REPORT, QSIZE, MAC update, LCM structures"
