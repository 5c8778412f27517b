# kelp-commander (iCommander) scripted mode over the acomms_e2e set-up: two pAcommsHandler
# communities over kelp-modemsim. A GoToCommand sent with --send arrives decoded at the
# vehicle with every field, and the topside's acknowledgement is printed as iCommander shows it;
# a value out of the field's range is refused before anything is published.
. "$(dirname "$0")/lib.sh"
cd $T
. $KELP_ROOT/missions/acomms_e2e/e2e_lib.sh
. $KELP_ROOT/missions/acomms_e2e/commander_lib.sh

start s 30
if $BIN/kelp-commander topsides.moos --send GoToCommand Destination=2 goto_x=10001 > refused.out 2>&1; then
  cat refused.out; fail "goto_x=10001 (max 10000) was accepted"
fi
grep -q "goto_x=10001: out of range" refused.out || { cat refused.out; fail "no out-of-range refusal"; }
$BIN/kelp-commander topsides.moos --send GoToCommand Destination=2 goto_x=150 goto_y=294 lights_on=true \
  new_instructions=make_toast goto_speed=2.3 --wait 25 > send.out 2>&1 || { cat send.out; fail "--send --wait failed"; }
finish s
cat send.out
grep -qx "SPECIAL_INSTRUCTIONS: new_instructions=make_toast" send.out || fail "SPECIAL_INSTRUCTIONS publication"
grep -qx "OUTGOING_COMMAND: CommandType=GoTo,Destination=2,goto_x=150,goto_y=294,lights_on=true,goto_speed=2.3" send.out ||
  fail "OUTGOING_COMMAND publication"
grep -A2 -x "Message acknowledged from queue: GoToCommand" send.out | grep -qx " for destination: 2" || fail "ack note"
grep -A2 -x "Message acknowledged from queue: GoToCommand" send.out |
  grep -qE "^ at time: 20[0-9][0-9]-[A-Z][a-z][a-z]-[0-3][0-9] [0-2][0-9]:[0-5][0-9]:[0-5][0-9]$" || fail "ack time"
vals s.mm2.txt INCOMING_COMMAND > in_cmd.txt
grep -qx "Destination=2,type=goto,goto_x=150,goto_y=294,lights_on=true,new_instructions=make_toast,goto_speed=2.29" in_cmd.txt ||
  { cat in_cmd.txt; fail "INCOMING_COMMAND at the vehicle"; }
[ "$(wc -l < in_cmd.txt)" = 1 ] || { cat in_cmd.txt; fail "INCOMING_COMMAND not exactly once"; }
[ "$(vals s.mm1.txt ACOMMS_OUTGOING_DATA | wc -l)" = 1 ] || fail "the refused message was queued"
ok "kelp-commander --send: refused goto_x=10001; GoToCommand decoded at the vehicle; ack printed"
