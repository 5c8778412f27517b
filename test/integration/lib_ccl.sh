# Helpers of test/integration/basic_ccl.sh, ccl_and_dccl.sh and btr_ctd.sh: the seed's two example
# deployments (Goby 1.1 section 2.3.15, missions/basic_ccl, missions/ccl_and_dccl) run from
# their unchanged mission files.  Those name the fixed paths /tmp/ttyLOOP{A,B}{1,2} and the
# fixed bus ports 9101, 9102 (ServerPort) and 49234 (iModemSim's IPPort): the test runs in its
# own mount namespace with a private /tmp (and, from lib.sh, its own network namespace), so
# that nothing it makes is seen by, or collides with, anything else on the machine.
# Source this BEFORE lib.sh.
if [ -z "${KELP_PRIVATE_TMP:-}" ]; then
  export KELP_PRIVATE_TMP=1
  if [ "$(id -u)" -eq 0 ]; then exec unshare -m bash "$0" "$@"; else exec unshare -rm bash "$0" "$@"; fi
fi
# the checkout or the build may themselves live under /tmp (a CI clone there): the old /tmp is
# bound on /mnt (in this namespace only) and those directories bound back into the new /tmp
if [ "$KELP_PRIVATE_TMP" = 1 ]; then # once: lib.sh's network namespace re-runs the script
export KELP_PRIVATE_TMP=done
ccl_keep=()
for d in "$(cd "$(dirname "$0")/../.." && pwd)" "${KELP_ROOT:-}" "${BUILD:-}"; do
  case "$d" in /tmp/*) ccl_keep+=("$d") ;; esac
done
if [ ${#ccl_keep[@]} -gt 0 ]; then
  mount --bind /tmp /mnt || { echo "FAIL: cannot keep the old /tmp on /mnt"; exit 1; }
fi
mount -t tmpfs tmpfs /tmp || { echo "FAIL: cannot make a private /tmp"; exit 1; }
for d in "${ccl_keep[@]}"; do
  mkdir -p "$d" && mount --bind "/mnt${d#/tmp}" "$d" || { echo "FAIL: cannot keep $d"; exit 1; }
done
fi

# run_pair MISSION_DIR SECONDS: copy the mission, make the loopbacks, record both communities'
# buses, launch mm1 and mm2 for SECONDS; printed bus logs in $T/mm1.txt, $T/mm2.txt
run_pair() {
  local dir=$1 secs=$2
  cp $dir/* .
  sh ./loopbacks
  unset KELP_LCM_URL # each community on its ServerPort
  bg $BIN/kelp-record --lcm-url="udpm://239.255.76.67:9101?ttl=0" -f mm1.lcm -q
  bg $BIN/kelp-record --lcm-url="udpm://239.255.76.67:9102?ttl=0" -f mm2.lcm -q
  sleep 0.3
  $BIN/kelp-launch --run-seconds $secs --log-dir logs.mm1 mm1.moos > launch.mm1 2>&1 & local L1=$!
  $BIN/kelp-launch --run-seconds $secs --log-dir logs.mm2 mm2.moos > launch.mm2 2>&1 & local L2=$!
  PIDS+=($L1 $L2)
  wait $L1 || { cat launch.mm1; tail -n 20 logs.mm1/*; fail "mm1: launcher failed"; }
  wait $L2 || { cat launch.mm2; tail -n 20 logs.mm2/*; fail "mm2: launcher failed"; }
  sleep 0.3
  kill ${PIDS[-4]} ${PIDS[-3]} 2>/dev/null || true
  sleep 0.3
  # (kelp-logcheck exits 1 because the structured ACOMMS_*_LCM channels are not kelp vars)
  $BIN/kelp-logcheck mm1.lcm --print > mm1.txt || true
  $BIN/kelp-logcheck mm2.lcm --print > mm2.txt || true
  [ -z "${CCL_KEEP:-}" ] || cp -r $T/. $CCL_KEEP/ # (the private /tmp goes with the test)
  [ -s mm1.txt ] && [ -s mm2.txt ] || fail "empty bus logs"
}

# values of a variable in a printed log ("time source NAME value")
vals() { awk -v v=$2 '$3 == v { $1 = $2 = $3 = ""; sub(/^ +/, ""); print }' $1; }
# sources of a variable in a printed log
srcs() { awk -v v=$2 '$3 == v { print $2 }' $1; }
