#!/usr/bin/env bash
# pContactMgrV20 benchmark (make bench): N contacts reporting at 1 Hz, ownship at 4 Hz, one
# iteration per 0.25 s, an avoidance alert, a custom range report, CONTACT_RANGES on, fed
# straight into the core for 10 s of simulated time: CPU per simulated second as % of one core,
# contacts held, alerts posted / owed (owed: contacts that came within the alert range), state
# size. Goal (issue 15): 500 contacts under 5% of one core.
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_contactmgr" bench/bench_contactmgr.c "$B/libkelp_core.a" -lm || exit 1
printf "%6s %10s %9s %8s %8s %9s\n" N "cpu %core" contacts alerts owed state
for n in ${CMGR_BENCH_N:-10 100 500 2000}; do
  out=$("$B/bench/bench_contactmgr" "$n" 10); rc=$?
  read -r _ N _ cpu _ held _ al _ owed _ _ _ size <<<"$out"
  mark=""; [ $rc -eq 0 ] || mark="  MISMATCH (rc $rc)"
  printf "%6s %10s %9s %8s %8s %9s%s\n" "$N" "$cpu" "$held" "$al" "$owed" "$size" "$mark"
done
