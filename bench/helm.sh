#!/usr/bin/env bash
# Helm benchmark (make bench): cost of one helm iteration (behaviours' checks and function
# builds + the IvP solve + postings) with 3 and 10 active behaviours, in callgrind
# instructions (ITERS=101 minus ITERS=1, divided by 100) and median wall time.
#   3 behaviours:  SimpleWaypoint (ZAIC), Waypoint, Loiter
#   10 behaviours: those + SimpleWaypoint (Reflector, 1000 pieces), 2 Waypoint, Loiter,
#                  ConstantSpeed, ConstantHeading, SimpleWaypoint (ZAIC)
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_helm" bench/bench_helm.c "$B/libkelp_core.a" -lm || exit 1
instr() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
have_vg=1; command -v valgrind >/dev/null || have_vg=0
for nb in 3 10; do
  out=$("$B/bench/bench_helm" $nb 2001) || { echo "helm bench $nb failed"; continue; }
  us=$(awk '{for(i=1;i<=NF;i++) if($i=="median_ns") printf "%.1f", $(i+1)/1000}' <<<"$out")
  rest=$(sed 's/median_ns [0-9]* //' <<<"$out")
  if [ $have_vg = 1 ]; then
    a=$(instr "$B/bench/bench_helm" $nb 1); b=$(instr "$B/bench/bench_helm" $nb 101)
    echo "helm iteration, $nb behaviours: $(( (b - a) / 100 )) instr/iteration, median ${us} us/iteration; $rest"
  else
    echo "helm iteration, $nb behaviours: median ${us} us/iteration (valgrind missing); $rest"
  fi
done
