#!/usr/bin/env bash
# Build every fuzz/fuzz_*.c with libFuzzer + ASan + UBSan and run each for FUZZ_SECONDS.
# Seeds come from fuzz/corpus/<target>/ (copied; findings never touch the repo).
set -euo pipefail
cd "$(dirname "$0")/.."
S=${FUZZ_SECONDS:-20}
O=build-fuzz
mkdir -p $O
inc="-Iinclude -I$O/gen $(pkg-config --cflags lcm)"
make --no-print-directory BUILD=$O CC=clang OPT="-O1 -g -fsanitize=fuzzer-no-link,address,undefined" $O/libkelp_core.a $O/libkelp.a >/dev/null
# build every target first, then run them two at a time (one per core)
for t in "$@"; do
  clang -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -O1 -g -fsanitize=fuzzer,address,undefined $inc -o $O/$t fuzz/$t.c \
    $O/libkelp.a $O/libkelp_core.a $(pkg-config --libs lcm) -lexpat -lmbedtls -lmbedx509 -lmbedcrypto -lserialport -lm -lpthread -lutil &
done
wait
for t in "$@"; do [ -x $O/$t ] || { echo "FUZZ BUILD FAIL: $t"; exit 1; }; done
run_target() {
  local t=$1 S=$2 O=$3
  local c=$O/corpus/$t
  mkdir -p $c
  [ -d fuzz/corpus/$t ] && cp -n fuzz/corpus/$t/* $c/ 2>/dev/null || true
  if (cd $O && ./$t -max_total_time=$S -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 corpus/$t >$t.log 2>&1); then
    echo "== $t ($S s): $(grep -E '^stat::number_of_executed_units' $O/$t.log | awk '{print $2}') runs, no crash"
  else
    echo "FUZZ FAIL: $t"; tail -50 $O/$t.log; return 1
  fi
}
export -f run_target
jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
printf '%s\n' "$@" | xargs -P "$jobs" -I{} bash -c 'run_target "$@"' _ {} "$S" "$O"
