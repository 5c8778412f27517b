# Helpers of test/integration/acomms_e2e*.sh (sourced after test/integration/lib.sh, in $T).
# Two communities on two LCM URLs plus the acoustic channel on a third, from the templates
# topside.moos and auv.moos; `run` launches both with kelp-launch, pokes the GoToCommands into
# the topside and leaves the printed bus logs of each community in $T/<name>.mm1.txt / .mm2.txt.
[ -x $BIN/pAcommsHandler ] || fail "pAcommsHandler is not built"
M=$KELP_ROOT/missions/acomms_e2e
cp $M/*.xml .
base=${KELP_LCM_URL%%\?*}; base=${base%:*}
URL1="$base:$((TEST_PORT + 1))?ttl=0"
URL2="$base:$((TEST_PORT + 2))?ttl=0"
CHAN="$base:$((TEST_PORT + 3))?ttl=0"
unset KELP_LCM_URL # each community has its own URL (the missions' LCM_URL)

# mission TEMPLATE OUT URL: fill a template with LOSS GOTO RATE SLOT (variables set by the test)
mission() {
  sed -e "s|@URL@|$3|; s|@CHAN@|$CHAN|; s|@DIR@|$T|g; s|@LOSS@|$LOSS|; s|@GOTO@|$GOTO|g; s|@RATE@|$RATE|g" \
      -e "s|@SLOT@|$SLOT|g" $M/$1 > $T/$2
}

# run NAME SECONDS NCOMMANDS SPACING, with LOSS GOTO RATE SLOT set (and TOPSIDE / AUV naming other
# templates than topside.moos / auv.moos, and TOPSIDE_ENV environment assignments for the
# topside's processes, e.g. KELP_CLOCK_STEPS): the vehicle for SECONDS and
# the topside 6 s longer (so that whatever the vehicle sent has landed), the GoToCommands
# goto_x=101.. poked into the topside SPACING s apart after start-up
run() {
  local name=$1 secs=$2 n=$3 gap=$4 k
  mission ${TOPSIDE:-topside.moos} topside$name.moos "$URL1"
  mission ${AUV:-auv.moos} auv$name.moos "$URL2"
  bg lcm-logger --lcm-url="$URL1" -f $name.mm1.lcm -q
  bg lcm-logger --lcm-url="$URL2" -f $name.mm2.lcm -q
  sleep 0.3
  env ${TOPSIDE_ENV:-} $BIN/kelp-launch --run-seconds $((secs + 6)) --log-dir logs.$name.mm1 topside$name.moos > launch.$name.mm1 2>&1 & local L1=$!
  $BIN/kelp-launch --run-seconds $secs --log-dir logs.$name.mm2 auv$name.moos > launch.$name.mm2 2>&1 & local L2=$!
  PIDS+=($L1 $L2)
  sleep 4 # start-up: $CCCLK, $CCCFG,SRC, $CCCFQ,ALL on both links
  for ((k = 1; k <= n; k++)); do
    $BIN/kelp-poke topside$name.moos \
      "OUTGOING_COMMAND:=Destination=2,CommandType=GoTo,goto_x=$((100 + k)),goto_y=294,lights_on=true,special_instructions=make_toast,goto_speed=2.3" > /dev/null
    sleep $gap
  done
  wait $L1 || { cat launch.$name.mm1; fail "$name: topside launcher failed"; }
  wait $L2 || { cat launch.$name.mm2; fail "$name: vehicle launcher failed"; }
  sleep 0.3
  kill ${PIDS[-4]} ${PIDS[-3]} 2>/dev/null || true
  sleep 0.3
  # (kelp-logcheck exits 1 because the structured ACOMMS_*_LCM channels are not kelp vars)
  $BIN/kelp-logcheck $name.mm1.lcm --print > $name.mm1.txt || true
  $BIN/kelp-logcheck $name.mm2.lcm --print > $name.mm2.txt || true
  [ -s $name.mm1.txt ] && [ -s $name.mm2.txt ] || fail "$name: empty bus logs"
}

# values of a variable in a printed log ("time source NAME value")
vals() { awk -v v=$2 '$3 == v { $1 = $2 = $3 = ""; sub(/^ +/, ""); print }' $1; }
# the data field of ModemDataTransmission text (of orig_msg for ACOMMS_ACK / ACOMMS_EXPIRE)
data_of() { sed -n 's/.* data: "\(.*\)" frame: .*/\1/p'; }
# message number (1..N, push order at the topside) of each ACOMMS_ACK / ACOMMS_EXPIRE
numbers() { # log var
  vals $1 ACOMMS_OUTGOING_DATA | data_of > pushed.txt
  vals $1 $2 | data_of | while IFS= read -r d; do grep -nxF -- "$d" pushed.txt | cut -d: -f1; done
}

# the DCCL messages inside each $CCTXD the topside wrote (stitched frames split as Goby 1.1
# does): one line per message transmission, the message's header bytes 1..4 in hex (unique per
# message: id, time of day, src)
sent_messages() {
  vals $1 ACOMMS_NMEA_OUT | grep '^\$CCTXD,' | sed 's/\*..$//' | awk -F, '{ print $5 }' | awk '
    function byte(i,  h) { h = tolower(substr($0, 2 * i + 1, 2))
                           return (index("0123456789abcdef", substr(h, 1, 1)) - 1) * 16 + index("0123456789abcdef", substr(h, 2, 1)) - 1 }
    length($0) >= 12 && substr($0, 1, 2) == "20" {
      n = length($0) / 2; p = 1
      while (p + 5 <= n) {
        print substr($0, 2 * p + 1, 8)
        if (int(byte(p + 4) / 8) % 2 == 0) break # multimessage flag (0x08) clear: the last one
        p += 6 + byte(p + 5)                     # 5 header bytes, 1 length byte, the body
      }
    }'
}
