#!/usr/bin/env bash
# pREMUSCodec (seed 002 section 2.5; the ccl_and_dccl example's block): with create_status it
# makes a REMUS State (first byte 14, 32 bytes) from NAV_* at LatOrigin/LongOrigin on
# OUT_REMUS_STATUS; that ModemDataTransmission, fed back on IN_REMUS_STATUS (as a receiving
# pAcommsHandler's CCL queue would publish it), becomes a NODE_REPORT named from the modem-id
# lookup file (mm2, auv) at the position sent (X=123, Y=321 within a code of lat/lon).
. "$(dirname "$0")/lib.sh"
cd "$T"
printf '1,mm1,topside\n2,mm2,auv\n' > modemidlookup.txt
cat > m.moos <<'M'
ServerPort = 9125
Community = mm2
LatOrigin = 42.35
LongOrigin = -70.95
modem_id_lookup_path = modemidlookup.txt
ProcessConfig = pREMUSCodec
{
  AppTick = 4
  create_status: true
  mdat_state_var: "IN_REMUS_STATUS"
  mdat_state_out: "OUT_REMUS_STATUS"
  modem_id_lookup_path: "modemidlookup.txt"
}
M
"$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f m1.lcmlog > rec1.out 2>&1 &
rec1=$!
sleep 0.5
bg "$BIN/pREMUSCodec" m.moos
sleep 1
"$BIN/kelp-poke" m.moos MODEM_ID=2 NAV_X=123 NAV_Y=321 NAV_HEADING=45 NAV_SPEED=1.2 NAV_DEPTH=111 > poke1.out 2>&1 ||
  fail "poke: $(cat poke1.out)"
sleep 1.5
# the first log, closed (flushed) before it is read
kill -INT $rec1; wait $rec1 2>/dev/null || true
"$BIN/kelp-logcheck" --print m1.lcmlog > m1.txt || fail "log undecodable"
out=$(awk '$3=="OUT_REMUS_STATUS" {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print; exit}' m1.txt)
[ -n "$out" ] || { cat m1.txt | tail; fail "no OUT_REMUS_STATUS"; }
echo "$out" | grep -q '^base { src: 2 dest: 0 } data: "\\016' || fail "State text: $out"
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f m.lcmlog
sleep 0.5
"$BIN/kelp-poke" m.moos "IN_REMUS_STATUS:=$out" > poke2.out 2>&1 || fail "poke: $(cat poke2.out)"
sleep 1
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print m.lcmlog > m.txt || fail "log undecodable"
nr=$(awk '$3=="NODE_REPORT" {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print; exit}' m.txt)
[ -n "$nr" ] || { tail m.txt; fail "no NODE_REPORT"; }
echo "$nr" | grep -q '^NAME=mm2,TYPE=auv,' || fail "NODE_REPORT name/type: $nr"
echo "$nr" | grep -q 'MODE=NOMOOS' || fail "NODE_REPORT mode: $nr"
x=$(echo "$nr" | sed -n 's/.*,X=\([^,]*\),.*/\1/p'); y=$(echo "$nr" | sed -n 's/.*,Y=\([^,]*\),.*/\1/p')
awk -v x="$x" -v y="$y" 'BEGIN { exit !(x > 121 && x < 125 && y > 319 && y < 323) }' || fail "X,Y = $x,$y, want 123,321: $nr"
grep -q ' MM2_NAV_DEPTH 111$' m.txt || { grep MM2_NAV m.txt; fail "MM2_NAV_DEPTH"; }
ok "State $out -> $nr"
