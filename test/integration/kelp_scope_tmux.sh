#!/usr/bin/env bash
# kelp-scope as uXMS in a real terminal (tmux: new-session, send-keys, capture-pane):
#  - variables named on the command line (NAV_X NAV_Y) and in the block (VAR = DEPLOY) are
#    listed, never-written ones as n/a, under uXMS's header;
#  - a value poked onto the bus is shown, and a second poke replaces it in place (one header
#    on the screen: ncurses, not a scrolling print);
#  - key 's' shows the source column (the poker's name), key 'h' shows the help;
#  - --all shows a variable nobody named; the plain-output mode (stdout a file) prints the
#    table as lines.
. "$(dirname "$0")/lib.sh"
cd "$T"
command -v tmux > /dev/null || { echo "skip: tmux is not installed"; exit 0; }

cat > alder.moos <<M
Community = alder
ProcessConfig = uXMS
{
  VAR = DEPLOY
  TERM_REPORT_INTERVAL = 0.2
}
M

TM="tmux -L kelp-it-$$"
cleanup_tmux() { $TM kill-server 2>/dev/null || true; }
trap 'cleanup_tmux; cleanup' EXIT
pane() { $TM capture-pane -p -t "$1" > "$2"; }
# wait_pane SESSION FILE PATTERN: capture until PATTERN shows (5 s)
wait_pane() {
  local i=0
  while [ $i -lt 50 ]; do
    pane "$1" "$2"
    grep -qE "$3" "$2" && return 0
    sleep 0.1; i=$((i + 1))
  done
  return 1
}

$TM -f /dev/null new-session -d -s xms -x 120 -y 30 \
  "KELP_LCM_URL='$KELP_LCM_URL' $BIN/kelp-scope $T/alder.moos NAV_X NAV_Y --history=NAV_X 2> $T/xms.err; sleep 30" ||
  fail "tmux would not start"
wait_pane xms p1.txt '^VarName' || { cat p1.txt xms.err; fail "kelp-scope drew no table"; }
grep -qx 'VarName  (S)  (T)  (C)  VarValue (SCOPING:EVENTS)' p1.txt || { cat p1.txt; fail "header"; }
grep -qx -- '-------  ---  ---  ---  -------------------------' p1.txt || { cat p1.txt; fail "header dashes"; }
for v in DEPLOY NAV_X NAV_Y; do
  grep -qE "^$v +n/a\$" p1.txt || { cat p1.txt; fail "$v is not listed as n/a"; }
done
ok "kelp-scope lists the command-line variables NAV_X NAV_Y and the block's VAR DEPLOY"

"$BIN/kelp-poke" alder.moos NAV_X=12.5 > /dev/null
wait_pane xms p2.txt '^NAV_X +12\.5$' || { cat p2.txt; fail "NAV_X=12.5 not shown"; }
"$BIN/kelp-poke" alder.moos NAV_X=-3.25 'DEPLOY:=true' > /dev/null
wait_pane xms p3.txt '^NAV_X +-3\.25$' || { cat p3.txt; fail "NAV_X=-3.25 not shown"; }
grep -q '12\.5' p3.txt && { cat p3.txt; fail "the old value is still on the screen"; }
grep -qE '^DEPLOY +"true"$' p3.txt || { cat p3.txt; fail "DEPLOY string value"; }
[ "$(grep -c '^VarName' p3.txt)" -eq 1 ] || { cat p3.txt; fail "the table is not redrawn in place"; }
ok "a poked value is refreshed in place (12.5 -> -3.25, one header on the screen)"

$TM send-keys -t xms s
wait_pane xms p4.txt '^VarName +\(S\)ource' || { cat p4.txt; fail "'s' did not show the source column"; }
grep -qE '^NAV_X +kelp-poke +-3\.25$' p4.txt || { cat p4.txt; fail "NAV_X row with its source"; }
$TM send-keys -t xms h
wait_pane xms p5.txt '\(HELP\)' || { cat p5.txt; fail "'h' did not show the help"; }
$TM send-keys -t xms h
wait_pane xms p6.txt '^VarName +\(S\)ource' || { cat p6.txt; fail "'h' again did not go back"; }
$TM send-keys -t xms ' '
wait_pane xms p7.txt 'SCOPING:PAUSED' || { cat p7.txt; fail "space did not pause"; }
"$BIN/kelp-poke" alder.moos NAV_X=7 > /dev/null
sleep 1
pane xms p8.txt
grep -qE '^NAV_X +kelp-poke +-3\.25$' p8.txt || { cat p8.txt; fail "paused, yet the table changed"; }
$TM send-keys -t xms u
wait_pane xms p9.txt '^NAV_X +kelp-poke +7$' || { cat p9.txt; fail "'u' did not refresh"; }
ok "keys: 's' shows the source column (kelp-poke), 'h' help and back, space pauses, 'u' refreshes"

