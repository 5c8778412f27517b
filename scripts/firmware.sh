#!/usr/bin/env bash
# Build the allocation-free core for Cortex-M4 (hard float, newlib nano) and print its size and
# the worst-case stack of each public entry point (GCC's call graph with frame sizes,
# -fcallgraph-info=su, summed by scripts/stack_report.py).
set -euo pipefail
cd "$(dirname "$0")/.."
CC=arm-none-eabi-gcc
O=build-fw
rm -rf "$O"; mkdir -p "$O/obj"
FLAGS="-std=c11 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffunction-sections -fdata-sections
 -Wall -Wextra -Werror -Wno-double-promotion -Iinclude --specs=nano.specs -DKELP_OWN_PRINTF"
objs=()
for f in $(ls src/*/*.c | grep -v "^src/app/"); do
  o="$O/obj/$(echo "${f%.c}" | tr / _).o"
  $CC $FLAGS -fcallgraph-info=su -c "$f" -o "$o"
  objs+=("$o")
done
arm-none-eabi-ar rcs "$O/libkelp_core_m4.a" "${objs[@]}"
# Link a firmware image that keeps every public core function (--undefined for each) to show what it costs
# with nano newlib; firmware/fw_main.c provides a reset handler and references the public API.
syms=$(arm-none-eabi-nm -g --defined-only "$O/libkelp_core_m4.a" | awk '$2=="T"{printf " -Wl,--undefined=%s", $3}')
$CC $FLAGS --specs=nosys.specs -Wl,--gc-sections $syms -Wl,-Map="$O/fw.map" -Wl,--whole-archive "$O/libkelp_core_m4.a" -Wl,--no-whole-archive \
  firmware/fw_main.c -lm -o "$O/kelp_fw.elf"
echo "== arm-none-eabi-size (core archive, per object, Cortex-M4 -Os)"
arm-none-eabi-size -t "$O/libkelp_core_m4.a" | tail -n 1 | sed 's/(TOTALS)/libkelp_core_m4.a (total)/'
echo "== arm-none-eabi-size (whole core linked into an image with newlib nano)"
arm-none-eabi-size "$O/kelp_fw.elf"
# (nm's output is read whole first: `nm | grep -q` under pipefail turned a match into "ok"
# whenever grep's early exit gave nm a SIGPIPE)
syms_img=$(arm-none-eabi-nm "$O/kelp_fw.elf")
if grep -wE '_malloc_r|malloc|_free_r|_realloc_r' <<<"$syms_img"; then
  echo "firmware: malloc was pulled in (who calls it: arm-none-eabi-objdump -d $O/kelp_fw.elf)"; exit 1
fi
echo "firmware: ok, no malloc in image"
# The same image with the messages of kelp_diag compiled out (-DKELP_NO_ERRMSG): no reason text may
# reach it (a few of the mission parser's, the DCCL codec's and the helm's messages are looked for)
mkdir -p "$O/noerr"
nobjs=()
for f in $(ls src/*/*.c | grep -v "^src/app/"); do
  o="$O/noerr/$(echo "${f%.c}" | tr / _).o"
  $CC $FLAGS -DKELP_NO_ERRMSG -c "$f" -o "$o"
  nobjs+=("$o")
done
arm-none-eabi-ar rcs "$O/libkelp_core_m4_noerr.a" "${nobjs[@]}"
syms_n=$(arm-none-eabi-nm -g --defined-only "$O/libkelp_core_m4_noerr.a" | awk '$2=="T"{printf " -Wl,--undefined=%s", $3}')
$CC $FLAGS -DKELP_NO_ERRMSG --specs=nosys.specs -Wl,--gc-sections $syms_n -Wl,--whole-archive "$O/libkelp_core_m4_noerr.a" \
  -Wl,--no-whole-archive firmware/fw_main.c -lm -o "$O/kelp_fw_noerr.elf"
echo "== arm-none-eabi-size (the same image built with -DKELP_NO_ERRMSG)"
arm-none-eabi-size "$O/kelp_fw_noerr.elf"
str_img=$(strings -a "$O/kelp_fw.elf"); str_noerr=$(strings -a "$O/kelp_fw_noerr.elf")
for msg in "block not closed: missing '}'" "protobuf-style 'key: value' outside" "unterminated string"; do
  grep -qF "$msg" <<<"$str_img" || { echo "firmware: '$msg' is not in the normal image (check the probe)"; exit 1; }
  if grep -qF "$msg" <<<"$str_noerr"; then echo "firmware: '$msg' is in the KELP_NO_ERRMSG image"; exit 1; fi
done
echo "firmware: no diagnostic text in the KELP_NO_ERRMSG image"
echo "== worst-case stack of the public core entry points (Cortex-M4 -Os; calls through the core's function tables followed)"
# (tiles_rec, the one recursion, descends once per domain variable: at most KELP_IVP_MAX_DIM
# rounds of 32 bytes under kelp_ivp_func_tiles, which stays far under the limit). An indirect call
# reaches every core function a const table puts in its slot (the behaviours' kelp_bhv_ops, the
# DCCL algorithms); sinks and callbacks the library's caller supplies are listed, not followed.
python3 scripts/stack_report.py --fail --limit 1024 --top ${FW_STACK_TOP:-15} "$O"/obj/*.ci
# The CAN node example (firmware/can_node.c): kelp's CAN framing with the firmware's own
# capacities (2 reassembly slots, 128-byte messages, 8 dictionary entries), linked with only
# what it uses, as a vehicle's microcontroller image would be.
FWDEF="-DKELP_CAN_SLOTS=2 -DKELP_CAN_MAX_BODY=128 -DKELP_CAN_DICT_MAX=8"
$CC $FLAGS $FWDEF -c src/bus/can.c -o "$O/can_fw.o"
$CC $FLAGS $FWDEF --specs=nosys.specs -Wl,--gc-sections -Wl,-Map="$O/can_node.map" firmware/can_node.c "$O/can_fw.o" \
  "$O/libkelp_core_m4.a" -lm -o "$O/can_node.elf"
echo "== arm-none-eabi-size (firmware/can_node.c: CAN node publishing DEPTH, subscribing THRUST_CMD)"
arm-none-eabi-size "$O/can_node.elf"
syms_can=$(arm-none-eabi-nm "$O/can_node.elf")
if grep -wE '_malloc_r|malloc|_free_r|_realloc_r' <<<"$syms_can"; then
  echo "firmware: malloc was pulled into can_node.elf"; exit 1
fi
grep -qw kelp_can_send <<<"$syms_can" && grep -qw kelp_can_rx_frame <<<"$syms_can" || { echo "firmware: CAN framing missing from can_node.elf"; exit 1; }
echo "firmware: can_node ok, no malloc in image"
