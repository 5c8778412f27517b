# Acoustic end-to-end (issue 6 "Done when"), no loss: two vehicle communities on two LCM URLs,
# each with pAcommsHandler (DRIVER_WHOI_MICROMODEM) and a kelp-modemsim on a pseudo-terminal;
# the two simulated modems, 500 m apart, share an acoustic channel on a third LCM URL.  Under a
# FIXED TDMA cycle of two 7 s slots (topside rate 2 = 3 x 64 B frames, vehicle rate 0) the
# topside sends four of the seed's GoToCommand (acknowledged) to the vehicle and the vehicle
# broadcasts the seed's VehicleStatus every 10 s.  Every GoToCommand arrives exactly once and is
# acknowledged once; every VehicleStatus sent arrives once.  (missions/acomms_e2e)
. "$(dirname "$0")/lib.sh"
cd $T
. $KELP_ROOT/missions/acomms_e2e/e2e_lib.sh

N=4 LOSS=0 GOTO=goto.xml RATE=2 SLOT=7
run clean 40 $N 1
for f in clean.mm1.txt clean.mm2.txt; do
  grep -q ' ACOMMS_NMEA_IN \$CACFG,SRC,' $f || { head -50 $f; fail "$f: start-up never answered by the modem"; }
done
vals clean.mm2.txt INCOMING_COMMAND > in_cmd.txt
for ((k = 1; k <= N; k++)); do
  c=$(grep -c "goto_x=$((100 + k))," in_cmd.txt || true)
  [ "$c" = 1 ] || { cat in_cmd.txt; fail "GoToCommand goto_x=$((100 + k)) arrived $c times"; }
done
[ "$(wc -l < in_cmd.txt)" = $N ] || { cat in_cmd.txt; fail "$(wc -l < in_cmd.txt) INCOMING_COMMAND, want $N"; }
# the seed's trigger string decodes as Goby 1.1 does (goto_speed 2.3 -> 2.29, SPECIAL_INSTRUCTIONS unset)
grep -q "^Destination=2,type=goto,goto_x=101,goto_y=294,lights_on=true,new_instructions=,goto_speed=2.29$" in_cmd.txt ||
  { cat in_cmd.txt; fail "INCOMING_COMMAND content"; }
[ "$(vals clean.mm1.txt ACOMMS_OUTGOING_DATA | wc -l)" = $N ] || fail "$N GoToCommand not all queued"
acked=$(numbers clean.mm1.txt ACOMMS_ACK | sort -n | tr '\n' ' ')
[ "$acked" = "$(seq -s ' ' 1 $N) " ] || fail "acknowledged messages '$acked', want each of 1..$N once"
[ -z "$(vals clean.mm1.txt ACOMMS_EXPIRE)" ] || fail "ACOMMS_EXPIRE without loss"
# each GoToCommand went out once, several in one rate-2 packet (3 x 64 B frames, stitched)
grep -q ' ACOMMS_NMEA_OUT \$CCCYC,0,1,2,2,1,3\*' clean.mm1.txt || fail "no rate-2 cycle"
sent_messages clean.mm1.txt > tx.txt
[ "$(sort -u tx.txt | wc -l)" = $N ] && [ "$(wc -l < tx.txt)" = $N ] || { cat tx.txt; fail "GoToCommand transmissions"; }
[ "$(grep -c ' ACOMMS_NMEA_OUT \$CCCYC,0,1,' clean.mm1.txt)" -lt $N ] || fail "no two GoToCommands shared a packet"
# VehicleStatus (broadcast, no ack): each one the vehicle sent arrived once at the topside
sent=$(vals clean.mm2.txt ACOMMS_OUTGOING_DATA | data_of | sort)
recv=$(vals clean.mm1.txt ACOMMS_INCOMING_DATA | grep 'id: 2 }' | data_of | sort)
ns=$(echo "$sent" | grep -c . || true); nr=$(echo "$recv" | grep -c . || true)
[ "$ns" -ge 3 ] && [ "$nr" -ge 2 ] || fail "only $ns VehicleStatus queued, $nr sent"
[ -z "$(echo "$recv" | uniq -d)" ] || fail "a VehicleStatus arrived twice"
[ -z "$(comm -13 <(echo "$sent") <(echo "$recv"))" ] || fail "a VehicleStatus arrived that was not sent"
# the ones not arrived are still queued at the vehicle when it stopped (last ACOMMS_QSIZE), or
# (at most one) handed to the modem in the vehicle's last slot as the run ended: on a loaded
# machine the topside's extra 6 s of listening can end before that packet is on the water.
# Nothing may be lost on the channel itself: that is checked strictly below.
pending=$(vals clean.mm2.txt ACOMMS_QSIZE | grep 'id: 2 }' | tail -1 | sed 's/.*size: //')
missing=$((ns - ${pending:-0} - nr))
[ "$missing" -ge 0 ] && [ "$missing" -le 1 ] || fail "$ns VehicleStatus queued, $nr arrived, ${pending:-0} still queued"
[ "$(vals clean.mm1.txt STATUS_SUMMARY | sort -u)" = "nav_x=100.0,nav_y=300.0,health=low_battery" ] ||
  { vals clean.mm1.txt STATUS_SUMMARY; fail "STATUS_SUMMARY content"; }
# the channel lost nothing and nothing collided
grep -q 'lost: random 0 collision 0 half_duplex 0' logs.clean.mm1/*iModemSim* || { cat logs.clean.mm1/*iModemSim* | tail -20; fail "losses on a clean channel"; }
ok "no loss: $N GoToCommand each sent once and arrived once, $N acks; $nr VehicleStatus sent and all arrived once ($pending still queued)"
