#!/usr/bin/env bash
# DCCL speed and size: instructions per encode and per decode of a 40-byte message
# with every field type, 33- and 50-bit ints among them (valgrind callgrind, `--repeat N` minus `--repeat 1`), and
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
cat > "$T/alltypes.xml" <<'EOF'
<?xml version="1.0" encoding="UTF-8"?>
<message_set>
  <message>
    <name>ALL_TYPES</name><size>40</size>
    <header><id>30</id><time><name>when</name></time><dest_id><name>to</name></dest_id></header>
    <layout>
      <static><name>kind</name><value>all</value></static>
      <int><name>count</name><max>1000</max><min>0</min></int>
      <int><name>serial</name><max>4000000000</max><min>-4000000000</min></int>
      <int><name>stamp</name><max>1e15</max><min>0</min></int>
      <float><name>heading</name><max>360</max><min>0</min><precision>2</precision></float>
      <bool><name>ok</name></bool>
      <string><name>note</name><max_length>10</max_length></string>
      <enum><name>mode</name><value>idle</value><value>survey</value><value>home</value></enum>
      <hex><name>raw</name><num_bytes>4</num_bytes></hex>
      <float><name>depth</name><max>6400</max><min>0</min><precision>1</precision><array_length>2</array_length><max_delta>100</max_delta></float>
    </layout>
  </message>
</message_set>
EOF
ARGS=(to=4 count=999 serial=-3999999999 stamp=999999999999999 heading=270.25 ok=true note=hello_kelp mode=survey raw=deadbeef depth=100.5 depth=120.2)
HEX=$("$K" encode --xml "$T/alltypes.xml" --msg ALL_TYPES --modem-id 1 --now $NOW "${ARGS[@]}") || { echo "encode failed"; exit 1; }
echo "message ALL_TYPES: $(( ${#HEX} / 2 )) bytes on the wire (encrypted): $HEX"
if ! command -v valgrind >/dev/null; then echo "valgrind missing: no instruction counts"; else
  ir() { # args...: total Ir of one run
    valgrind --tool=callgrind --callgrind-out-file="$T/cg.out" "$@" >/dev/null 2>&1 || return 1
    awk '/^(summary|totals):/ {print $2; exit}' "$T/cg.out"
  }
  e1=$(ir "$K" encode --repeat 1 --xml "$T/alltypes.xml" --msg ALL_TYPES --modem-id 1 --now $NOW "${ARGS[@]}")
  eN=$(ir "$K" encode --repeat $N --xml "$T/alltypes.xml" --msg ALL_TYPES --modem-id 1 --now $NOW "${ARGS[@]}")
  d1=$(ir "$K" decode --repeat 1 --xml "$T/alltypes.xml" --now $NOW "$HEX")
  dN=$(ir "$K" decode --repeat $N --xml "$T/alltypes.xml" --now $NOW "$HEX")
  pe1=$(ir "$K" encode --plain --repeat 1 --xml "$T/alltypes.xml" --msg ALL_TYPES --modem-id 1 --now $NOW "${ARGS[@]}")
  peN=$(ir "$K" encode --plain --repeat $N --xml "$T/alltypes.xml" --msg ALL_TYPES --modem-id 1 --now $NOW "${ARGS[@]}")
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
