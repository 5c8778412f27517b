#!/usr/bin/env bash
# --help is complete: every option a program in build/bin accepts is named in its --help.
# The options a program accepts are read from its sources: the kelp_cli_opt tables of
# apps/<name>/*.c (and of an edge file whose kelp_cli is named after the program, e.g. the
# viewer's replay), the MOOS runner's table (src/app/app.c) when the program runs
# kelp_app_run, every "--x" an argv loop compares by hand (kelp-commander's --send/--wait), and
# the case patterns of a script in tools/. Each must appear as "--x" in `<name> --help`.
. "$(dirname "$0")/lib.sh"
cd "$T"
R=$KELP_ROOT
# the long options of C sources: table rows { "name", x_argument, ... } and hand-written
# comparisons of an argv element with "--name"
c_opts() {
  cat "$@" | tr '\n' ' ' |
    grep -oE '\{ *"[a-z][a-z0-9-]*" *, *(no|required|optional)_argument|str(n)?cmp\( *argv\[[^]]*\] *, *"--[a-z][a-z0-9-]*' |
    sed -E 's/^\{ *"([^"]*)".*/\1/; s/.*"--//' || true
}
n=0 nopt=0 bad=""
for b in "$BIN"/*; do
  [ -x "$b" ] && [ -f "$b" ] || continue
  name=$(basename "$b")
  src=()
  if [ -d "$R/apps/$name" ]; then
    src=("$R/apps/$name"/*.c)
    # edge files that describe this program's command line (kelp_cli .name = "<name>")
    while IFS= read -r f; do src+=("$f"); done < <(grep -lE "\.name *= *\"$name\"" "$R"/src/*/edge/*.c "$R"/src/app/*.c || true)
    grep -q 'kelp_app_run(' "$R/apps/$name"/*.c && src+=("$R/src/app/app.c")
    opts=$(c_opts "${src[@]}" | sort -u)
  elif [ -f "$R/tools/$name" ]; then
    opts=$(grep -oE '^ *(-[a-zA-Z]\|)?--[a-z][a-z0-9-]*(=\*)?\)' "$R/tools/$name" | sed -E 's/.*--([a-z0-9-]*).*/\1/' | sort -u)
  else
    fail "$name: no sources in apps/$name or tools/$name"
  fi
  help=$(timeout 10 "$b" --help) || fail "$name --help: exit $?"
  for o in $opts; do
    nopt=$((nopt + 1))
    grep -qE -- "--$o([^a-z0-9-]|\$)" <<< "$help" || bad+="$name --$o"$'\n'
  done
  n=$((n + 1))
done
[ -z "$bad" ] || fail "options accepted but missing from --help:"$'\n'"$bad"
[ $n -ge 40 ] || fail "only $n programs in $BIN"
# the extraction itself: a table row and a hand-written comparison (kelp-commander's old --send)
printf '%s\n' '{ "table-opt", required_argument, 1000, "N", "x" },' 'if (strcmp(argv[i], "--hand-opt") == 0 && i + 1 < argc)' > x.c
[ "$(c_opts x.c | tr '\n' ' ')" = "table-opt hand-opt " ] || fail "the extraction reads: $(c_opts x.c | tr '\n' ' ')"
ok "$n programs: each of $nopt accepted options is in the program's --help"
