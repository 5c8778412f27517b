# kelp-commander's ncurses console, driven in tmux over the acomms_e2e set-up: Select Message,
# edit the GoToCommand fields (an out-of-range goto_x is refused on screen), Send; the vehicle
# receives it decoded and the acknowledgement appears at the top of the console.
. "$(dirname "$0")/lib.sh"
command -v tmux > /dev/null || fail "tmux is not installed (scripts/deps.sh)"
cd $T
. $KELP_ROOT/missions/acomms_e2e/e2e_lib.sh
. $KELP_ROOT/missions/acomms_e2e/commander_lib.sh
SOCK=kelp-cmdr-$$
tm() { tmux -L $SOCK "$@"; }
screen() { tm capture-pane -p -t cmdr > screen.txt; }
# see PATTERN SECONDS: wait until the console shows PATTERN
see() {
  local i=0
  while [ $i -lt $(($2 * 10)) ]; do
    screen; grep -qE "$1" screen.txt && return 0
    sleep 0.1; i=$((i + 1))
  done
  cat screen.txt; fail "the console never showed '$1'"
}
keys() { tm send-keys -t cmdr "$@"; sleep 0.3; }
trap 'tm kill-server 2>/dev/null || true; cleanup' EXIT

start c 35
tm new-session -d -s cmdr -x 100 -y 40 "$BIN/kelp-commander $T/topsidec.moos 2> $T/cmdr.err; sleep 60"
see "iCommander: Vehicle Command Message Sender" 5
grep -q "1 messages loaded." screen.txt || { cat screen.txt; fail "message count"; }
grep -q "Return to active message" screen.txt && fail "Return to active message before any edit"
keys Enter  # Select Message
see "> GoToCommand" 3
keys Enter
see "Editing message variable 1 of 7: Destination" 3
keys -l 2; keys Down
see "Editing message variable 2 of 7: type" 3
grep -q "(static) you cannot change the value of this field" screen.txt || { cat screen.txt; fail "static row info"; }
keys Down; keys -l 10001; keys Enter
see 'refused "10001": out of range' 3
grep -q "^|3. goto_x (int) ||$" screen.txt || { cat screen.txt; fail "goto_x took an out-of-range value"; }
keys -l 150; keys Down; keys -l 294; keys Down; keys -l true; keys Down; keys -l make_toast; keys Down; keys -l 2.3; keys Up; keys Down
see "^\|7. goto_speed \(int|float\) \|2.3\|" 3
cp screen.txt editing_screen.txt
keys Enter
see "Choose an action" 3
keys Down; keys Enter  # Send
see "Message GoToCommand sent." 3
grep -qx "OUTGOING_COMMAND: CommandType=GoTo,Destination=2,goto_x=150,goto_y=294,lights_on=true,goto_speed=2.3" screen.txt ||
  { cat screen.txt; fail "what was sent"; }
keys Escape
see "^\|Message acknowledged from queue: GoToCommand" 30
grep -A1 "^|Message acknowledged from queue: GoToCommand" screen.txt | grep -q "^| for destination: 2" ||
  { cat screen.txt; fail "ack destination"; }
finish c
vals c.mm2.txt INCOMING_COMMAND > in_cmd.txt
grep -qx "Destination=2,type=goto,goto_x=150,goto_y=294,lights_on=true,new_instructions=make_toast,goto_speed=2.29" in_cmd.txt ||
  { cat in_cmd.txt; fail "INCOMING_COMMAND at the vehicle"; }
cat editing_screen.txt
ok "console: edited GoToCommand (goto_x=10001 refused), sent, decoded at the vehicle, ack on screen"
