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
rc=0
for t in "$@"; do
  clang -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -O1 -g -fsanitize=fuzzer,address,undefined $inc -o $O/$t fuzz/$t.c \
    $O/libkelp.a $O/libkelp_core.a $(pkg-config --libs lcm) -lexpat -lmbedtls -lmbedx509 -lmbedcrypto -lserialport -lsqlite3 -lm
  c=$O/corpus/$t; mkdir -p $c
  [ -d fuzz/corpus/$t ] && cp -n fuzz/corpus/$t/* $c/ 2>/dev/null || true
  echo "== $t ($S s)"
  if ! (cd $O && ./$t -max_total_time=$S -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 corpus/$t >$t.log 2>&1); then
    echo "FUZZ FAIL: $t"; tail -50 $O/$t.log; rc=1
  else
    grep -E '^stat::number_of_executed_units|^Done' $O/$t.log | tr '\n' ' '; echo
  fi
done
exit $rc
