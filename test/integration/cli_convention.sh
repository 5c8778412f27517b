#!/usr/bin/env bash
# One command-line convention (src/app/cli.c): every program in build/bin answers --help and
# --version on stdout with exit 0 and names itself; an unknown option is a usage error (exit 2,
# "<name>: unknown option '--x'" on stderr). MOOS-role apps (kelp_app_run) also answer
# --example and --interface, their --example lists every parameter the app's source reads, and
# run with their own --example block they report no parameter outside the table; --interface
# lists every variable the source publishes or registers by name.
. "$(dirname "$0")/lib.sh"
cd "$T"
version=$(sed -n 's/^VERSION *:= *//p' "$KELP_ROOT/Makefile")
n=0
for b in "$BIN"/*; do
  [ -x "$b" ] && [ -f "$b" ] || continue
  name=$(basename "$b")
  for opt in --help --version; do
    out=$(timeout 10 "$b" $opt 2> err) || fail "$name $opt: exit $? ($(head -3 err))"
    [ -n "$out" ] || fail "$name $opt: nothing on stdout"
    grep -qF -- "$name" <<< "$out" || fail "$name $opt does not name itself: $(head -2 <<< "$out")"
  done
  [ "$(timeout 10 "$b" --version)" = "$name (kelp) $version" ] || fail "$name --version: $(timeout 10 "$b" --version)"
  grep -q "^usage: $name" <<< "$(timeout 10 "$b" --help)" || fail "$name --help has no 'usage: $name' line"
  rc=0; timeout 10 "$b" --no-such-option > out 2> err || rc=$?
  [ $rc -eq 2 ] || fail "$name --no-such-option: exit $rc, want 2"
  grep -qF -- "$name: unknown option '--no-such-option'" err || fail "$name --no-such-option said: $(head -2 err)"
  [ ! -s out ] || fail "$name --no-such-option wrote to stdout"
  n=$((n + 1))
done
[ $n -ge 15 ] || fail "only $n programs in $BIN"
ok "$n programs: --help, --version, unknown option"

# MOOS-role apps: the ones whose source runs kelp_app_run
cp "$KELP_ROOT/missions/alder/alder.bhv" .   # files the examples name: pHelmIvP's and pAcommsHandler's
cp "$KELP_ROOT"/missions/acomms/{example1.xml,simple_status.xml,modemidlookup.txt} .
m=0 ran="" refused=""
for d in "$KELP_ROOT"/apps/*/; do
  name=$(basename "$d")
  grep -q 'kelp_app_run(' "$d"*.c || continue
  b=$BIN/$name
  [ -x "$b" ] || fail "$name not built"
  "$b" --example > ex.txt || fail "$name --example: exit $?"
  "$b" -e | cmp -s - ex.txt || fail "$name -e differs from --example"
  "$b" --interface > if.txt || fail "$name --interface: exit $?"
  "$b" -i | cmp -s - if.txt || fail "$name -i differs from --interface"
  grep -q "^$name Example MOOS Configuration" ex.txt || fail "$name --example header"
  grep -q "^ProcessConfig = " ex.txt || fail "$name --example has no ProcessConfig block"
  grep -q "^$name INTERFACE" if.txt || fail "$name --interface header"
  for s in SYNOPSIS: SUBSCRIPTIONS: PUBLICATIONS:; do grep -q "^$s" if.txt || fail "$name --interface lacks $s"; done
  # every parameter named in the source appears in --example as "  NAME =", "  NAME:" or "  NAME {"
  # (commented out, "  // NAME =", when it stands in for another)
  # (kelp_app_param*(app, "Key") and the app's own helpers taking (app, "Key"))
  keys=$(grep -ohE '[a-z_]+\(app, "[A-Za-z_0-9]+"' "$d"*.c | grep -vE 'notify|register|warning|error|event|global' |
         sed -E 's/.*"([^"]+)"/\1/' | sort -u || true)
  for k in $keys; do
    grep -qiE "^  (// )?$k( *=|:| \\{)" ex.txt || fail "$name reads parameter $k but --example does not show it"
  done
  # every variable the source publishes or subscribes to by name appears in --interface
  vars=$(grep -ohE 'kelp_app_(notify_[a-z]+|register)\([a-z>-]+, "[A-Z][A-Z_0-9]+"' "$d"*.c |
         sed -E 's/.*"([^"]+)"/\1/' | sort -u || true)
  for v in $vars; do
    grep -qE "^  $v( |$)" if.txt || fail "$name uses variable $v but --interface does not list it"
  done
  # run it with its own example block: nothing read outside the table, nothing in the table unknown
  { echo "ServerHost = localhost"; echo "Community = clitest"; echo "LatOrigin = 43.825"; echo "LongOrigin = -70.33"
    sed -n '/^ProcessConfig = /,/^}/p' ex.txt; } > m.moos
  timeout -s INT 1.5 "$b" m.moos > run.txt 2>&1 || true
  if grep -E "missing from .* --example|unknown parameter" run.txt; then fail "$name: table and parser disagree"; fi
  # the unknown-parameter check runs once OnStartUp has accepted the block
  if grep -q "^Configuration warnings:" run.txt; then ran="$ran $name"; else refused="$refused $name($(grep -m1 -iE 'error|need|cannot|must' run.txt | cut -c1-60 || true))"; fi
  m=$((m + 1))
done
[ $m -ge 8 ] || fail "only $m MOOS-role apps found"
ok "$m MOOS-role apps: --example lists what the source reads, --interface what it publishes and registers by name"
echo "ran with their own --example block:$ran"
# every one must start on its own example, or the run-time check above proved nothing for it
[ -z "$refused" ] || fail "refused their own --example block at start-up:$refused"
