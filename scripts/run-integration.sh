#!/usr/bin/env bash
# Run each test/integration/*.sh, several at a time (KELP_IT_JOBS, default 3): every test
# makes its own network namespace(s) and LCM port, so they cannot hear each other.
# KELP_IT=pattern runs a subset; KELP_IT_ONLY="name ..." runs just those; KELP_IT_SKIP="name ..." leaves those out. Each test's output is kept and shown when it fails.
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
export BUILD=${BUILD:-$here/build} KELP_ROOT=$here
jobs=${KELP_IT_JOBS:-3}
R=$(mktemp -d /tmp/kelp-it.XXXXXX)
tests=()
for t in "$here"/test/integration/*.sh; do
  [ -e "$t" ] || continue
  n=$(basename "$t" .sh)
  case "$n" in lib*) continue ;; esac
  [ -n "${KELP_IT:-}" ] && [[ "$n" != *${KELP_IT}* ]] && continue
  if [ -n "${KELP_IT_ONLY:-}" ] && [[ " $KELP_IT_ONLY " != *" $n "* ]]; then continue; fi
  if [[ " ${KELP_IT_SKIP:-} " == *" $n "* ]]; then echo "SKIP $n (KELP_IT_SKIP: it runs in make test)"; continue; fi
  tests+=("$t")
done
run_one() {
  local t=$1 R=$2 n s rc
  n=$(basename "$t" .sh)
  s=$(date +%s.%N)
  timeout 300 bash "$t" > "$R/$n.log" 2>&1; rc=$?
  printf '%s %.1f\n' "$rc" "$(echo "$(date +%s.%N) - $s" | bc)" > "$R/$n.rc"
  if [ "$rc" -eq 0 ]; then printf 'PASS %-28s %5.1fs\n' "$n" "$(cut -d' ' -f2 "$R/$n.rc")"
  else printf 'FAIL %-28s (exit %s)\n' "$n" "$rc"; fi
}
export -f run_one
printf '%s\n' "${tests[@]}" | xargs -P "$jobs" -I{} bash -c 'run_one "$@"' _ {} "$R"
# a test that failed beside the others runs once more, alone: several of them run apps against
# a warped clock, and a host loaded by the others (and by CI's background builds) can starve
# them. Its first failure is shown either way; failing alone too, it fails the run.
retried=0
for t in "${tests[@]}"; do
  n=$(basename "$t" .sh)
  [ "$(cut -d' ' -f1 "$R/$n.rc" 2>/dev/null)" = 0 ] && continue
  echo "---- $n failed beside the others (last 40 lines); running it again, alone"
  tail -40 "$R/$n.log" | sed 's/^/    /'
  mv "$R/$n.log" "$R/$n.first.log"
  run_one "$t" "$R"
  retried=$((retried+1))
done
pass=0; failn=0
for t in "${tests[@]}"; do
  n=$(basename "$t" .sh)
  if [ "$(cut -d' ' -f1 "$R/$n.rc" 2>/dev/null)" = 0 ]; then pass=$((pass+1)); else
    failn=$((failn+1)); echo "---- $n (alone; last 40 lines)"; tail -40 "$R/$n.log" | sed 's/^/    /'; fi
done
[ $retried -gt 0 ] && echo "integration: $retried test(s) failed beside the others and were run again alone (above)"
rm -rf "$R"
echo "integration: $pass passed, $failn failed"
[ $failn -eq 0 ]
