#!/usr/bin/env bash
# Helm with spawned avoidance behaviours (make bench): one helm iteration with 1, 5 and 20
# BHV_AvoidCollision instances spawned from a template plus a BHV_Waypoint, in callgrind
# instructions (ITERS=21 minus ITERS=1, divided by 20) and median wall time.
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_helm_spawn" bench/bench_helm_spawn.c "$B/libkelp_core.a" -lm || exit 1
instr() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
have_vg=1; command -v valgrind >/dev/null || have_vg=0
for ns in 1 5 20; do
  out=$("$B/bench/bench_helm_spawn" $ns 201) || { echo "helm spawn bench $ns failed"; continue; }
  us=$(awk '{for(i=1;i<=NF;i++) if($i=="median_ns") printf "%.1f", $(i+1)/1000}' <<<"$out")
  rest=$(sed 's/median_ns [0-9]* //' <<<"$out")
  if [ $have_vg = 1 ]; then
    a=$(instr "$B/bench/bench_helm_spawn" $ns 1); b=$(instr "$B/bench/bench_helm_spawn" $ns 21)
    echo "helm iteration, $ns avoidance + 1 waypoint: $(( (b - a) / 20 )) instr/iteration, median ${us} us/iteration; $rest"
  else
    echo "helm iteration, $ns avoidance + 1 waypoint: median ${us} us/iteration (valgrind missing); $rest"
  fi
done
