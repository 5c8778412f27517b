# The fleet demo (scripts/demo-fleet.sh, the main job of make demo): shoreside + three vehicle
# communities on separate LCM URLs joined by kelp-bridge. Every vehicle must finish its mission
# (survey waypoints, loiter, return) within the demo's time, the shoreside must have seen all
# three through the bridge, and the picture must be written.  The acoustic link: every vehicle's
# pAcommsHandler sends DCCL FleetStatus messages over its simulated modem to the shoreside modem;
# at least one from each must arrive, be decoded and be acknowledged, and the counts must agree
# (every message queued is acknowledged or still queued; only what was sent arrives).
. "$(dirname "$0")/lib.sh"
if [ ! -x "$BIN/pHelmIvP" ]; then echo "SKIP: pHelmIvP not built (the helm is on branch helm)"; exit 0; fi
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cd $T
start=$(date +%s)
DEMO_DIR=$T/demo DEMO_TIMEOUT=50 KELP_DEMO_HEADLESS=1 "$KELP_ROOT/scripts/demo-fleet.sh" "$BUILD" > demo.out 2>&1 || { tail -40 demo.out; fail "demo-fleet.sh failed"; }
el=$(( $(date +%s) - start ))
sed -n '/^== summary/,$p' demo.out
[ $el -le 60 ] || fail "the demo took ${el}s (more than a minute)"
for v in alpha bravo charlie; do
  line=$(awk -v v="$v" '/^== /{s=0} /^== summary/{s=1} s && $1==v' demo.out)
  [ -n "$line" ] || fail "no summary line for $v"
  echo "$line" | grep -qE " 4 \(survey 3, return 1\) +3 \(survey:loiter:return\) +complete$" || fail "$v: $line"
  dist=$(echo "$line" | awk '{print $2}')
  awk -v d="$dist" 'BEGIN{exit !(d > 500 && d < 900)}' || fail "$v travelled $dist m"
  # the table on the shoreside showed it (through the bridge)
  grep -qE "^$v +UUV +-?[0-9.]+ +-?[0-9.]+ " demo.out || fail "$v never in the shoreside table"
done
head -c 8 $T/demo/fleet.png | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "fleet.png is not a PNG"
grep -q "<svg" $T/demo/fleet.svg || fail "fleet.svg missing"
# three distinct tracks: end points near their own starts, far apart in the middle
grep -qE "^alpha +report .* \(0\.0,0\.0\)" $T/demo/plot.out || fail "alpha track does not start at (0,0)"
grep -qE "^bravo +report .* \(15\.0,10\.0\)" $T/demo/plot.out || fail "bravo track does not start at (15,10)"
grep -qE "^charlie +report .* \(-15\.0,-5\.0\)" $T/demo/plot.out || fail "charlie track does not start at (-15,-5)"

