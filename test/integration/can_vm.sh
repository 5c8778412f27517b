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
# the real apps from the plain build, with the shared libraries they use (liblcm, glib for the
# recorder) copied into the VM at their own paths
AB=${KELP_CANVM_BUILD:-$ROOT/build}
mkdir -p "$T/extra/bin"
for a in kelp-canbridge kelp-poke kelp-record kelp-logcheck; do
  [ -x "$AB/bin/$a" ] || { echo "can_vm: build $AB first (make all): no $a"; exit 1; }
  cp "$AB/bin/$a" "$T/extra/bin/"
  for l in $(ldd "$AB/bin/$a" | awk '$2=="=>" && $3 ~ /^\// {print $3} $1 ~ /^\// {print $1}'); do
    mkdir -p "$T/extra$(dirname "$l")"; cp -L "$l" "$T/extra$l"
  done
done
cat > "$T/extra/app_test.sh" <<'EOS'
# inside the VM: kelp-canbridge on vcan0 and LCM over the loopback, the firmware node next to it
export KELP_LCM_URL="udpm://239.255.76.67:7667?ttl=0"
ip link set lo up; ip link set lo multicast on 2>/dev/null; ip route add 224.0.0.0/4 dev lo
cd /tmp
cat > can.moos <<M
ServerPort = 9000
Community = alder
ProcessConfig = kelp-canbridge
{
  AppTick = 10
  CAN_INTERFACE = vcan0
  NODE_ID = 1
  DICTIONARY = 3=THRUST_CMD, 7=DEPTH
  TO_CAN = DESIRED_THRUST -> THRUST_CMD
  FROM_CAN = DEPTH -> NAV_DEPTH_FW
  FROM_CAN = [FW_STATUS, INJ_*]
}
M
kelp-record -q can.lcmlog & R=$!
kelp-canbridge can.moos > cb.log 2>&1 & C=$!
cantest fwnode 40 > fw.log 2>&1 & F=$!
sleep 1.5
kelp-poke can.moos DESIRED_THRUST=42.5 > /dev/null
sleep 0.7
kelp-poke can.moos DESIRED_THRUST=-13.75 > /dev/null
sleep 5
ip link set vcan0 down; sleep 1; ip link set vcan0 up; sleep 1.5
kelp-poke can.moos DESIRED_THRUST=7.5 > /dev/null
wait $F
sleep 1
kill -INT $C $R; wait $C; wait $R
sed 's/^/APP fw: /' fw.log
sed 's/^/APP cb: /' cb.log | tail -15
kelp-logcheck --print can.lcmlog > log.txt || echo "APP log undecodable"
for v in NAV_DEPTH_FW FW_STATUS INJ_TEXT CANBRIDGE_STATUS THRUST_CMD; do
  echo "APP count $v $(grep -c " $v " log.txt)"
done
grep -E ' (FW_STATUS|CANBRIDGE_STATUS) ' log.txt | tail -4 | sed 's/^/APP last: /'
EOS
start=$(date +%s)
rc=0
VCAN_VM_LOG=$T/console.log scripts/vcan_vm.sh "$T/cantest" "$T/extra" > "$T/out.log" 2>&1 || rc=$?
grep -E '^CAN_VM|^CANTEST_EXIT|^APP|insmod|FAIL' "$T/out.log" || true
echo "can_vm: microVM run took $(( $(date +%s) - start )) s"
if [ $rc -ne 0 ] || ! grep -q '^CAN_VM PASSED' "$T/out.log"; then
  echo "can_vm: FAILED (last console lines:)"; tail -30 "$T/out.log"; exit 1
fi
# the real kelp-canbridge: three commands reached the firmware (the last after vcan0 went down
# and up), its status came back each time, the injected message arrived twice (reversed, and
# whole) but not the one with a dropped frame (timed out), the 100 junk frames were counted
grep -q '^APPTEST_EXIT=0' "$T/out.log" || { echo "can_vm: the app test did not finish"; exit 1; }
app_status=$(grep '^APP last: .*CANBRIDGE_STATUS' "$T/out.log" | tail -1)
for want in 'APP fw: FWNODE commands=3 thrust=7.5' 'FW_STATUS thrust=7.5,commands=3' 'APP count INJ_TEXT 2' \
            'out of order: 38 frames reversed' 'dropped frame: not delivered, timed_out=1' 'after re-create: THRUST_CMD 99'; do
  grep -q "$want" "$T/out.log" || { echo "can_vm: missing '$want'"; exit 1; }
done
for want in up=true tx_msgs=3 bad_frame=100 out_of_order=37 timed_out=1 reopened=1; do
  [[ "$app_status" == *"$want"* ]] || { echo "can_vm: kelp-canbridge status lacks $want: $app_status"; exit 1; }
done
# one status per command at least (a loaded VM may carry a status twice: the count is a floor)
n=$(awk '$1=="APP" && $2=="count" && $3=="FW_STATUS" {print $4}' "$T/out.log")
[ "${n:-0}" -ge 3 ] || { echo "can_vm: ${n:-0} FW_STATUS, want one per command (3)"; exit 1; }
n=$(awk '$1=="APP" && $2=="count" && $3=="NAV_DEPTH_FW" {print $4}' "$T/out.log")
[ "${n:-0}" -ge 50 ] || { echo "can_vm: only ${n:-0} NAV_DEPTH_FW from the firmware's 10 Hz DEPTH"; exit 1; }
echo "can_vm: ok"
