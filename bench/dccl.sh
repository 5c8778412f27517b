#!/usr/bin/env bash
# DCCL speed and size: instructions per encode and per decode of WIDE_ALL in test/data/dccl/wide.xml
# (every field type, ints of 32 to 64 bits, a 41-bit float, a 33-bit delta array; 65 bytes on the wire)
# (valgrind callgrind, `--repeat N` minus `--repeat 1`), and
# the size of the core codec for Cortex-M4. Goby 1.1 reference: 134k instructions
# to encode, 128k to decode (both encrypted).
set -uo pipefail
BUILD=${BUILD:-$(pwd)/build}
KELP_ROOT=${KELP_ROOT:-$(pwd)}
K=$BUILD/bin/kelp-dccl
T=$(mktemp -d /tmp/kelp-dccl-bench.XXXXXX)
trap 'rm -rf "$T"' EXIT
N=${DCCL_BENCH_N:-2001}
NOW=1699963200
XML=$KELP_ROOT/test/data/dccl/wide.xml
ARGS=(to=4 u32=4000000000 s34=-5000000000 q32=2147483646 stamp=999999999999999 s64=-9200000000000000000
      pos=-123456789.125 ok=true note=hello_kelp mode=survey raw=deadbeef track=-3999999999 track=-999999999 track=1)
HEX=$("$K" encode --xml "$XML" --msg WIDE_ALL --modem-id 1 --now $NOW "${ARGS[@]}") || { echo "encode failed"; exit 1; }
echo "message WIDE_ALL: $(( ${#HEX} / 2 )) bytes on the wire (encrypted): $HEX"
if ! command -v valgrind >/dev/null; then echo "valgrind missing: no instruction counts"; else
  ir() { # args...: total Ir of one run
    valgrind --tool=callgrind --callgrind-out-file="$T/cg.out" "$@" >/dev/null 2>&1 || return 1
    awk '/^(summary|totals):/ {print $2; exit}' "$T/cg.out"
  }
  e1=$(ir "$K" encode --repeat 1 --xml "$XML" --msg WIDE_ALL --modem-id 1 --now $NOW "${ARGS[@]}")
  eN=$(ir "$K" encode --repeat $N --xml "$XML" --msg WIDE_ALL --modem-id 1 --now $NOW "${ARGS[@]}")
  d1=$(ir "$K" decode --repeat 1 --xml "$XML" --now $NOW "$HEX")
  dN=$(ir "$K" decode --repeat $N --xml "$XML" --now $NOW "$HEX")
  pe1=$(ir "$K" encode --plain --repeat 1 --xml "$XML" --msg WIDE_ALL --modem-id 1 --now $NOW "${ARGS[@]}")
  peN=$(ir "$K" encode --plain --repeat $N --xml "$XML" --msg WIDE_ALL --modem-id 1 --now $NOW "${ARGS[@]}")
  enc=$(( (eN - e1) / (N - 1) )); dec=$(( (dN - d1) / (N - 1) )); penc=$(( (peN - pe1) / (N - 1) ))
  echo "kelp encode: $enc instructions/message (encrypted; $penc without crypto)   Goby 1.1: 134000"
  echo "kelp decode: $dec instructions/message (encrypted)   Goby 1.1: 128000"
  echo "kelp encode+decode: $((enc + dec)) instructions; Goby 1.1 262000 -> $(awk -v a=$((enc + dec)) 'BEGIN{printf "%.1f", 262000/a}')x fewer"
fi
if command -v arm-none-eabi-gcc >/dev/null; then
  mkdir -p "$T/m4"
  objs=()
  for f in "$KELP_ROOT"/src/dccl/*.c; do
    o="$T/m4/$(basename "${f%.c}").o"
    arm-none-eabi-gcc -std=c11 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffunction-sections \
      -fdata-sections -Wall -Wextra -Werror -Wno-double-promotion -I"$KELP_ROOT/include" --specs=nano.specs -c "$f" -o "$o" || { echo "M4 build failed: $f"; exit 1; }
    objs+=("$o")
  done
  echo "core codec (src/dccl/*.c) for Cortex-M4, -Os hard-float, arm-none-eabi-size:"
  arm-none-eabi-size -t "${objs[@]}" | sed "s|$T/m4/||"
else
  echo "arm-none-eabi-gcc missing: no Cortex-M4 size"
fi
