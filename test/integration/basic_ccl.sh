# The seed's example 1, "Basic CCL" (Goby 1.1 section 2.3.15; missions/basic_ccl), run from the
# seed's mission files unchanged: kelp-launch starts iModemSim as kelp-modemsim and skips
# MOOSDB.  Node 1's uTimerScript writes OUT_TEST_32B = data: "\002\002\003\004" (every 10 s,
# RESET_TIME = end); pAcommsHandler queues it on CCL queue 2 and sends it in the 10 s slot
# 1 -> 2 over the simulated modems; node 2 publishes IN_TEST_32B and ACOMMS_INCOMING_DATA
# with those bytes, and the acoustic ack (the queue's default ack: true) reaches node 1 as
# ACOMMS_ACK.
. "$(dirname "$0")/lib_ccl.sh"
. "$(dirname "$0")/lib.sh"
cd $T
# 44 s: the TDMA slots sit on the UTC clock (10 s), the posts on the launch time, so a post
# can wait almost a whole slot; from 44 s on, at least two posts have always arrived
run_pair $KELP_ROOT/missions/basic_ccl 44
grep -q ' ACOMMS_NMEA_IN \$CACFG,SRC,1' mm1.txt && grep -q ' ACOMMS_NMEA_IN \$CACFG,SRC,2' mm2.txt ||
  { cat logs.mm1/*iModemSim* | tail; fail "start-up never answered by the modems"; }
# (uTimerScript strips the outer quotes of val="data: "\002\002\003\004\"", as MOOS-IvP's does,
# leaving the seed's trailing backslash-quote: pAcommsHandler reads the data up to it)
[ "$(vals mm1.txt OUT_TEST_32B | sort -u)" = 'data: "\002\002\003\004\"' ] || { vals mm1.txt OUT_TEST_32B; fail "uTimerScript's OUT_TEST_32B"; }
# arrivals at node 2: IN_TEST_32B and ACOMMS_INCOMING_DATA, the bytes from modem 1 on CCL queue 2.
# The value uTimerScript posts ends inside its quoted string; Goby's parse_for_moos (protobuf
# TextFormat) keeps the field anyway, escapes applied: 02 02 03 04 22.
D='data: "\002\002\003\004\""'
vals mm2.txt IN_TEST_32B > in.txt
[ -s in.txt ] || { grep -E ' ACOMMS_NMEA_(IN|OUT) ' mm2.txt | tail; fail "no IN_TEST_32B on mm2"; }
[ "$(grep -cF "$D" in.txt)" = "$(wc -l < in.txt)" ] || { cat in.txt; fail "IN_TEST_32B with other bytes"; }
grep -q '^base { src: 1 dest: 0 .* queue_key { type: QUEUE_CCL id: 2 }$' in.txt || { cat in.txt; fail "IN_TEST_32B not from 1 on queue 2"; }
[ "$(vals mm2.txt ACOMMS_INCOMING_DATA | grep -cF "$D")" = "$(wc -l < in.txt)" ] ||
  { vals mm2.txt ACOMMS_INCOMING_DATA; fail "ACOMMS_INCOMING_DATA does not match IN_TEST_32B"; }
# uTimerScript posts every 10 s (RESET_TIME = end) from 10 s on; one message per 10 s slot
n=$(wc -l < in.txt)
[ "$n" -ge 2 ] || fail "only $n arrivals in 44 s"
# node 2 sends nothing (it has no slot) and node 1 receives nothing
[ -z "$(vals mm1.txt IN_TEST_32B)" ] || fail "IN_TEST_32B on mm1"
! grep -q ' ACOMMS_NMEA_OUT \$CCCYC' mm2.txt || fail "mm2 started a cycle"
# acks: the queue's ack is true, but the message names no destination (dest 0, broadcast),
# and a broadcast never requests an acoustic ack: none is asked for, none arrives
vals mm1.txt ACOMMS_OUTGOING_DATA > out.txt
grep -q 'ack_requested: false' out.txt && ! grep -q 'ack_requested: true' out.txt || { cat out.txt; fail "ack requested for a broadcast"; }
grep -qE ' ACOMMS_NMEA_OUT \$CCCYC,0,1,[02],0,0,1\*' mm1.txt || fail "no rate-0 cycle from 1"
[ -z "$(vals mm1.txt ACOMMS_ACK)" ] || fail "ACOMMS_ACK for a broadcast"
[ -z "$(vals mm1.txt ACOMMS_EXPIRE)" ] || fail "ACOMMS_EXPIRE"
ok "basic_ccl: $n CCL messages 02 02 03 04 .. arrived on mm2 (IN_TEST_32B, ACOMMS_INCOMING_DATA); broadcast, so no ack"