$TM send-keys -t xms z
wait_pane xms h1.txt '^\(J\)VarName +\(S\)ource +\(T\) +VarValue \(HISTORY:PAUSED\)$' ||
  { cat h1.txt; fail "'z' did not show the history of NAV_X"; }
grep -qE '^NAV_X +kelp-poke +\(1\) 12\.5$' h1.txt || { cat h1.txt; fail "history: 12.5"; }
grep -qE '^NAV_X +kelp-poke +\(1\) -3\.25$' h1.txt || { cat h1.txt; fail "history: -3.25"; }
grep -qE '^NAV_X +kelp-poke +\(1\) 7$' h1.txt || { cat h1.txt; fail "history: 7"; }
[ "$(grep -n '12\.5' h1.txt | cut -d: -f1)" -lt "$(grep -n -- '-3\.25' h1.txt | cut -d: -f1)" ] || fail "history: not oldest first"
$TM send-keys -t xms z
wait_pane xms h2.txt '^VarName' || { cat h2.txt; fail "'z' again did not go back to scoping"; }
ok "--history=NAV_X: 'z' shows its history oldest first ((1) 12.5, (1) -3.25, (1) 7), 'z' again goes back"

$TM send-keys -t xms p
wait_pane xms s1.txt '^a +kelp-poke +[0-9.]+ +-$' || { cat s1.txt; fail "'p' did not list kelp-poke as process a"; }
$TM send-keys -t xms - a Enter
wait_pane xms s2.txt '^NAV_Y ' || { cat s2.txt; fail "'-' a Enter did not go back to the table"; }
grep -qE '^(NAV_X|DEPLOY) ' s2.txt && { cat s2.txt; fail "'-' a: kelp-poke's variables are still shown"; }
$TM send-keys -t xms - '?' Enter
wait_pane xms s3.txt '^NAV_X +kelp-poke' || { cat s3.txt; fail "'-' ? did not show them again"; }
ok "filter by source: 'p' lists kelp-poke as a, '-' a hides its variables, '-' ? shows them again"

$TM -f /dev/null new-session -d -s all -x 120 -y 30 \
  "KELP_LCM_URL='$KELP_LCM_URL' $BIN/kelp-scope $T/alder.moos --all 2> $T/all.err; sleep 30" ||
  fail "tmux would not start (--all)"
wait_pane all a1.txt '^VarName' || { cat a1.txt all.err; fail "kelp-scope --all drew no table"; }
"$BIN/kelp-poke" alder.moos 'NOBODY_NAMED_ME:=hello there' > /dev/null
wait_pane all a2.txt '^NOBODY_NAMED_ME +"hello there"$' || { cat a2.txt; fail "--all: the unnamed variable is not shown"; }
grep -qx '  -- displaying all variables --' a2.txt || { cat a2.txt; fail "--all: no footer"; }
grep -q '_STATUS' a2.txt && { cat a2.txt; fail "--all shows *_STATUS"; }
ok "--all shows NOBODY_NAMED_ME, which nobody named"

# plain output: stdout a file, keys from a FIFO
mkfifo keys
exec 3<>keys
"$BIN/kelp-scope" alder.moos NAV_Y < keys > plain.out 2>&1 &
PIDS+=($!)
wait_for plain.out '^VarName' 5 || { cat plain.out; fail "plain: no table"; }
"$BIN/kelp-poke" alder.moos NAV_Y=42 > /dev/null
wait_for plain.out '^NAV_Y +42$' 5 || { cat plain.out; fail "plain: NAV_Y=42 not printed"; }
printf 't' >&3
wait_for plain.out '^VarName  \(S\)  \(T\)ime' 5 || { cat plain.out; fail "plain: 't' did not show the time column"; }
ok "plain output (not a terminal): the table as lines, NAV_Y=42, 't' adds the time column"
