#!/usr/bin/env bash
# Run every Check suite, then every integration test. Exit non-zero on any failure.
set -uo pipefail
B=${1:-build}
fail=0
# each suite in its own process, KELP_SUITE_JOBS at a time (default: one per core); a suite's
# output is shown when it fails. KELP_SUITE_JOBS=0 runs every suite in one process.
jobs=${KELP_SUITE_JOBS:-$(nproc 2>/dev/null || echo 2)}
run_suite() {
  local t=$1 i=$2 out=$3
  if "$t" --suite "$i" > "$out/$i.log" 2>&1; then echo "ok $i"; else echo "FAIL $i"; fi
}
export -f run_suite
for t in "$B/test/check_core" "$B/test/check_edge"; do
  echo "== $(basename "$t")"
  if [ "$jobs" = 0 ]; then "$t" || fail=1; continue; fi
  n=$("$t" --count) || { echo "$t: cannot count its suites"; fail=1; continue; }
  out=$(mktemp -d /tmp/kelp-suites.XXXXXX)
  seq 0 $((n - 1)) | xargs -P "$jobs" -I{} bash -c 'run_suite "$@"' _ "$t" {} "$out" > "$out/summary"
  checks=0; failed=0
  for i in $(seq 0 $((n - 1))); do
    line=$(grep -E '^[a-z0-9-]+: 1 suites, [0-9]+ checks, [0-9]+ failed$' "$out/$i.log" | tail -1)
    if [ -z "$line" ] || ! grep -qx "ok $i" "$out/summary"; then
      fail=1; failed=$((failed + 1)); echo "---- suite $i"; grep -v '^ *$' "$out/$i.log" | tail -40
      continue
    fi
    checks=$((checks + $(echo "$line" | awk '{print $4}')))
  done
  echo "$(basename "$t" | sed 's/^check_//'): $n suites, $checks checks, $failed suites failed"
  rm -rf "$out"
done
echo "== benchmarks compile"
for b in bench/*.c; do
  if ! ${CC:-gcc} -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -fsyntax-only -Wall -Werror -Iinclude -I"$B/gen" \
       $(pkg-config --cflags lcm 2>/dev/null) "$b"; then echo "benchmark $b does not compile"; fail=1; fi
done
echo "== integration"
if ! BUILD=$(cd "$B" && pwd) "$(dirname "$0")/run-integration.sh"; then fail=1; fi
if [ $fail -ne 0 ]; then echo "make test: FAILED"; exit 1; fi
echo "make test: all passed"
