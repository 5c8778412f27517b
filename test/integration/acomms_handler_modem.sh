#!/usr/bin/env bash
# pAcommsHandler (DRIVER_WHOI_MICROMODEM) against a scripted fake Micro-Modem on a socat pty pair.
#  1. start-up: $CCCLK, $CCCFG,SRC,1, $CCCFG,<nvram>, $CCCFQ,ALL answered as a modem does
#  2. garbage (a non-NMEA line, a bad checksum) is reported and ignored
#  3. OUTGOING_COMMAND (a GoToCommand trigger) poked on the bus -> at the 2 s TDMA slot $CCCYC,
#     the modem's $CADRQ -> $CCTXD whose hex equals kelp-dccl's encoding at the header time
#  4. $CAACK from modem 2 -> ACOMMS_ACK; $CARXD of a VehicleStatus -> STATUS_SUMMARY published
#  5. silence: the modem stops answering -> retries, give-up, "not responding" -> the link is
#     re-opened and the start-up sequence runs again; the unacknowledged message is sent after
#  6. the device disappears (socat killed) and comes back under the same name: the handler
#     reconnects, re-runs the start-up, and a message poked while the device was gone is sent
. "$(dirname "$0")/lib.sh"
# stdbuf (and the pty shim) are LD_PRELOADs: let an ASan build (make asan) accept them
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
cd "$T"
cp "$KELP_ROOT/missions/acomms/example1.xml" .
command -v socat >/dev/null || fail "socat not installed"

cat > mm.moos <<EOF
Community = mm1
ProcessConfig = pAcommsHandler
{
  AppTick = 10
  common { verbosity: VERBOSITY_DEBUG }
  modem_id: 1
  driver_type: DRIVER_WHOI_MICROMODEM
  driver_cfg {
    connection_type: CONNECTION_SERIAL
    serial_port: "$T/ttyA"
    serial_baud: 19200
    [MicroModemConfig.reset_nvram]: false
    [MicroModemConfig.nvram_cfg]: "dto,2"
  }
  mac_cfg { type: MAC_FIXED_DECENTRALIZED
            slot { src: 1 dest: 2 rate: 0 type: SLOT_DATA slot_seconds: 2 } }
  queue_cfg { message_file { path: "example1.xml" } }
}
EOF