# ---- the acoustic link
D=$T/demo
grep -q "^== acoustic link: DCCL FleetStatus" demo.out || fail "no acoustic link summary"
# the printed bus logs: the ModemDataTransmission data field of ACOMMS_* lines
data_of() { sed -n 's/.* data: "\(.*\)" frame: .*/\1/p'; }
k=1 total=0
for v in alpha bravo charlie; do
  k=$((k + 1))
  line=$(awk -v v="$v" '/^== /{s=0} /^== acoustic link/{s=1} s && $1==v' demo.out)
  [ -n "$line" ] || fail "no acoustic summary line for $v"
  read -r _ modem sent tx rcv lost acked expired queued _ <<< "$line"
  [ "$modem" = $k ] || fail "$v: modem $modem, want $k ($line)"
  # about one status every 25 s of a ~300 s mission, one 8 s slot every 24 s
  [ "$sent" -ge 8 ] && [ "$tx" -ge 8 ] || fail "$v: only $sent FleetStatus queued, $tx transmitted ($line)"
  [ "$rcv" -ge 1 ] && [ "$acked" -ge 1 ] || fail "$v: no FleetStatus received and acknowledged at the shoreside ($line)"
  [ "$acked" -le "$rcv" ] && [ "$rcv" -le "$tx" ] || fail "$v: acked $acked, received $rcv, transmitted $tx ($line)"
  # each transmission either arrived or the shoreside modem reports the data frame lost (the
  # last one may still have been on the water when the demo stopped)
  [ $((rcv + lost)) -ge $((tx - 1)) ] && [ $((rcv + lost)) -le "$tx" ] || fail "$v: $tx transmitted, $rcv received + $lost lost ($line)"
  [ "$expired" = 0 ] || fail "$v: $expired FleetStatus expired ($line)"
  [ $((acked + queued)) = "$sent" ] || fail "$v: $sent queued = $acked acknowledged + $queued still queued? ($line)"
  # what arrived was sent by this vehicle, and what was acknowledged had arrived
  awk '$2=="pAcommsHandler" && $3=="ACOMMS_OUTGOING_DATA"' $D/$v.txt | data_of | sort -u > sent_$v.txt
  awk -v k=$k '$2=="pAcommsHandler" && $3=="ACOMMS_INCOMING_DATA" && index($0, "base { src: "k" ")' $D/shoreside.txt | data_of | sort -u > rcv_$v.txt
  awk '$2=="pAcommsHandler" && $3=="ACOMMS_ACK"' $D/$v.txt | data_of | sort -u > ack_$v.txt
  [ "$(wc -l < sent_$v.txt)" = "$sent" ] || fail "$v: FleetStatus messages not all different"
  [ -s rcv_$v.txt ] && [ -z "$(comm -13 sent_$v.txt rcv_$v.txt)" ] || fail "$v: the shoreside received data $v never sent"
  # (the shoreside modem acknowledges a frame as it decodes it; a frame decoded in the last
  # seconds, as the apps were being stopped, may be acknowledged and never reach the shoreside's
  # pAcommsHandler: such an acknowledgement is allowed only that close to the end of the log)
  [ -s ack_$v.txt ] || fail "$v: no acknowledgement"
  shore_end=$(tail -n 1 $D/shoreside.txt | awk '{print $1}')
  comm -13 rcv_$v.txt ack_$v.txt | while IFS= read -r d; do
    t_ack=$(awk '$2=="pAcommsHandler" && $3=="ACOMMS_ACK"' $D/$v.txt | grep -F -- "data: \"$d\"" | head -n 1 | awk '{print $1}')
    awk -v a="$t_ack" -v e="$shore_end" 'BEGIN{exit !(a != "" && a >= e - 5)}' ||
      { echo "acknowledged at $t_ack, the shoreside's log ends at $shore_end: $d"; exit 1; }
  done || fail "$v: acknowledged a FleetStatus the shoreside never received"
  # decoded at the shoreside: STATUS_REPORT with this vehicle's name, a position on the chart
  nrep=$(awk -v v="$v" '$2=="pAcommsHandler" && $3=="STATUS_REPORT" && index($4, ",name="v",")' $D/shoreside.txt | grep -c . || true)
  [ "$nrep" = "$rcv" ] || fail "$v: $rcv received, $nrep STATUS_REPORT decoded"
  awk -v v="$v" '$3=="STATUS_REPORT" && index($4, ",name="v",")' $D/shoreside.txt |
    grep -qE ",nav_x=-?[0-9]+\.[0-9],nav_y=-?[0-9]+\.[0-9],heading=[0-9]+,speed=[0-9]\.[0-9],behavior=(survey|loiter|return|)$" ||
    fail "$v: STATUS_REPORT content: $(grep -m1 "name=$v," $D/shoreside.txt)"
  total=$((total + rcv))
done
# one comms pulse per message decoded, drawn in the picture; no random loss on this channel
npulse=$(awk '$2=="pAcommsHandler" && $3=="VIEW_COMMS_PULSE"' $D/shoreside.txt | grep -c . || true)
[ "$npulse" = $total ] || fail "$npulse VIEW_COMMS_PULSE for $total FleetStatus received"
! grep -q "reason=random" $D/shoreside.txt || fail "random losses on a loss-free channel"
grep -q "ACOMMS_SIM_EVENT modem=1,event=tx,kind=ack" $D/shoreside.txt || fail "the shoreside modem never acknowledged"

