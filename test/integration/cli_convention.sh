#!/usr/bin/env bash
# One command-line convention: every program in build/bin answers --help and --version with
# exit 0 and its own name, rejects an unknown option with exit 2 and its own name; MOOS-role
# programs answer --example and --interface, and --example names every parameter the app's
# source reads from its ProcessConfig block.
set -euo pipefail
BUILD=${BUILD:-$(pwd)/build}
KELP_ROOT=${KELP_ROOT:-$(pwd)}
fail() { echo "FAIL: $*"; exit 1; }
T=$(mktemp -d /tmp/kelp-cli.XXXXXX)
trap 'rm -rf "$T"' EXIT
version=$(sed -n 's/^VERSION *:= *//p' "$KELP_ROOT/Makefile")
n=0 moos=0
for p in "$BUILD"/bin/*; do
  [ -x "$p" ] || continue
  name=$(basename "$p")
  n=$((n + 1))
  timeout 10 "$p" --help >"$T/out" 2>"$T/err" </dev/null || fail "$name --help exit $?"
  grep -q "usage: $name" "$T/out" || fail "$name --help does not name itself: $(head -1 "$T/out")"
  timeout 10 "$p" --version >"$T/out" 2>&1 </dev/null || fail "$name --version exit $?"
  grep -qx "$name (kelp) $version" "$T/out" || fail "$name --version says '$(head -1 "$T/out")'"
  rc=0; timeout 10 "$p" --no-such-option >"$T/out" 2>"$T/err" </dev/null || rc=$?
  [ $rc -eq 2 ] || fail "$name --no-such-option exit $rc (want 2)"
  grep -q "^$name: " "$T/err" || fail "$name: unknown option not reported under its own name: $(head -1 "$T/err")"
  # MOOS-role programs
  if grep -q "MISSION.moos \[NAME\]" <(timeout 10 "$p" --help); then
    moos=$((moos + 1))
    timeout 10 "$p" --example >"$T/ex" 2>&1 </dev/null || fail "$name --example exit $?"
    timeout 10 "$p" -e >"$T/ex2" 2>&1 </dev/null || fail "$name -e exit $?"
    cmp -s "$T/ex" "$T/ex2" || fail "$name -e differs from --example"
    grep -q "ProcessConfig" "$T/ex" || fail "$name --example has no ProcessConfig block"
    timeout 10 "$p" --interface >"$T/if" 2>&1 </dev/null || fail "$name --interface exit $?"
    grep -qi "publish" "$T/if" || fail "$name --interface lists no publications"
    src="$KELP_ROOT/apps/$name"
    if [ -d "$src" ]; then
      # parameters read by name from the app's block: kelp_app_param*(app, "Key") and helpers (app, "Key")
      for key in $(grep -ohE '[a-z_]+\(app, "[A-Za-z_]+"' "$src"/*.c |
                   grep -vE 'notify|register|warning|error|event|global' |
                   sed -E 's/.*"([A-Za-z_]+)"/\1/' | sort -u); do
        grep -qiw -- "$key" "$T/ex" || fail "$name --example does not list parameter $key"
      done
    fi
  fi
done
[ $n -ge 15 ] || fail "only $n programs found in $BUILD/bin"
[ $moos -ge 8 ] || fail "only $moos MOOS-role programs found"
echo "ok: $n programs answer --help/--version/unknown options; $moos MOOS-role programs answer --example/--interface"