# the fake modem (bash, run by socat on the other side of the pty): answers like a WHOI
# Micro-Modem; lines appended to $T/inject are sent as if the modem produced them
cp "$KELP_ROOT/test/shim/fake_modem.sh" fakemodem.sh
cks() { local s=$1 c=0 i o; for ((i = 0; i < ${#s}; i++)); do printf -v o '%d' "'${s:i:1}"; c=$((c ^ o)); done; printf '%02X' $c; }
inject() { echo "$1" >> "$T/inject"; }
# wait until a $CCTXD carried a GoToCommand with this goto_x (decoded independently)
wait_txd() {
  local x=$1 s=$2 i h
  for ((i = 0; i < s * 10; i++)); do
    for h in $(grep '^20' "$T/txd.log" 2>/dev/null); do
      "$BIN/kelp-dccl" decode --xml example1.xml "$h" | grep -q "^goto_x=$x\$" && { echo "$h"; return 0; }
    done
    sleep 0.1
  done
  return 1
}
start_modem() {
  rm -f "$T/inject"
  socat pty,raw,echo=0,link="$T/ttyA" EXEC:"bash $T/fakemodem.sh $T" 2>>"$T/socat.err" & SOCAT=$!
  PIDS+=($SOCAT)
  for _ in $(seq 50); do [ -e "$T/ttyA" ] && return 0; sleep 0.1; done
  fail "socat did not create the pty"
}

echo normal > mode
start_modem
sleep 0.3
"$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f "$T/bus.lcmlog" >/dev/null 2>&1 & PIDS+=($!)
sleep 1   # the logger must be listening before the handler's start-up writes
stdbuf -oL "$BIN/pAcommsHandler" --verbose mm.moos > h.out 2>&1 & H=$!; PIDS+=($H)

# 1. start-up sequence
wait_for modem.log '^> \$CCCFQ,ALL\*' 10 || { cat modem.log; tail -30 h.out; fail "no start-up sequence"; }
grep -q '^> \$CCCLK,[0-9]\{4\},' modem.log || fail "no \$CCCLK"
grep -q '^> \$CCCFG,SRC,1\*' modem.log || fail "no \$CCCFG,SRC,1"
grep -q '^> \$CCCFG,DTO,2\*' modem.log || fail "nvram_cfg not sent upper-cased"
grep -q '^> \$CCCFG,ALL,0' modem.log && fail "reset_nvram false but \$CCCFG,ALL,0 sent"
ok "start-up: CLK, CFG SRC,1, CFG DTO,2, CFQ ALL"

# 2. garbage
inject 'this is not nmea'
inject '$CARXD,2,1,0,1,2000*00'
sleep 0.5

# 3. a DCCL message triggered on the bus
"$BIN/kelp-poke" mm.moos "OUTGOING_COMMAND:=Destination=2,CommandType=GoTo,goto_x=351,goto_y=294,lights_on=true,goto_speed=2.3" > poke.out
wait_for txd.log '^20' 10 || { cat modem.log; tail -40 h.out; fail "no \$CCTXD with DCCL data"; }
hex=$(grep '^20' txd.log | head -1)
grep -q '^> \$CCCYC,0,1,2,0,1,1\*' modem.log || fail "cycle not \$CCCYC,0,1,2,0,1,1"
grep -q "^> \\\$CCTXD,1,2,1,$hex\\*" modem.log || fail "\$CCTXD not 1,2,1,<hex>"
# header time (17 bits after 8+9) -> UNIX time of today, then encode the same message independently
tod=$(( (16#${hex:2:8} >> 6) & 0x1FFFF ))
midnight=$(( $(date -u +%s) / 86400 * 86400 ))
[ $(( $(date -u +%s) - midnight )) -lt $tod ] && midnight=$((midnight - 86400))
exp=$("$BIN/kelp-dccl" encode --xml example1.xml --msg GoToCommand --modem-id 1 --now $((midnight + tod)) \
      Destination=2 goto_x=351 goto_y=294 lights_on=true goto_speed=2.3)
[ "$hex" = "$exp" ] || fail "TXD hex $hex != kelp-dccl $exp"
dec=$("$BIN/kelp-dccl" decode --xml example1.xml --now $((midnight + tod)) "$hex")
echo "$dec" | grep -q "goto_x=351" && echo "$dec" | grep -q "_dest_id=2\|Destination=2" || { echo "$dec"; fail "decoded fields wrong"; }
ok "\$CCTXD,1,2,1,$hex = kelp-dccl encoding (tod $tod)"

# 4. ack and a received frame
wait_for h.out 'ack from 2 for GoToCommand' 12 || { tail -40 h.out; fail "no ACOMMS_ACK event"; }
vs=$("$BIN/kelp-dccl" encode --xml example1.xml --msg VehicleStatus --modem-id 2 nav_x=100 nav_y=300 health=low_battery)
inject "\$CARXD,2,1,0,1,$vs*$(cks "CARXD,2,1,0,1,$vs")"
sleep 1

# 5. silence: the modem stops answering (the $CCCLKs counted before it: the restart's may
#    come right after "not responding" is logged)
n_clk_before=$(grep -c '^> \$CCCLK' modem.log || true)
echo silent > mode
"$BIN/kelp-poke" mm.moos "OUTGOING_COMMAND:=Destination=2,CommandType=GoTo,goto_x=1000,goto_y=2000,lights_on=false,goto_speed=1" > poke2.out
wait_for h.out 'modem not responding' 40 || { tail -40 h.out; tail -20 modem.log; fail "silence not detected"; }
echo normal > mode
hex2=$(wait_txd 1000 20) || { tail -40 h.out; tail -30 modem.log; fail "message not sent after the modem came back"; }
[ "$(grep -c '^> \$CCCLK' modem.log)" -gt "$n_clk_before" ] || fail "no start-up after the silence"
ok "silence: detected, link re-opened, start-up re-run, queued message sent ($hex2)"

# 6. the device disappears and comes back
kill $SOCAT 2>/dev/null || true
wait $SOCAT 2>/dev/null || true
rm -f "$T/ttyA"
wait_for h.out 'modem link lost' 15 || { tail -30 h.out; fail "loss of the device not reported"; }
"$BIN/kelp-poke" mm.moos "OUTGOING_COMMAND:=Destination=2,CommandType=GoTo,goto_x=4321,goto_y=1234,lights_on=true,goto_speed=0.5" > poke3.out
sleep 3   # slots pass while the device is gone: nothing may be taken from the queue
start_modem
wait_for h.out 'modem link re-established' 15 || { tail -30 h.out; fail "no reconnection"; }
hex3=$(wait_txd 4321 20) || { tail -40 h.out; tail -30 modem.log; fail "message poked while the device was gone was lost"; }
ok "device removed and recreated: reconnected, message kept and sent ($hex3)"

kill $H; wait $H 2>/dev/null || true
sleep 0.3
"$BIN/kelp-logcheck" bus.lcmlog --print > bus.txt 2> logcheck.err || true
grep -q 'STATUS_SUMMARY .*nav_x=100.0,nav_y=300.0,health=low_battery' bus.txt || { grep STATUS bus.txt; fail "received VehicleStatus not published"; }
grep -q 'ACOMMS_ACK .*orig_msg' bus.txt || fail "no ACOMMS_ACK on the bus"
grep -q 'ACOMMS_NMEA_OUT .*\$CCCYC' bus.txt || fail "no ACOMMS_NMEA_OUT"
grep -q 'ACOMMS_NMEA_IN .*\$CADRQ' bus.txt || fail "no ACOMMS_NMEA_IN"
grep -q 'ACOMMS_INCOMING_DATA .*src: 2 dest: 1' bus.txt || fail "no ACOMMS_INCOMING_DATA"
grep -q 'ACOMMS_OUTGOING_DATA ' bus.txt || fail "no ACOMMS_OUTGOING_DATA"
grep -q 'bad line from the modem' h.out || fail "garbage not reported"
ok "bus: STATUS_SUMMARY, ACOMMS_ACK, NMEA in/out, incoming/outgoing data; garbage reported"
