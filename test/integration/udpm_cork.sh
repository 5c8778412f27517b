#!/usr/bin/env bash
# A corked udpm socket (what an app does around its iteration: postings go to the kernel in
# sendmmsg batches): every message arrives, in publication order, a fragmented one in the
# middle included, and only whole batches leave before the uncork.
. "$(dirname "$0")/lib.sh"
cd "$KELP_ROOT"
# built here from the sources (whatever BUILD's flags are)
gcc -O2 -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Wall -Wextra -Werror -Iinclude -o "$T/udpm_cork" \
  test/integration/udpm_cork.c src/bus/edge/udpm.c src/bus/udpm.c src/util/*.c -lm -lpthread
out=$("$T/udpm_cork" "$KELP_LCM_URL") || { echo "$out"; fail "udpm_cork"; }
echo "$out"
ok "corked postings complete and in order"
