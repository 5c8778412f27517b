# pCTDCodec's and pBTRCodec's jobs (Goby 1.1: both deprecated for DCCL <max_delta> and
# <array_length>) end to end through the simulated modems (missions/btr_ctd): the vehicle mm2
# encodes one CTD profile (10 samples each of depth, temperature and conductivity, delta-coded
# against the first) and one beamformer record (20 beam levels) from the variables its
# uTimerScript writes, and sends both in its rate-2 slot; the topside mm1 publishes every
# array, each sample within its field's precision (one unit of the last decimal kept: Goby's
# encoder truncates, e.g. 14.18 may arrive as 14.17),
# and acknowledges both messages (ACOMMS_ACK on mm2).
. "$(dirname "$0")/lib_ccl.sh"
. "$(dirname "$0")/lib.sh"
cd $T
run_pair $KELP_ROOT/missions/btr_ctd 30
for c in mm1 mm2; do
  grep -q ' ACOMMS_NMEA_IN \$CACFG,SRC,' $c.txt || fail "$c: start-up never answered by the modem"
done
# compare NAME: the last value of SENT_VAR on mm2 and of GOT_VAR on mm1, sample by sample
near() { # name sent_var got_var tolerance
  local s g
  s=$(vals mm2.txt $2 | tail -1); g=$(vals mm1.txt $3 | tail -1)
  [ -n "$g" ] || { grep -E ' ACOMMS_(IN|OUT)' mm1.txt | tail -n 5; fail "$1: no $3 on mm1"; }
  awk -v s="$s" -v g="$g" -v tol=$4 'BEGIN {
      n = split(s, a, ","); m = split(g, b, ",")
      if (n != m) exit 1
      for (i = 1; i <= n; i++) { d = a[i] - b[i]; if (b[i] == "" || b[i] ~ /nan/ || d > tol || -d > tol) exit 1 }
    }' || fail "$1: sent $s, arrived $g"
  echo "$1: $g"
}
near depth CTD_DEPTH CTD_DEPTH_IN 0.1001
near temperature CTD_TEMPERATURE CTD_TEMPERATURE_IN 0.01001
near conductivity CTD_CONDUCTIVITY CTD_CONDUCTIVITY_IN 0.001001
# Goby 1.1 strips trailing zero bytes of a received frame, so when the BTR frame (DCCL id 31)
# ends in 0x00 the field packed in that byte, the first level, decodes as null (goby-wire.md 6;
# acomms_handler_loopback allows the same): then the other 19 levels must still be exact.
btr_sent=$(vals mm2.txt BTR_LEVELS | tail -1) btr_got=$(vals mm1.txt BTR_LEVELS_IN | tail -1)
if [ "${btr_got%%,*}" = "" ] && [ "${btr_got#*,}" = "${btr_sent#*,}" ]; then
  fr=$(grep ' ACOMMS_INCOMING_DATA ' mm1.txt | grep 'id: 31 }' | tail -1 | sed -E 's/.* frame: ([0-9]+) .*/\1/')
  hex=$(grep -E " ACOMMS_NMEA_IN [$]CARXD,2,1,[01],$((fr + 1))," mm1.txt | tail -1 | sed -E 's/.*,([0-9a-fA-F]+)[*][0-9A-F]{2}$/\1/')
  case $hex in *00) echo "note: the BTR frame ended in 0x00: the first level decoded as Goby 1.1 would (trailing zeros stripped)" ;;
    *) fail "levels: sent $btr_sent, arrived $btr_got (frame $fr: $hex)" ;; esac
else
  near levels BTR_LEVELS BTR_LEVELS_IN 0
  [ "$btr_got" = "$btr_sent" ] || fail "BTR levels not exact"
fi
vals mm1.txt BTR_RECORD_IN | grep -q 'heading=87' || { vals mm1.txt BTR_RECORD_IN; fail "BTR heading"; }
vals mm1.txt CTD_PROFILE_IN | grep -q 'depth={10.0,12.5,15.1,17.6,20.0,22.4,25.0,27.5,30.1,32.6},temperature={14.2' || { vals mm1.txt CTD_PROFILE_IN; fail "CTD_PROFILE_IN arrays"; }
# one of each arrived, from modem 2 to modem 1, each acknowledged once
for id in 30 31; do
  [ "$(vals mm1.txt ACOMMS_INCOMING_DATA | grep -c "^base { src: 2 dest: 1 .*QUEUE_DCCL id: $id }")" = 1 ] ||
    { vals mm1.txt ACOMMS_INCOMING_DATA; fail "DCCL id $id did not arrive once"; }
  [ "$(vals mm2.txt ACOMMS_ACK | grep -c "QUEUE_DCCL id: $id }")" = 1 ] || { vals mm2.txt ACOMMS_ACK; fail "DCCL id $id not acknowledged once"; }
done
ok "btr_ctd: CTD profile (3 x 10 samples, max_delta) and BTR record (20 levels) arrived within precision and were acknowledged"
