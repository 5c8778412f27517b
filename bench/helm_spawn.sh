#!/usr/bin/env bash
# Helm with spawned avoidance behaviours (make bench): one helm iteration with 1, 5, 20 and 50
# BHV_AvoidCollision instances spawned from a template plus a BHV_Waypoint, in callgrind
# instructions (ITERS=21 minus ITERS=1, divided by 20; split into the IvP solve and the rest,
# the rest being mostly the behaviours' function builds) and median wall time (with the
# helm's own build / solve times). The helm and IvP sources are compiled here with room for 50
# spawned instances (KELP_HELM_MAX_SPAWNED=64, KELP_HELM_MAX_BHVS=72; the library's defaults
# are 24 and 32). Goal (issue 28): 20 avoidance at most 16 M instructions, 50 at most 40 M.
# Last, pContactMgrV20 and the helm together for 50 contacts at AppTick 4: the contact
# manager's CPU (bench_contactmgr 50) plus four 50-avoidance helm iterations per second, as a
# share of one core. Wall times are indicative on a shared machine; instructions are not.
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
O=$B/bench/helm_spawn_obj
mkdir -p "$O"
DEFS="-DKELP_HELM_MAX_SPAWNED=64 -DKELP_HELM_MAX_BHVS=72"
objs=()
for c in src/helm/*.c src/ivp/*.c src/field/nodereport.c; do
  o=$O/$(echo "${c%.c}" | tr / _).o
  if [ ! -e "$o" ] || [ "$c" -nt "$o" ] || [ -n "$(find include src/helm src/ivp -newer "$o" -name '*.h' 2>/dev/null | head -1)" ]; then
    gcc -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -O2 $DEFS -Iinclude -c "$c" -o "$o" || exit 1
  fi
  objs+=("$o")
done
gcc -std=c11 -O2 $DEFS -Iinclude -o "$B/bench/bench_helm_spawn" bench/bench_helm_spawn.c "${objs[@]}" "$B/libkelp_core.a" -lm || exit 1
cg() { # callgrind: total instructions and the inclusive cost of the helm's solve
  local f=$B/bench/helm_spawn.cg
  valgrind --tool=callgrind --callgrind-out-file="$f" "$@" >/dev/null 2>&1 || return 1
  local tot sol
  tot=$(callgrind_annotate "$f" 2>/dev/null | sed -n 's/^ *\([0-9,]*\) .*PROGRAM TOTALS.*/\1/p' | tr -d ,)
  sol=$(callgrind_annotate --inclusive=yes "$f" 2>/dev/null | grep -m1 'kelp_ivp_solve ' | sed 's/^ *\([0-9,]*\) .*/\1/' | tr -d ,)
  rm -f "$f"
  echo "${tot:-0} ${sol:-0}"
}
have_vg=1; command -v valgrind >/dev/null || have_vg=0
printf "%6s %14s %12s %12s %10s %10s %10s %7s  %s\n" "avoid" "instr/iter" "solve" "build+rest" "wall us" "build us" "solve us" pieces decision
helm50_us=""
for ns in 1 5 20 50; do
  out=$("$B/bench/bench_helm_spawn" $ns 201) || { echo "helm spawn bench $ns failed"; continue; }
  read -r _ med _ bu _ su _ pcs _ dec <<<"$out"
  us=$(awk -v m="$med" 'BEGIN{printf "%.1f", m/1000}')
  [ $ns = 50 ] && helm50_us=$us
  if [ $have_vg = 1 ]; then
    read -r a as <<<"$(cg "$B/bench/bench_helm_spawn" $ns 1)"; read -r b bs <<<"$(cg "$B/bench/bench_helm_spawn" $ns 21)"
    it=$(( (b - a) / 20 )); sv=$(( (bs - as) / 20 ))
    printf "%6s %14s %12s %12s %10s %10s %10s %7s  %s\n" $ns $it $sv $((it - sv)) "$us" "$bu" "$su" "$pcs" "$dec"
  else
    printf "%6s %14s %12s %12s %10s %10s %10s %7s  %s\n" $ns "(no valgrind)" - - "$us" "$bu" "$su" "$pcs" "$dec"
  fi
done
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_contactmgr" bench/bench_contactmgr.c "$B/libkelp_core.a" -lm || exit 1
cm=$("$B/bench/bench_contactmgr" 50 10)
read -r _ _ _ cmcpu _ <<<"$cm"
if [ -n "$helm50_us" ]; then
  awk -v c="$cmcpu" -v h="$helm50_us" 'BEGIN{printf "pContactMgrV20 + helm, 50 contacts at AppTick 4: %.2f%% + %.2f%% = %.2f%% of one core\n", c, h*4/1e4, c + h*4/1e4}'
fi
