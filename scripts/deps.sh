#!/usr/bin/env bash
# Install the Debian packages kelp needs, only those missing. Usage: deps.sh build|test|ci|all
# Uses sudo when not root. Set KELP_NO_APT=1 to skip.
set -euo pipefail
what=${1:-build}
BUILD_PKGS="build-essential pkg-config liblcm-dev liblcm-bin liblcm-java libglib2.0-dev libserialport-dev
 check libexpat1-dev libmbedtls-dev libncurses-dev libcairo2-dev libsqlite3-dev libmicrohttpd-dev socat iproute2 procps"
# lcm-spy (kelp-spy, test spy_xvfb): a JDK (make spy-jar compiles kelp_types.jar), the full JRE
# (lcm-spy is a Swing program: the headless one lacks AWT's X11 library) and jchart2d (the detail
# view's plots); the test runs it under Xvfb, drives it with xdotool, screenshots with ImageMagick
SPY_PKGS="default-jdk-headless default-jre libjchart2d-java xvfb xauth imagemagick xdotool"
TEST_PKGS="$BUILD_PKGS $SPY_PKGS bc valgrind python3 tmux qemu-system-x86 busybox-static cpio sqlite3 libxml2-utils
 chromium chromium-driver python3-selenium"
CI_PKGS="$TEST_PKGS clang libclang-rt-14-dev cppcheck clang-tidy
 gcc-arm-none-eabi libnewlib-arm-none-eabi gcc-aarch64-linux-gnu libc6-dev-arm64-cross
 gcc-arm-linux-gnueabihf libc6-dev-armhf-cross qemu-user"
case "$what" in
  build) pkgs=$BUILD_PKGS ;;
  test) pkgs=$TEST_PKGS ;;
  ci|all) pkgs=$CI_PKGS ;;
  *) echo "deps.sh: unknown set '$what'" >&2; exit 2 ;;
esac
[ "${KELP_NO_APT:-0}" = 1 ] && exit 0
missing=()
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
SUDO=; [ "$(id -u)" -ne 0 ] && SUDO=sudo
echo "deps.sh: installing ${missing[*]}"
# a mirror caught mid-sync makes "update" fail on one index; retry, then go on with what we have
for try in 1 2 3; do
  $SUDO apt-get -o DPkg::Lock::Timeout=300 update -q >/dev/null 2>&1 && break
  echo "deps.sh: apt-get update failed (try $try), retrying"; sleep 5
done
for try in 1 2; do
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get -o DPkg::Lock::Timeout=300 install -y -q --no-install-recommends "${missing[@]}" >/dev/null && exit 0
  echo "deps.sh: apt-get install failed (try $try)"; sleep 5; $SUDO apt-get update -q >/dev/null 2>&1 || true
done
echo "deps.sh: could not install: ${missing[*]}" >&2
exit 1
