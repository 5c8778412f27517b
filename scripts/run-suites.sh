#!/usr/bin/env bash
# Run every Check suite of one runner, each suite in its own process, KELP_SUITE_JOBS at a time
# (default: one per core); a failing suite's output is shown. One process per suite keeps each
# fork small (under ASan a single process forking for every check spends most of its time
# copying itself), and the suites run side by side.
#   scripts/run-suites.sh RUNNER [WRAPPER ...]   e.g. build/test/check_core, or qemu-aarch64 RUNNER
# KELP_SUITE_JOBS=0 runs every suite in one process. Exit 1 when a suite fails.
set -uo pipefail
[ $# -ge 1 ] || { echo "usage: $0 RUNNER [WRAPPER ...]" >&2; exit 2; }
t=$1; shift
jobs=${KELP_SUITE_JOBS:-$(nproc 2>/dev/null || echo 2)}
if [ "$jobs" = 0 ]; then "$@" "$t"; exit; fi
n=$("$@" "$t" --count) || { echo "$t: cannot count its suites"; exit 1; }
out=$(mktemp -d /tmp/kelp-suites.XXXXXX)
trap 'rm -rf "$out"' EXIT
run_suite() {
  local out=$1 i=$2; shift 2
  if "$@" --suite "$i" > "$out/$i.log" 2>&1; then echo "ok $i"; else echo "FAIL $i"; fi
}
export -f run_suite
seq 0 $((n - 1)) | xargs -P "$jobs" -I{} bash -c 'run_suite "$@"' _ "$out" {} "$@" "$t" > "$out/summary"
checks=0 failed=0 name=
for i in $(seq 0 $((n - 1))); do
  line=$(grep -E '^[a-z0-9_-]+: 1 suites, [0-9]+ checks, [0-9]+ failed$' "$out/$i.log" | tail -1)
  if [ -z "$line" ] || ! grep -qx "ok $i" "$out/summary"; then
    failed=$((failed + 1)); echo "---- suite $i"; grep -v '^ *$' "$out/$i.log" | tail -40
    continue
  fi
  name=${line%%:*}
  checks=$((checks + $(echo "$line" | awk '{print $4}')))
done
echo "${name:-$(basename "$t")}: $n suites, $checks checks, $failed suites failed"
[ "$failed" -eq 0 ]
