# pGeneralCodec (deprecated in Goby 1.1 for "pAcommsHandler with no driver, no MAC and no
# queuing", seed 002 section 2.10): a launcher line "Run = pGeneralCodec" starts pAcommsHandler
# under that name, reading ProcessConfig = pGeneralCodec, as a DCCL codec only.  It encodes
# SIMPLE_STATUS (time trigger, 5 s) from its initializers to OUT_SIMPLE_STATUS_HEX_32B and
# nothing else: no modem, no queue (ACOMMS_QSIZE), no loopback delivery; the hex written back
# by another process on IN_SIMPLE_STATUS_HEX_32B is decoded into STATUS_REPORT_IN.
. "$(dirname "$0")/lib.sh"
cd $T
cp $KELP_ROOT/missions/ccl_and_dccl/simple_status.xml $KELP_ROOT/missions/ccl_and_dccl/modemidlookup.txt .
cat > codec.moos <<'M'
Community  = mm1
LatOrigin  = 42.35
LongOrigin = -70.95
modem_id_lookup_path = modemidlookup.txt

ProcessConfig = ANTLER
{
  MSBetweenLaunches = 10
  Run = MOOSDB @ NewConsole = false
  Run = pGeneralCodec @ NewConsole = false
}

ProcessConfig = pGeneralCodec
{
  common {
    initializer { type: INI_STRING moos_var: "VEHICLE_NAME" sval: "mm1" }
    initializer { type: INI_DOUBLE moos_var: "NAV_X" dval: 100 }
    initializer { type: INI_DOUBLE moos_var: "NAV_Y" dval: 300 }
    initializer { type: INI_DOUBLE moos_var: "NAV_HEADING" dval: 150 }
    initializer { type: INI_DOUBLE moos_var: "NAV_SPEED" dval: 0 }
    initializer { type: INI_DOUBLE moos_var: "NAV_DEPTH" dval: 0 }
  }
  modem_id: 1
  dccl_cfg { message_file { path: "simple_status.xml" } }
}
M
bg $BIN/kelp-record --lcm-url="$KELP_LCM_URL" -f codec.lcm -q
sleep 0.3
$BIN/kelp-launch --run-seconds 12 --log-dir logs codec.moos > launch.out 2>&1 & L=$!
PIDS+=($L)
sleep 7
# the encoded message, written back as another process would (a bridge, a different link)
$BIN/kelp-logcheck codec.lcm --print > early.txt 2>/dev/null || true
hex=$(awk '$3 == "OUT_SIMPLE_STATUS_HEX_32B" { $1 = $2 = $3 = ""; sub(/^ +/, ""); print; exit }' early.txt)
[ -n "$hex" ] || { cat launch.out; tail -n 30 logs/*; fail "no OUT_SIMPLE_STATUS_HEX_32B"; }
$BIN/kelp-poke codec.moos "IN_SIMPLE_STATUS_HEX_32B:=$hex" > /dev/null
wait $L || { cat launch.out; fail "launcher failed"; }
kill ${PIDS[-2]} 2>/dev/null || true
sleep 0.3
$BIN/kelp-logcheck codec.lcm --print > log.txt || true
grep -q 'started pGeneralCodec *as pGeneralCodec' launch.out || { cat launch.out; fail "pGeneralCodec not launched"; }
[ "$(awk '$3 == "OUT_SIMPLE_STATUS_HEX_32B" { print $2 }' log.txt | sort -u)" = pGeneralCodec ] || fail "encoder's name"
n=$(grep -c ' OUT_SIMPLE_STATUS_HEX_32B ' log.txt)
[ "$n" -ge 2 ] || fail "$n SIMPLE_STATUS encoded in 12 s (trigger_time 5)"
grep -q 'Configuration warnings: 0' logs/pGeneralCodec.log || { tail -n 30 logs/pGeneralCodec.log; fail "configuration warnings"; }
# nothing queued, sent or looped back
! grep ' ACOMMS_QSIZE ' log.txt | grep -qv 'size: 0$' || fail "a message was queued"
for v in ACOMMS_NMEA_OUT ACOMMS_INCOMING_DATA ACOMMS_ACK; do
  ! grep -q " $v " log.txt || fail "$v published by a codec"
done
# decoded: exactly the one poked back
s=$(awk '$3 == "STATUS_REPORT_IN"' log.txt)
[ "$(echo "$s" | grep -c .)" = 1 ] || { echo "$s"; fail "STATUS_REPORT_IN count"; }
echo "$s" | grep -q 'pGeneralCodec STATUS_REPORT_IN .*MessageType=LAMSS_STATUS.*nav_x=100.*nav_y=300' || { echo "$s"; fail "STATUS_REPORT_IN content"; }
ok "pGeneralCodec: pAcommsHandler under that name encoded $n SIMPLE_STATUS, queued and sent nothing, decoded the one written back"
