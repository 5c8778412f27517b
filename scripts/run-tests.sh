#!/usr/bin/env bash
# Run every Check suite, then every integration test. Exit non-zero on any failure.
set -uo pipefail
B=${1:-build}
fail=0
for t in "$B/test/check_core" "$B/test/check_edge"; do
  echo "== $(basename "$t")"
  "$(dirname "$0")/run-suites.sh" "$t" || fail=1
done
echo "== benchmarks compile"
for b in bench/*.c; do
  if ! ${CC:-gcc} -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -c -o /dev/null -Wall -Wextra -Werror -Iinclude -I"$B/gen" \
       $(pkg-config --cflags lcm 2>/dev/null) "$b"; then echo "benchmark $b does not compile"; fail=1; fi
done
echo "== integration"
if ! BUILD=$(cd "$B" && pwd) "$(dirname "$0")/run-integration.sh"; then fail=1; fi
if [ $fail -ne 0 ]; then echo "make test: FAILED"; exit 1; fi
echo "make test: all passed"
