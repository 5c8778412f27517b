#!/usr/bin/env bash
# uFldNodeComms benchmark (make bench): N vehicles 60 m apart reporting at 4 Hz (comms range
# 100 m, critical 30 m, report pulses on) fed straight into the core for 10 s of simulated
# time: CPU per simulated second as % of one core (report parsing, relaying, pulse strings),
# relays made / relays owed (owed: pairs within range, by brute force in the bench), and the
# core's state size. Goal: 500 vehicles under 25% of one core with every owed relay made.
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_nodecomms" bench/bench_nodecomms.c "$B/libkelp_core.a" -lm || exit 1
printf "%6s %10s %10s %10s %8s\n" N "cpu %core" relayed owed state
for n in 10 100 500 2000; do
  out=$("$B/bench/bench_nodecomms" $n 10); rc=$?
  read -r _ N _ cpu _ rel _ owed _ _ _ _ _ size <<<"$out"
  mark=""; [ $rc -eq 0 ] || mark="  MISMATCH (rc $rc)"
  printf "%6s %10s %10s %10s %8s%s\n" "$N" "$cpu" "$rel" "$owed" "$size" "$mark"
done
