# Acoustic end-to-end with centralized polling: the topside's pAcommsHandler runs MAC_POLLED and
# takes its cycle from pAcommsPoller (ACOMMS_MAC_CYCLE_UPDATE); the vehicle runs MAC_NONE and
# transmits only when polled: the topside's modem sends a third-party cycle init
# ($CCCYC,0,2,1,...), the vehicle's modem hears it, asks its host for data ($CADRQ) and sends.
# Templates topside_polled.moos / auv_polled.moos, no loss, 7 s slots.
#  - the poller's REPLACE reaches the handler: the topside writes $CCCYC for both slots
#  - GoToCommands (topside slot) arrive once each and are acknowledged
#  - VehicleStatus (polled slot) arrives at the topside, each once, none unsolicited
. "$(dirname "$0")/lib.sh"
cd $T
. $KELP_ROOT/missions/acomms_e2e/e2e_lib.sh

N=3 LOSS=0 GOTO=goto.xml RATE=2 SLOT=7 TOPSIDE=topside_polled.moos AUV=auv_polled.moos
run polled 40 $N 1
grep -q ' ACOMMS_MAC_CYCLE_UPDATE dest: 1 update_type: REPLACE slot { src: 1 dest: 2 rate: 2 type: SLOT_DATA slot_seconds: 7 } slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 7 }' polled.mm1.txt ||
  fail "no MACUpdate from pAcommsPoller"
polls=$(grep -c ' ACOMMS_NMEA_OUT \$CCCYC,0,2,1,0,1,1\*' polled.mm1.txt || true)
[ "$polls" -ge 2 ] || fail "the topside polled the vehicle $polls times"
# the vehicle never starts a cycle itself; it answers polls with $CADRQ -> $CCTXD
! grep -q ' ACOMMS_NMEA_OUT \$CCCYC' polled.mm2.txt || fail "the vehicle (MAC_NONE) started a cycle"
grep -q ' ACOMMS_NMEA_IN \$CACYC,0,2,1,0,1,1\*' polled.mm2.txt || fail "the vehicle did not hear the poll"
grep -q ' ACOMMS_NMEA_OUT \$CCTXD,2,1,0,2001' polled.mm2.txt || fail "the vehicle did not answer a poll with VehicleStatus"
vals polled.mm2.txt INCOMING_COMMAND > in_cmd.txt
for ((k = 1; k <= N; k++)); do
  c=$(grep -c "goto_x=$((100 + k))," in_cmd.txt || true)
  [ "$c" = 1 ] || { cat in_cmd.txt; fail "GoToCommand goto_x=$((100 + k)) arrived $c times"; }
done
acked=$(numbers polled.mm1.txt ACOMMS_ACK | sort -n | tr '\n' ' ')
[ "$acked" = "$(seq -s ' ' 1 $N) " ] || fail "acknowledged messages '$acked', want each of 1..$N once"
sent=$(vals polled.mm2.txt ACOMMS_OUTGOING_DATA | data_of | sort)
recv=$(vals polled.mm1.txt ACOMMS_INCOMING_DATA | grep 'id: 2 }' | data_of | sort)
nr=$(echo "$recv" | grep -c . || true)
[ "$nr" -ge 2 ] || fail "only $nr VehicleStatus arrived"
[ -z "$(echo "$recv" | uniq -d)" ] || fail "a VehicleStatus arrived twice"
[ -z "$(comm -13 <(echo "$sent") <(echo "$recv"))" ] || fail "a VehicleStatus arrived that was not sent"
ok "polled: $polls polls, $N GoToCommand arrived once and acknowledged, $nr VehicleStatus arrived"
