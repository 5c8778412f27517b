#!/usr/bin/env bash
# A corked udpm socket (what an app does around its iteration: postings go to the kernel in
# sendmmsg batches, consecutive datagrams of nearly one size as one segmented send): every message arrives, in publication order, a fragmented one in the
# middle included, and only whole batches leave before the uncork.
. "$(dirname "$0")/lib.sh"
cd "$KELP_ROOT"
# built here from the sources (whatever BUILD's flags are)
gcc -O2 -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -Wall -Wextra -Werror -Iinclude -o "$T/udpm_cork" \
  test/integration/udpm_cork.c src/bus/edge/udpm.c src/bus/udpm.c src/util/*.c -lm -lpthread
out=$("$T/udpm_cork" "$KELP_LCM_URL" gso) || { echo "$out"; fail "udpm_cork (segmented sends)"; }
echo "$out"
ok "corked postings complete and in order, segmented sends padded with zeros only"
case $KELP_LCM_URL in *\?*) plain="$KELP_LCM_URL&gso=0" ;; *) plain="$KELP_LCM_URL?gso=0" ;; esac
out=$("$T/udpm_cork" "$plain" plain) || { echo "$out"; fail "udpm_cork (gso=0)"; }
echo "$out"
ok "with gso=0: one datagram per send, payloads exact"
