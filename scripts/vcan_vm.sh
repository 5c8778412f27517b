#!/bin/sh
# Run a static test program inside a qemu TCG microVM whose kernel has SocketCAN and vcan0
# (Debian's stock kernel and its modules; this host's kernel has no CAN at all).
#   scripts/vcan_vm.sh --deps          install what it needs (qemu-system-x86 busybox-static cpio)
#   scripts/vcan_vm.sh STATIC_BIN [DIR] boot, insmod can/can-raw/can-dev/vcan, bring vcan0 up, run
#                                      STATIC_BIN, exit with its status (console in $VCAN_VM_LOG);
#                                      DIR's files join the VM's root, and its app_test.sh runs next
# The kernel package is downloaded once (apt-get download) and unpacked under
# ${KELP_VCAN_CACHE:-build/vcanvm}; reruns reuse it.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
CACHE=${KELP_VCAN_CACHE:-$ROOT/build/vcanvm}
VCAN_VM_PKGS="qemu-system-x86 busybox-static cpio"

vcan_vm_deps() {
  missing=""
  for p in $VCAN_VM_PKGS; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing="$missing $p"
  done
  [ -z "$missing" ] && return 0
  SUDO=; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  echo "vcan_vm: installing$missing"
  $SUDO apt-get update -q >/dev/null 2>&1 || true
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends $missing >/dev/null
}

vcan_vm_kernel() {
  mkdir -p "$CACHE"
  [ -d "$CACHE/kroot/lib/modules" ] && return 0
  KPKG=$(apt-cache depends linux-image-amd64 | awk '/Depends: linux-image-[0-9]/{print $2; exit}')
  [ -n "$KPKG" ] || { echo "vcan_vm: no linux-image package known to apt (apt-get update?)"; return 1; }
  (cd "$CACHE" && rm -f ./*.deb && apt-get download "$KPKG" >/dev/null 2>&1 && dpkg-deb -x "$KPKG"_*.deb kroot.tmp \
    && mv kroot.tmp kroot && rm -f ./*.deb) || { echo "vcan_vm: cannot download $KPKG"; return 1; }
}

if [ "${1:-}" = "--deps" ]; then
  vcan_vm_deps
  exit $?
fi
[ $# -ge 1 ] || { echo "usage: $0 --deps | STATIC_TEST_BIN [EXTRA_DIR]"; exit 2; }
TEST=$(readlink -f "$1")
vcan_vm_deps
vcan_vm_kernel
KVER=$(ls "$CACHE/kroot/lib/modules" | head -1); M=$CACHE/kroot/lib/modules/$KVER/kernel
W=$(mktemp -d "${TMPDIR:-/tmp}/vcanvm.XXXXXX")
trap 'rm -rf "$W"' EXIT
mkdir -p "$W/ir/bin" "$W/ir/lib/modules" "$W/ir/proc" "$W/ir/sys" "$W/ir/dev" "$W/ir/tmp"
cp /bin/busybox "$W/ir/bin/"
cp "$M/net/can/can.ko" "$M/net/can/can-raw.ko" "$M/drivers/net/can/dev/can-dev.ko" "$M/drivers/net/can/vcan.ko" \
  "$W/ir/lib/modules/"
cp "$TEST" "$W/ir/bin/cantest"
# EXTRA_DIR: more files for the VM's root; its app_test.sh (if any) runs after the test program
[ -n "${2:-}" ] && cp -a "$2"/. "$W/ir/"
cat > "$W/ir/init" <<'EOS'
#!/bin/busybox sh
/bin/busybox --install -s /bin
mount -t proc proc /proc; mount -t sysfs sys /sys; mount -t devtmpfs dev /dev 2>/dev/null
for m in can can-raw can-dev vcan; do insmod /lib/modules/$m.ko || echo "insmod $m failed"; done
ip link set lo up
ip link add dev vcan0 type vcan && ip link set vcan0 up
ip link show vcan0
/bin/cantest; echo "CANTEST_EXIT=$?"
if [ -f /app_test.sh ]; then
  ip link show vcan0 >/dev/null 2>&1 || { ip link add dev vcan0 type vcan; ip link set vcan0 up; }
  sh /app_test.sh; echo "APPTEST_EXIT=$?"
fi
poweroff -f
EOS
chmod +x "$W/ir/init"
(cd "$W/ir" && find . | cpio -o -H newc 2>/dev/null | gzip -1) > "$W/initrd.gz"
LOG=${VCAN_VM_LOG:-$W/console.log}
timeout "${VCAN_VM_TIMEOUT:-170}" qemu-system-x86_64 -accel tcg -cpu max -m 256 -nographic -no-reboot \
  -kernel "$CACHE/kroot/boot/vmlinuz-$KVER" -initrd "$W/initrd.gz" -append "console=ttyS0 panic=-1 quiet" 2>&1 \
  | tr -d '\r' > "$LOG" || true
cat "$LOG"
grep -q '^CANTEST_EXIT=0' "$LOG"
