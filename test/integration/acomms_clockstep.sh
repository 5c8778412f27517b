# The time step rule end to end (issue 29): the acomms_e2e pair (pAcommsHandler + kelp-modemsim
# per side, FIXED TDMA of two 7 s slots) with the topside's pAcommsHandler clock stepped an hour
# forward 6 s after start-up and back 8 s later (KELP_CLOCK_STEPS, read once by the app runner).
# GoToCommands (acknowledged, ttl 2 h so the step does not expire them) are poked before, during
# and after the hour.  The MAC must not replay the hour's slots: the first command, queued and
# waiting for its ack when the clock jumps, would otherwise go out in a burst of $CCCYC (one per
# missed slot).  Every command must still be sent, arrive and be acknowledged.
. "$(dirname "$0")/lib.sh"
cd $T
. $KELP_ROOT/missions/acomms_e2e/e2e_lib.sh

sed 's|<ttl>40</ttl>|<ttl>7200</ttl>|' goto_ttl.xml > goto_step.xml
grep -q '<ttl>7200</ttl>' goto_step.xml || fail "goto_step.xml: no ttl to change"
N=3 LOSS=0 GOTO=goto_step.xml RATE=2 SLOT=7 SECS=50
TOPSIDE_ENV="KELP_CLOCK_STEPS=6:3600,14:-3600 KELP_CLOCK_STEPS_APP=pAcommsHandler" run step $SECS $N 8
log=step.mm1.txt
# the clock really stepped: the topside's postings carry times an hour ahead for a while
awk '$2 == "pAcommsHandler" { print $1 }' $log | sort -n |
  awk 'NR == 1 { lo = $1 } { hi = $1 } END { exit !(hi - lo > 3600) }' || fail "the topside's clock never stepped"
# no burst: one topside slot per 14 s cycle at most (plus the re-alignments' first slots)
cyc=$(grep -c ' ACOMMS_NMEA_OUT \$CCCYC,' $log || true)
[ "$cyc" -le $((SECS / 14 + 3)) ] || fail "$cyc \$CCCYC from the topside in $SECS s: a burst of replayed slots"
vals step.mm2.txt INCOMING_COMMAND > in_cmd.txt
for ((k = 1; k <= N; k++)); do
  c=$(grep -c "goto_x=$((100 + k))," in_cmd.txt || true)
  [ "$c" -ge 1 ] || { cat in_cmd.txt; fail "GoToCommand goto_x=$((100 + k)) never arrived"; }
done
acked=$(numbers $log ACOMMS_ACK | sort -nu | tr '\n' ' ')
[ "$acked" = "$(seq -s ' ' 1 $N) " ] || fail "acknowledged messages '$acked', want 1..$N"
[ -z "$(vals $log ACOMMS_EXPIRE)" ] || fail "a message expired"
ok "topside clock +1 h and back: $cyc \$CCCYC in $SECS s, $N GoToCommands arrived and acknowledged"
