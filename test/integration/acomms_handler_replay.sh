#!/usr/bin/env bash
# kelp-acomms-replay: the queue and MAC on scripted timelines, checked against the numbers of
# the spec (acomms.md section 9 and goby-wire.md sections 5, 8, 9).
. "$(dirname "$0")/lib.sh"
cd "$T"
R="$BIN/kelp-acomms-replay"
M="$KELP_ROOT/missions/acomms"
cat > pq.xml <<'X'
<?xml version="1.0" encoding="UTF-8"?>
<message_set>
  <message>
    <name>A</name><id>10</id><size>32</size>
    <queuing><ack>false</ack><value_base>4</value_base><ttl>1000</ttl></queuing>
    <layout><int><name>x</name><max>100</max><min>0</min></int></layout>
  </message>
  <message>
    <name>B</name><id>11</id><size>32</size>
    <queuing><ack>false</ack><value_base>1.5</value_base><ttl>300</ttl><max_queue>1</max_queue><newest_first>true</newest_first></queuing>
    <layout><int><name>x</name><max>100</max><min>0</min></int></layout>
  </message>
  <message>
    <name>C</name><id>12</id><size>32</size>
    <queuing><ack>true</ack><newest_first>false</newest_first></queuing>
    <layout><int><name>x</name><max>100</max><min>0</min></int></layout>
  </message>
</message_set>
X
# 1. priority contest (spec 9.42/43): A (4, ttl 1000) 0.4 vs B (1.5, ttl 300) 0.5 after 100 s; B wins;
#    max_queue 1 + newest_first keeps the newest (9.46); A expires after its ttl (9.49)
cat > t1.txt <<'X'
push A x=1
push B x=2
push B x=3
advance 100
status
data_request dest=5 bytes=7
advance 901
status
X
"$R" --plain --xml pq.xml t1.txt > o1.txt || { cat o1.txt; fail "replay 1 exit status"; }
grep -q '^ *100.000 status queue=A size=1 priority=0.4$' o1.txt || { cat o1.txt; fail "A priority not 0.4"; }
grep -q '^ *100.000 status queue=B size=1 priority=0.5$' o1.txt || fail "B priority not 0.5"
grep -q '^ *100.000 frame frame=0 .* bytes=7 hex=2005800002..04$' o1.txt || { cat o1.txt; fail "B (x=3, code 4) did not win"; }
grep -q 'expire queue=A dest=0 hex=20050000020002' o1.txt || fail "A did not expire"
e=$(awk '/expire queue=A/{print $1; exit}' o1.txt)
awk -v e="$e" 'BEGIN{exit !(e > 1000 && e <= 1000.2)}' || fail "A expired at $e, not just after ttl 1000 s"
ok "contest 0.4 vs 0.5, newest kept, expiry at ${e}s"

# 2. FIFO with ack (9.47/48): C is FIFO with ack (to modem 3; broadcasts never ask for acks):
#    m1 is re-sent until acked, then m2
cat > t2.txt <<'X'
push C _dest_id=3 x=1
push C _dest_id=3 x=2
data_request bytes=7
data_request bytes=7
ack 0 src=3
data_request bytes=7
X
"$R" --plain --xml pq.xml t2.txt > o2.txt || { cat o2.txt; fail "replay 2 exit status"; }
[ "$(grep -c 'frame frame=0 .*hex=20060000023002$' o2.txt)" = 2 ] || { cat o2.txt; fail "m1 not re-sent before its ack"; }
grep -q 'ack queue=C from=3 frame=0 hex=20060000023002' o2.txt || fail "no ack of m1"
tail -1 o2.txt | grep -q 'hex=20060000023003$' || fail "m2 not sent after the ack"
ok "FIFO + ack: m1 twice, ack, then m2"

# 2b. an ack addressed to another modem is ignored (Goby's queue checks dest); flush empties a queue
cat > t2b.txt <<'X'
push C _dest_id=3 x=1
data_request bytes=7
ack 0 src=3 dest=4
data_request bytes=7
push A x=5
flush C
status
X
"$R" --plain --xml pq.xml t2b.txt > o2b.txt || { cat o2b.txt; fail "replay 2b exit status"; }
grep -q 'ack-ignored frame=0 (addressed to 4, not us)' o2b.txt || { cat o2b.txt; fail "foreign ack not ignored"; }
grep -q 'ack queue=C' o2b.txt && fail "an ack for modem 4 removed our message"
[ "$(grep -c 'frame frame=0 .*hex=20060000023002$' o2b.txt)" = 2 ] || { cat o2b.txt; fail "m1 not re-sent after a foreign ack"; }
grep -q 'flush queue=C' o2b.txt && grep -q 'qsize queue=C size=0' o2b.txt || { cat o2b.txt; fail "flush C"; }
grep -q 'status queue=C size=0' o2b.txt && grep -q 'status queue=A size=1' o2b.txt || { cat o2b.txt; fail "flush emptied the wrong queue"; }
printf 'flush Nope\n' | "$R" --plain --xml pq.xml > o2c.txt && fail "flush of an unknown queue exit 0"
grep -q 'error line=1 flush needs the name of a queue' o2c.txt || { cat o2c.txt; fail "flush error"; }
ok "foreign ack ignored, flush C (A kept)"