# ---- the uField brokers and comms: the vehicles found the shoreside themselves (no static
# bridge in any mission), and uFldNodeComms relayed every vehicle's reports to the others
grep -qE "^== uField handshake: 3 of 3 vehicles found the shoreside" demo.out || fail "uField handshake line missing"
! grep -q "UDPSHARE" $D/*.moos || fail "a generated mission still has a static UDPSHARE"
for v in alpha bravo charlie; do
  uc=$(echo $v | tr a-z A-Z)
  grep -q "uFldShoreBroker PMB_REGISTER src_var=NODE_REPORT_$uc,dest_community=$v," $D/shoreside.txt || fail "no NODE_REPORT_$uc bridge registered"
  line=$(awk -v v="$v" '/^== /{s=0} /^== uField comms/{s=1} s && $1==v' demo.out)
  for o in alpha bravo charlie; do
    [ $o = $v ] && continue
    echo "$line" | grep -qE "(^| )$o [1-9]" || fail "$v: no relayed report from $o ($line)"
  done
done
nrel=$(awk '$2=="uFldNodeComms" && $3=="VIEW_COMMS_PULSE"' $D/shoreside.txt | grep -c . || true)
[ "$nrel" -gt 0 ] || fail "no relay pulses"
grep -qE "VIEW_COMMS_PULSE=$((nrel + npulse))( |$)" $D/plot.out || fail "picture does not draw every pulse ($(grep -o 'VIEW_COMMS_PULSE=[0-9]*' $D/plot.out), want $((nrel + npulse)))"

# the demo's shoreside log in MOOS's .alog (kelp-alog --exact) and back to an LCM log: the same
# postings, in the same order, with the same sources and values (times as printed, to the
# millisecond: the .alog holds them relative to LOGSTART)
"$BIN/kelp-logcheck" $D/shoreside.lcm --print > sh.txt 2>/dev/null || true
"$BIN/kelp-alog" to-alog --exact --mark-types $D/shoreside.lcm sh.alog > alog.out || fail "kelp-alog to-alog"
"$BIN/kelp-alog" to-lcm sh.alog sh2.lcm > /dev/null || fail "kelp-alog to-lcm"
"$BIN/kelp-logcheck" sh2.lcm --print > sh2.txt 2>/dev/null || true
na=$(wc -l < sh.txt)
[ "$na" -gt 1000 ] && [ "$na" -eq "$(wc -l < sh2.txt)" ] || fail "alog round trip: $na postings, $(wc -l < sh2.txt) after"
diff <(cut -d' ' -f2- sh.txt) <(cut -d' ' -f2- sh2.txt) > alog.diff || { head -4 alog.diff; fail "alog round trip changed postings"; }
paste -d' ' <(cut -d' ' -f1 sh.txt) <(cut -d' ' -f1 sh2.txt) | awk '{d = $1 - $2; if (d < 0) d = -d; if (d > 0.0011) bad++} END {exit bad > 0}' ||
  fail "alog round trip moved times"
ok "the demo's shoreside log as .alog and back: $na postings, the same events"

# ---- AppCasting: every app of every community (the Antler lists of the demo's missions) cast
# an APPCAST in MOOS-IvP's format on its community's bus (at start-up; the shoreside's also on
# kelp-viewer's APPCAST_REQ), with its community as the node
ncast=0
for c in shoreside alpha bravo charlie; do
  apps=$(sed -n 's/^ *Run *= *\([A-Za-z0-9_-]*\)[^~]*\(~ *\([A-Za-z0-9_-]*\)\)\{0,1\}.*/\1 \3/p' $D/$c.moos |
         awk '$1 != "MOOSDB" {print ($2 != "" ? $2 : $1)}')
  [ -n "$apps" ] || fail "$c: no apps in its Antler block"
  for a in $apps; do
    line=$(grep -E "^[0-9.]+ +$a +APPCAST " $D/$c.txt | tail -1)
    [ -n "$line" ] || fail "$c: no APPCAST from $a"
    echo "$line" | grep -qE " APPCAST proc=$a!@#iter=[0-9]+!@#node=$c!@#iter=[0-9]+!@#messages=.*!@#events_total=[0-9]+!@#.*run_warning_total=[0-9]+!@#" ||
      fail "$c: APPCAST of $a does not parse: ${line:0:200}"
    ncast=$((ncast + 1))
  done
done
echo "AppCasts: $ncast apps of 4 communities cast a well-formed APPCAST"

if [ -n "${FLEET_PNG:-}" ]; then cp $T/demo/fleet.png "$FLEET_PNG"; fi
ok "fleet demo in ${el}s: three missions complete, picture written; $ncast apps cast APPCAST; $total FleetStatus received at the shoreside; brokers found the shoreside; $nrel relays drawn"
