# The seed's example 2, "DCCL and CCL" (Goby 1.1 section 2.3.15; missions/ccl_and_dccl), run
# from the seed's mission files (iModemSim started as kelp-modemsim, MOOSDB skipped; only the
# XML's path differs).  TDMA: slot 1 -> 2, then 2 -> 1, 10 s each.  mm1 (topside) encodes the
# DCCL SIMPLE_STATUS every 5 s from its initializers and sends it down; mm2 (auv) decodes it
# (NO_ENCODE) into STATUS_REPORT_IN and NODE_REPORT.  mm2's pREMUSCodec (create_status) makes
# a REMUS CCL State (first byte 14) from its NAV_* on OUT_REMUS_STATUS, sent up on CCL queue
# 14; mm1 publishes IN_REMUS_STATUS and its pREMUSCodec turns the State into a NODE_REPORT.
. "$(dirname "$0")/lib_ccl.sh"
. "$(dirname "$0")/lib.sh"
cd $T
run_pair $KELP_ROOT/missions/ccl_and_dccl 46
for c in mm1 mm2; do
  grep -q ' ACOMMS_NMEA_IN \$CACFG,SRC,' $c.txt || fail "$c: start-up never answered by the modem"
done
# downlink: SIMPLE_STATUS (DCCL id 20) from mm1, decoded on mm2 and never encoded there
vals mm1.txt ACOMMS_OUTGOING_DATA | grep -q 'queue_key { type: QUEUE_DCCL id: 20 }' || fail "mm1 queued no SIMPLE_STATUS"
! vals mm2.txt ACOMMS_OUTGOING_DATA | grep -q 'QUEUE_DCCL' || fail "mm2 encoded SIMPLE_STATUS (NO_ENCODE)"
vals mm2.txt ACOMMS_INCOMING_DATA | grep -q '^base { src: 1 .*queue_key { type: QUEUE_DCCL id: 20 }' ||
  { vals mm2.txt ACOMMS_INCOMING_DATA; fail "no SIMPLE_STATUS arrived on mm2"; }
vals mm2.txt STATUS_REPORT_IN > status.txt
[ -s status.txt ] || fail "no STATUS_REPORT_IN on mm2"
grep -q 'MessageType=LAMSS_STATUS' status.txt && grep -q 'nav_x=100' status.txt && grep -q 'nav_y=300' status.txt &&
  grep -q 'Node=1' status.txt || { cat status.txt; fail "STATUS_REPORT_IN content"; }
vals mm2.txt NODE_REPORT > nr2.txt
grep -qE '^NAME=mm1,TYPE=topside,UTC_TIME=[0-9.]+,X=100,Y=300,LAT=42\.35[0-9]*,LON=-70\.94[0-9]*,SPD=0(\.0)?,HDG=150(\.0+)?,DEPTH=0(\.0)?$' nr2.txt ||
  { cat nr2.txt; fail "mm2's NODE_REPORT of mm1"; }
# uplink: REMUS State (CCL id 14) from mm2's pREMUSCodec, into mm1's NODE_REPORT
vals mm2.txt OUT_REMUS_STATUS | grep -q 'data: "\\016' || { vals mm2.txt OUT_REMUS_STATUS; fail "mm2's pREMUSCodec made no State"; }
vals mm1.txt IN_REMUS_STATUS > in.txt
grep -q '^base { src: 2 .*data: "\\016.*queue_key { type: QUEUE_CCL id: 14 }$' in.txt || { cat in.txt; fail "no REMUS State arrived on mm1"; }
[ "$(vals mm1.txt ACOMMS_INCOMING_DATA | grep -c 'QUEUE_CCL id: 14')" = "$(wc -l < in.txt)" ] || fail "ACOMMS_INCOMING_DATA vs IN_REMUS_STATUS"
vals mm1.txt NODE_REPORT > nr1.txt
grep '^NAME=mm2,TYPE=auv,' nr1.txt | head -1 > nr.txt
[ -s nr.txt ] || { cat nr1.txt; fail "no NODE_REPORT of mm2 on mm1"; }
[ "$(srcs mm1.txt NODE_REPORT | sort -u)" = pREMUSCodec ] || fail "NODE_REPORT on mm1 not from pREMUSCodec"
x=$(sed 's/.*,X=\([-0-9.]*\),.*/\1/' nr.txt); y=$(sed 's/.*,Y=\([-0-9.]*\),.*/\1/' nr.txt)
awk -v x=$x -v y=$y 'BEGIN { exit !((x - 123)^2 < 25 && (y - 321)^2 < 25) }' || { cat nr.txt; fail "mm2 reported at $x,$y, not 123,321"; }
grep -qE ',SPD=1\.20*,' nr.txt && grep -q ',HDG=45' nr.txt && grep -q ',DEPTH=111' nr.txt || { cat nr.txt; fail "NODE_REPORT speed/heading/depth"; }
# acks: SIMPLE_STATUS's <queuing> has ack false, and pREMUSCodec's States name no destination
# (dest 0, broadcast), which never requests an acoustic ack: none asked for, none arrives
! vals mm1.txt ACOMMS_OUTGOING_DATA | grep -q 'ack_requested: true' || fail "mm1 asked for an ack"
! vals mm2.txt ACOMMS_OUTGOING_DATA | grep -q 'ack_requested: true' || fail "mm2 asked for an ack"
[ -z "$(vals mm1.txt ACOMMS_ACK)$(vals mm2.txt ACOMMS_ACK)" ] || fail "ACOMMS_ACK without an ack requested"
ok "ccl_and_dccl: SIMPLE_STATUS mm1 -> mm2 decoded ($(wc -l < status.txt) STATUS_REPORT_IN), REMUS State mm2 -> mm1 as NODE_REPORT ($(grep -c . nr1.txt)); no acks asked for"
