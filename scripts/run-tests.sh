#!/usr/bin/env bash
# Run every Check suite, then every integration test. Exit non-zero on any failure.
set -uo pipefail
B=${1:-build}
fail=0
for t in "$B/test/check_core" "$B/test/check_edge"; do
  echo "== $(basename "$t")"
  if ! "$t"; then fail=1; fi
done
echo "== integration"
if ! BUILD=$(cd "$B" && pwd) "$(dirname "$0")/run-integration.sh"; then fail=1; fi
if [ $fail -ne 0 ]; then echo "make test: FAILED"; exit 1; fi
echo "make test: all passed"
