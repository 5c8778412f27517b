#!/usr/bin/env bash
# Run each test/integration/*.sh. Each test creates its own network namespace(s).
# Set KELP_IT=pattern to run a subset.
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
export BUILD=${BUILD:-$here/build} KELP_ROOT=$here
pass=0; failn=0; failed=()
for t in "$here"/test/integration/*.sh; do
  [ -e "$t" ] || continue
  n=$(basename "$t" .sh)
  case "$n" in lib*) continue ;; esac
  [ -n "${KELP_IT:-}" ] && [[ "$n" != *${KELP_IT}* ]] && continue
  log=$(mktemp /tmp/kelp-it-$n.XXXXXX)
  start=$(date +%s.%N)
  if timeout 300 bash "$t" >"$log" 2>&1; then
    pass=$((pass+1)); printf 'PASS %-28s %5.1fs\n' "$n" "$(echo "$(date +%s.%N) - $start" | bc)"
    rm -f "$log"
  else
    failn=$((failn+1)); failed+=("$n"); printf 'FAIL %s (log follows)\n' "$n"; tail -40 "$log" | sed 's/^/    /'
  fi
done
echo "integration: $pass passed, $failn failed"
[ $failn -eq 0 ]
