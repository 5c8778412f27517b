# Helpers of test/integration/commander*.sh (sourced after lib.sh and e2e_lib.sh, in $T): the
# acomms_e2e topside and vehicle, the topside with an iCommander block loading goto.xml.
LOSS=0 GOTO=goto.xml RATE=2 SLOT=5
# start NAME SECONDS: both communities (the topside 4 s longer), bus logs NAME.mm1.lcm / .mm2.lcm
start() {
  local name=$1 secs=$2
  mission topside.moos topside$name.moos "$URL1"
  cat >> topside$name.moos <<'MOOS'

ProcessConfig = iCommander
{
  common { verbosity: VERBOSITY_VERBOSE }
  dccl_cfg { modem_id: 1 message_file { path: "goto.xml" } }
  show_variable: "ACOMMS_QSIZE"
}
MOOS
  mission auv.moos auv$name.moos "$URL2"
  bg lcm-logger --lcm-url="$URL1" -f $name.mm1.lcm -q
  bg lcm-logger --lcm-url="$URL2" -f $name.mm2.lcm -q
  sleep 0.3
  $BIN/kelp-launch --run-seconds $((secs + 4)) --log-dir logs.$name.mm1 topside$name.moos > launch.$name.mm1 2>&1 & L1=$!
  $BIN/kelp-launch --run-seconds $secs --log-dir logs.$name.mm2 auv$name.moos > launch.$name.mm2 2>&1 & L2=$!
  PIDS+=($L1 $L2)
  sleep 4 # modem start-up on both links
}
# finish NAME: wait for both launchers, print the bus logs to NAME.mm1.txt / NAME.mm2.txt
finish() {
  local name=$1
  wait $L1 || { cat launch.$name.mm1; fail "$name: topside launcher failed"; }
  wait $L2 || { cat launch.$name.mm2; fail "$name: vehicle launcher failed"; }
  sleep 0.3
  kill ${PIDS[-4]} ${PIDS[-3]} 2>/dev/null || true
  sleep 0.3
  $BIN/kelp-logcheck $name.mm1.lcm --print > $name.mm1.txt || true
  $BIN/kelp-logcheck $name.mm2.lcm --print > $name.mm2.txt || true
}
