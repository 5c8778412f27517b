#!/usr/bin/env bash
# Build the allocation-free core for Cortex-M4 (hard float, newlib nano) and print its size.
set -euo pipefail
cd "$(dirname "$0")/.."
CC=arm-none-eabi-gcc
O=build-fw
rm -rf "$O"; mkdir -p "$O/obj"
FLAGS="-std=c11 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffunction-sections -fdata-sections
 -Wall -Wextra -Werror -Wno-double-promotion -Iinclude --specs=nano.specs"
objs=()
for f in $(ls src/*/*.c | grep -v "^src/app/"); do
  o="$O/obj/$(echo "${f%.c}" | tr / _).o"
  $CC $FLAGS -c "$f" -o "$o"
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
if arm-none-eabi-nm "$O/kelp_fw.elf" | grep -qwE '_malloc_r|malloc'; then
  echo "firmware: malloc was pulled in"; exit 1
fi
echo "firmware: ok, no malloc in image"
