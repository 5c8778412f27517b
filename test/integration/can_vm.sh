#!/usr/bin/env bash
# Real SocketCAN (this host's kernel has none): boot the vcan microVM (scripts/vcan_vm.sh) and
# run test/integration/can_vm.c in it, built -static: kelp-canbridge's CAN side (kelp_canbridge
# + the SocketCAN port with kernel filters) and the firmware node of firmware/can_node.c on
# vcan0, round trips both ways in classic CAN and CAN FD, a message with its frames out of
# order, a dropped frame (timed out, counted), junk (counted), kernel filters, and the
# interface going down/up and being re-created (both ports reopen).
# Needs qemu-system-x86 busybox-static cpio (scripts/vcan_vm.sh --deps installs them) and
# the Debian kernel package (downloaded once into build/vcanvm).
set -euo pipefail
ROOT=${KELP_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$ROOT"
T=$(mktemp -d /tmp/kelp-canvm.XXXXXX)
trap 'rm -rf "$T"' EXIT
# built here with plain gcc: the VM needs a static program, whatever BUILD's flags (ASan) are
gcc -static -O2 -std=c11 -D_GNU_SOURCE -Wall -Wextra -Werror -Iinclude -Ifirmware -DKELP_FW_HOSTED -o "$T/cantest" \
  test/integration/can_vm.c firmware/can_node.c src/drivers/edge/can.c src/bus/can.c src/bus/canbridge.c \
  src/bus/bridge.c src/bus/var.c src/util/*.c -lm
start=$(date +%s)
rc=0
VCAN_VM_LOG=$T/console.log scripts/vcan_vm.sh "$T/cantest" > "$T/out.log" 2>&1 || rc=$?
grep -E '^CAN_VM|^CANTEST_EXIT|insmod|FAIL' "$T/out.log" || true
echo "can_vm: microVM run took $(( $(date +%s) - start )) s"
if [ $rc -ne 0 ] || ! grep -q '^CAN_VM PASSED' "$T/out.log"; then
  echo "can_vm: FAILED (last console lines:)"; tail -30 "$T/out.log"; exit 1
fi
for want in 'out of order: 38 frames reversed' 'dropped frame: not delivered, timed_out=1' 'after re-create: THRUST_CMD 99'; do
  grep -q "$want" "$T/out.log" || { echo "can_vm: missing '$want'"; exit 1; }
done
echo "can_vm: ok"
