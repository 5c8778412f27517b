# Acoustic end-to-end (issue 6 "Done when"), with loss: the set-up of acomms_e2e.sh (two
# communities, pAcommsHandler + kelp-modemsim each, 500 m apart, missions/acomms_e2e) with 50 %
# loss at both simulated modems (data frames, acks, cycle inits), 6 s slots, the topside at
# rate 0 (one GoToCommand per packet), GoToCommand oldest-first with a ttl of 40 s (goto_ttl.xml).  Five
# GoToCommands are queued at once: at most four topside slots fit before the first ttl runs
# out, so at least one must expire.  The vehicle modem's seed (49) makes it lose the first
# GoToCommand frame it hears (its draws are: cycle init, frame, cycle init, frame, ... whatever
# the timing), so the first one is certainly sent again (oldest first: it is the next one); the rest of the loss is left to chance.
#  - unacknowledged messages are sent again (some message is handed to the modem twice);
#  - the ones not acknowledged within the ttl are reported on ACOMMS_EXPIRE;
#  - nothing else is lost: each message is acknowledged once or expires once, and each
#    acknowledged one arrived at the vehicle.
. "$(dirname "$0")/lib.sh"
cd $T
. $KELP_ROOT/missions/acomms_e2e/e2e_lib.sh

N=5 LOSS=0.5 GOTO=goto_ttl.xml RATE=0 SLOT=6
run lossy 55 $N 1
vals lossy.mm2.txt INCOMING_COMMAND > in_cmd.txt
[ "$(vals lossy.mm1.txt ACOMMS_OUTGOING_DATA | wc -l)" = $N ] || fail "$N GoToCommand not all queued"
numbers lossy.mm1.txt ACOMMS_ACK > acked.txt
numbers lossy.mm1.txt ACOMMS_EXPIRE > expired.txt
na=0; ne=0
for ((k = 1; k <= N; k++)); do
  a=$(grep -cx $k acked.txt || true); e=$(grep -cx $k expired.txt || true)
  r=$(grep -c "goto_x=$((100 + k))," in_cmd.txt || true)
  [ $((a + e)) = 1 ] || fail "message $k acknowledged $a times, expired $e times"
  [ $a = 0 ] || [ $r -ge 1 ] || fail "message $k acknowledged but never arrived"
  na=$((na + a)); ne=$((ne + e))
done
sent_messages lossy.mm1.txt > tx.txt
resent=$(sort tx.txt | uniq -d | wc -l)
grep -q 'lost: random [1-9]' logs.lossy.mm1/*iModemSim* logs.lossy.mm2/*iModemSim* || fail "the channel lost nothing"
[ "$resent" -ge 1 ] || { cat tx.txt; fail "no GoToCommand was sent twice"; }
[ "$ne" -ge 1 ] || fail "no message expired"
ok "50 % loss: $(wc -l < tx.txt) transmissions of $N messages ($resent sent again); $na acknowledged, $ne expired (ACOMMS_EXPIRE)"
