#!/usr/bin/env bash
# Cross-build the core and its unit tests for ARCH (aarch64 | armhf) and run them under qemu-user.
# Check for the target is taken from Debian's foreign-arch .debs, extracted into a sysroot
# (installing them would fight the native liblcm; see the platform notes).
set -euo pipefail
cd "$(dirname "$0")/.."
ARCH=${1:-aarch64}
case "$ARCH" in
  aarch64) TRIPLE=aarch64-linux-gnu; DEB=arm64; QEMU=qemu-aarch64 ;;
  armhf)   TRIPLE=arm-linux-gnueabihf; DEB=armhf; QEMU=qemu-arm ;;
  *) echo "cross: ARCH must be aarch64 or armhf" >&2; exit 2 ;;
esac
command -v $TRIPLE-gcc >/dev/null || scripts/deps.sh ci
O=build-cross-$ARCH
SYS=$O/sysroot
if [ ! -f "$SYS/.done" ]; then
  mkdir -p "$SYS/debs"
  SUDO=; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  SUDO_U=$SUDO
  if ! dpkg --print-foreign-architectures | grep -qx $DEB; then
    $SUDO dpkg --add-architecture $DEB
  fi
  # a mirror mid-sync can fail one index; retry, and go on if the packages can be fetched
  for try in 1 2 3; do $SUDO_U apt-get update -q >/dev/null 2>&1 && break; sleep 5; done
  chmod 777 "$SYS/debs"
  (cd "$SYS/debs" && apt-get download -q check:$DEB libsubunit-dev:$DEB libsubunit0:$DEB >/dev/null)
  for d in "$SYS"/debs/*.deb; do dpkg-deb -x "$d" "$SYS"; done
  touch "$SYS/.done"
fi
LIBDIR=$SYS/usr/lib/$TRIPLE
make --no-print-directory BUILD=$O CC=$TRIPLE-gcc AR=$TRIPLE-ar $O/libkelp_core.a $O/gen/core_suites.h >/dev/null
$TRIPLE-gcc -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -O2 -g -Wall -Wextra -Werror -Wno-missing-prototypes -Iinclude -Itest -I$O/gen -I$SYS/usr/include \
  -DKELP_SUITES='"core_suites.h"' -DKELP_RUNNER_NAME='"core-'$ARCH'"' -static \
  -o $O/check_core test/check_main.c $(ls test/check_*.c | grep -v check_main.c) $(ls test/fakes/*.c 2>/dev/null) $O/libkelp_core.a -L$LIBDIR -lcheck -lsubunit -lm -lrt -pthread
file $O/check_core | sed 's/,.*//'
# qemu-user runs the code 5-20x slower than the host (more on a loaded one): Check's per-test
# timeout (4 s) is scaled so that the long randomized checks (200,000 numbers against strtod) finish
CK_TIMEOUT_MULTIPLIER=${CK_TIMEOUT_MULTIPLIER:-15} scripts/run-suites.sh ./$O/check_core $QEMU
