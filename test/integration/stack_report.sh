#!/usr/bin/env bash
# The firmware stack report (scripts/stack_report.py) follows calls through the core's function
# tables: on a fixture (test/integration/data/stack_report/table.c and the call graph GCC wrote
# for it with -fcallgraph-info=su) a behaviour-like ops table's on_run and an algorithm
# registered from a positional table are reached, a sink the caller passes in is not, and
# --fail fails on the paths over the limit that only the table hops reveal. No build needed.
. "$(dirname "$0")/lib.sh"
d="$KELP_ROOT/test/integration/data/stack_report"
rep() { python3 "$KELP_ROOT/scripts/stack_report.py" --src "$d" "$@" "$d/table.ci"; }
out=$(rep --limit 1024) || { echo "$out"; fail "report without --fail"; }
echo "$out" | grep -qE '^ +1896  kelp_t_run +kelp_t_run =\[t_ops\.on_run\]=> big_run$' ||
  { echo "$out"; fail "kelp_t_run's path through t_ops.on_run (8 + 1888 bytes) not followed"; }
echo "$out" | grep -qE '^ +2296  kelp_t_alg_apply +kelp_t_alg_apply =\[t_alg_entry\.fn\]=> alg_big$' ||
  { echo "$out"; fail "the algorithm registered from the positional table not reached"; }
echo "$out" | grep -qE '^ +16  kelp_t_publish +kelp_t_publish$' || { echo "$out"; fail "the caller's sink was followed"; }
echo "$out" | grep -q 'caller supplies.*t_sink.publish (1)' || { echo "$out"; fail "the sink is not listed as not followed"; }
echo "$out" | grep -q '2 over 1024 bytes' || { echo "$out"; fail "over-limit count"; }
if out2=$(rep --limit 1024 --fail); then echo "$out2"; fail "--fail passed with paths over 1024 bytes through tables"; fi
# direct calls only: the same graph shows nothing over the limit (what the report printed before)
out3=$(rep --limit 1024 --fail --no-tables) || { echo "$out3"; fail "--no-tables should see no path over the limit"; }
echo "$out3" | grep -q '0 over 1024 bytes' || { echo "$out3"; fail "--no-tables count"; }
ok "stack report: table hops followed (t_ops.on_run 1896 B, t_alg_entry.fn 2296 B), the caller's sink not, --fail fails on them"
