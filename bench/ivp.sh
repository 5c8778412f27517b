#!/usr/bin/env bash
# IvP benchmarks (make bench): instructions per solve/build with callgrind (N=101 minus N=1,
# divided by 100) and median wall time. MOOS-IvP reference: 4.26 M instr (436 us) per 2-D solve,
# 3.79 M per 3-D solve, 104 k per ZAIC_PEAK build on this machine.
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
IVP=$B/bin/kelp-ivp
[ -x "$IVP" ] || { echo "ivp bench: $IVP missing (make all)"; exit 1; }
mkdir -p "$B/bench"
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_ivp" bench/bench_ivp.c "$B/libkelp_core.a" -lm || exit 1

instr() { # instructions of a command line under callgrind
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
per100() { # (cmd with 101) - (cmd with 1), /100
  local a b
  b=$(instr "$@" 1); a=$(instr "$@" 101)
  echo $(( (a - b) / 100 ))
}
solve_time_us() { # median over 5 runs of (t(--repeat 1001) - t(--repeat 1)) / 1000
  local f=$1 i t1 t2 out=()
  for i in 1 2 3 4 5; do
    t1=$(date +%s%N); "$IVP" solve "$f" --repeat 1 >/dev/null; t2=$(date +%s%N); local a=$((t2 - t1))
    t1=$(date +%s%N); "$IVP" solve "$f" --repeat 1001 >/dev/null; t2=$(date +%s%N); local b=$((t2 - t1))
    out+=($(( (b - a) / 1000 )))
  done
  printf '%s\n' "${out[@]}" | sort -n | sed -n 3p | awk '{printf "%.1f", $1/1000}'
}
have_vg=1; command -v valgrind >/dev/null || have_vg=0
for p in 2d:bench/ivp_2d.txt:4260000 3d:bench/ivp_3d.txt:3790000; do
  IFS=: read -r name file ref <<<"$p"
  dec=$("$IVP" solve "$file" | head -1)
  us=$(solve_time_us "$file")
  if [ $have_vg = 1 ]; then
    n=$(per100 "$IVP" solve "$file" --repeat)
    echo "ivp solve $name: $n instr/solve (MOOS-IvP $ref, ratio $(awk -v a=$ref -v b=$n 'BEGIN{printf "%.2f", a/b}')x), median ${us} us/solve; $dec"
  else
    echo "ivp solve $name: median ${us} us/solve (valgrind missing); $dec"
  fi
done
for what in zaic reflector; do
  t=$("$B/bench/bench_ivp" $what 2001)
  if [ $have_vg = 1 ]; then
    n=$(per100 "$B/bench/bench_ivp" $what)
    extra=""; [ $what = zaic ] && extra=" (MOOS-IvP 104000, ratio $(awk -v b=$n 'BEGIN{printf "%.2f", 104000/b}')x)"
    echo "ivp build $what: $n instr/build$extra; $t"
  else
    echo "ivp build $what: $t"
  fi
done
