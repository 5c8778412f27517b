#!/usr/bin/env bash
# CAN framing benchmark (make bench): frames/s, messages/s and per-message latency through
# kelp's CAN segmentation + reassembly (kelp/can.h), classic and FD frames, no I/O.
set -uo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${BUILD:-$ROOT/build}
cd "$ROOT"
mkdir -p "$B/bench"
gcc -std=c11 -O2 -Iinclude -o "$B/bench/bench_can" bench/bench_can.c "$B/libkelp_core.a" -lm || exit 1
"$B/bench/bench_can"
