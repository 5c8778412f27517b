#!/usr/bin/env bash
# acomms core throughput (queue contest + stitching, unstitching, NMEA parsing, driver).
set -euo pipefail
B=${BUILD:-build}
R=${KELP_ROOT:-.}
cc -std=c11 -D_DEFAULT_SOURCE -O2 -I"$R/include" -o "$B/acomms_bench" "$R/bench/acomms_bench.c" "$B/libkelp_core.a" -lm
"$B/acomms_bench"