# 3. the spec's SIMPLE_STATUS vector (3.8) at 12:00:00 UTC, blackout 10 s (9.45), broadcast flag
printf 'push SIMPLE_STATUS Node=2 nav_x=123 nav_y=321 Speed=1.2 Heading=45 Depth=111\ndata_request\nadvance 10.1\ndata_request\n' |
  "$R" --plain --xml "$M/simple_status.xml" --modem-id 2 --start 1262347200 > o3.txt || { cat o3.txt; fail "replay 3"; }
grep -q 'push queue=SIMPLE_STATUS id=20 dest=0 bytes=16 hex=200a2a300400061c7187e22111950457' o3.txt || { cat o3.txt; fail "SIMPLE_STATUS vector"; }
grep -q '^ *0.000 frame .* blank' o3.txt || fail "no blank during the 10 s blackout"
grep -q '^ *10.100 frame .*hex=200a2a300404061c7187e22111950457$' o3.txt || { cat o3.txt; fail "no frame with the broadcast flag (200a2a300404) after the blackout"; }
ok "SIMPLE_STATUS 200a2a300400061c7187e22111950457, blackout, flag 200a2a300404"

# 4. stitching: GoToCommand (21 B, to 2, ack) + VehicleStatus (10 B, broadcast) in one 32-byte frame
#    at the first TDMA slot: FIXED 2 x 10 s at 00:00:07 -> the cycle starts at 00:00:20 (9.61)
cat > r.moos <<X
ProcessConfig = pAcommsHandler
{
  modem_id: 1
  mac_cfg { type: MAC_FIXED_DECENTRALIZED
            slot { src: 1 dest: 2 rate: 0 type: SLOT_DATA slot_seconds: 10 }
            slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 10 } }
  queue_cfg { message_file { path: "$M/example1.xml" } }
}
X
cat > t4.txt <<'X'
push GoToCommand Destination=2 goto_x=351 goto_y=294 lights_on=true goto_speed=2.3
push VehicleStatus nav_x=100 nav_y=300 health=low_battery
advance 14
ack 0 src=2
advance 20
status
X
"$R" --plain --moos r.moos --start 1262304007 t4.txt > o4.txt || { cat o4.txt; fail "replay 4"; }
grep -q '^ *13.000 slot index=0 transmit src=1 dest=2 rate=0' o4.txt || { cat o4.txt; fail "first slot not at 00:00:20"; }
grep -q '^ *33.000 slot index=0 transmit' o4.txt || fail "second cycle not 20 s later"
grep -q '^ *23.000 slot' o4.txt && fail "slot 2 (src 2) fired at modem 1"
g=$(awk '/push queue=GoToCommand/{sub("hex=","",$NF); print $NF}' o4.txt)
v=$(awk '/push queue=VehicleStatus/{sub("hex=","",$NF); print $NF}' o4.txt)
h1=${g:2:8}; h1=${h1:0:8}$(printf '%02x' $(( 16#${g:10:2} | 8 )))
h2=${v:2:8}$(printf '%02x' $(( 16#${v:10:2} | 4 )))
exp="20${h1}$(printf '%02x' $(( ${#g} / 2 - 6 )))${g:12}${h2}${v:12}"
grep -q "^ *13.000 frame frame=0 request_dest=2 max_bytes=32 src=1 dest=2 ack=1 bytes=31 hex=$exp\$" o4.txt || { cat o4.txt; echo "expected $exp"; fail "stitched frame"; }
grep -q 'ack queue=GoToCommand from=2 frame=0' o4.txt || fail "GoToCommand not acked"
ok "stitched frame $exp at the 00:00:20 slot; ack"

# 5. bad input: errors are reported with the line, the replay goes on, exit status 1
printf 'push Nope x=1\nadvance -3\nfrobnicate\ndata_request bytes=9999\nstatus\n' | "$R" --plain --xml pq.xml > o5.txt && fail "bad timeline exit 0"
[ "$(grep -c '^ *0.000 error line=' o5.txt)" = 4 ] || { cat o5.txt; fail "not 4 errors"; }
grep -q 'status queue=A' o5.txt || fail "replay stopped at the first error"
"$R" --help > help.txt && grep -q 'data_request' help.txt || fail "--help lacks the language"
ok "bad timeline lines reported (4), --help documents the language"

# 6. a cycle of caller frames through the Micro-Modem driver (Goby's driver on demand): the
#    rate's frame count in $CCCYC, each $CADRQ answered from the frames, the rest empty
cat > t6.txt <<'X'
cycle rate=2 dest=3 abcd
modem start
advance 1.5
modem $CACLK,2010,1,1,0,0,1
advance 1.2
modem $CACFG,SRC,1
advance 0.2
modem $CACFG,ALL,0
advance 0.3
cycle rate=2 dest=3 ack=1 abcd
advance 0.2
modem $CACYC,0,1,3,2,1,3
modem $CADRQ,000001,1,3,1,64,1
advance 0.2
modem $CATXD,1,3,1,abcd
modem $CADRQ,000002,1,3,1,64,2
advance 0.2
modem $CATXD,1,3,1,
modem $CADRQ,000003,1,3,1,64,3
advance 0.2
cycle rate=2 dest=3 a b c d
cycle rate=0 dest=3 - -
X
"$R" --plain t6.txt > o6.txt && fail "caller-frames timeline with errors exit 0"
grep -q 'error line=1 cycle: say "modem start" first' o6.txt || { cat o6.txt; fail "cycle before modem start"; }
grep -q 'nmea-out \$CCCYC,0,1,3,2,1,3\*' o6.txt || { cat o6.txt; fail "CCCYC with the rate's 3 frames"; }
[ "$(grep -c 'nmea-out \$CCTXD,1,3,1,abcd\*' o6.txt)" = 1 ] || { cat o6.txt; fail "frame 1 from the caller"; }
[ "$(grep -c 'nmea-out \$CCTXD,1,3,1,\*' o6.txt)" = 2 ] || { cat o6.txt; fail "frames 2 and 3 empty"; }
grep -q 'cycle: bad argument "a"' o6.txt || fail "bad frame hex accepted"
grep -q 'cycle: rate 0 carries 1 frames' o6.txt || { cat o6.txt; fail "2 frames at rate 0 accepted"; }
ok "caller frames: \$CCCYC with 3 frames, 1 given + 2 empty \$CCTXD, errors for bad input"

# 7. the cycle changed while the MAC runs (ACOMMS_MAC_CYCLE_UPDATE): each change re-aligns the
#    cycle to the next boundary of the new length (goby-wire.md 9.61) at the update's time.
#    r.moos (test 4): FIXED, modem 1, slots (1->2, 10 s) (2->1, 10 s), start 00:00:07.
#    - cycle 20 s from 00:00:20: our slot at t=13, 33
#    - t=40 (00:00:47) ADD (1->3, 10 s): cycle 30 s from 00:01:00 (t=53): 53 idx0, 73 idx2, 83 idx0
#    - t=100 (00:01:47) REMOVE (2->1): cycle 20 s from 00:02:00 (t=113): 113, 123, 133, 143
#    A time handed to the MAC in the wrong unit re-aligned the cycle to 1970 and the replay
#    printed every slot since then at one second without end, hence the timeout.
cat > t7.txt <<'X'
advance 40
mac_update dest: 1 update_type: ADD slot { src: 1 dest: 3 rate: 0 type: SLOT_DATA slot_seconds: 10 }
advance 60
mac_update dest: 1 update_type: REMOVE slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 10 }
advance 50
X
timeout 20 "$R" --plain --moos r.moos --start 1262304007 t7.txt > o7.txt || { head -40 o7.txt; fail "replay 7 did not finish"; }
grep -q '^ *40.000 mac_update slots=3 cycle=30$' o7.txt || { head -40 o7.txt; fail "ADD not applied"; }
grep -q '^ *100.000 mac_update slots=2 cycle=20$' o7.txt || { cat o7.txt; fail "REMOVE not applied"; }
got=$(awk '/ slot index=/{printf "%s:%s ", $1, $3}' o7.txt)
want="13.000:index=0 33.000:index=0 53.000:index=0 73.000:index=2 83.000:index=0 113.000:index=0 123.000:index=1 133.000:index=0 143.000:index=1 "
[ "$got" = "$want" ] || { head -40 o7.txt; echo "got  ${got:0:400}"; echo "want $want"; fail "not one slot per slot time across the updates"; }
[ "$(awk '/ slot index=/{print $1}' o7.txt | sort | uniq -d | wc -l)" = 0 ] || fail "two slots at one time"
ok "mac_update ADD then REMOVE while the MAC runs: 9 slots, one per slot time, re-aligned each time"
