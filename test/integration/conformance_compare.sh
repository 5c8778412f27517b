#!/usr/bin/env bash
# The conformance comparator (test/conformance/compare.py) agrees with each recording of MOOS-IvP
# 24.8 compared with itself, and catches a changed copy (a dropped delivery, a renamed key): a
# suite that cannot fail would prove nothing. No network: it reads the recordings only.
. "$(dirname "$0")/lib.sh"
out=$(python3 "$KELP_ROOT/test/conformance/compare.py" --self-test --golden "$KELP_ROOT/test/conformance/moos-ivp-24.8") ||
  { echo "$out"; fail "comparator self-test"; }
echo "$out" | grep -q 'self-test: ok' || fail "no verdict: $out"
n=$(echo "$out" | grep -c 'recording against itself' || true)
[ "$n" -ge 10 ] || fail "only $n recordings compared"
ok "comparator: $n recordings agree with themselves; a changed copy fails $(echo "$out" | sed -n 's/.*failing figures \(.*\)/\1/p' | tr -cd ',' | wc -c | awk '{print $1+1}') figures"
