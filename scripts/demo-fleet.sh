#!/usr/bin/env bash
# make demo: a multi-vehicle mission on one host. A shoreside community and three vehicle
# communities (missions/fleet), each on its own LCM URL, joined by kelp-bridge through the
# uField brokers (each vehicle's uFldNodeBroker finds the shoreside from TRY_SHORE_HOST and
# uFldShoreBroker registers the bridges; uFldNodeComms relays node reports by range and the
# picture draws each relay as a comms pulse); every vehicle
# runs pHelmIvP, uSimMarine and pNodeReporter on an Alder-like mission (a survey over several
# waypoints, a loiter, then home) under MOOSTimeWarp. The shoreside shows the vehicles in a
# table while they run; every community is logged with kelp-record (lcm-logger drops bursts); at the end a summary per
# vehicle is printed and a picture of the tracks is written (build/demo-fleet/fleet.png).
# The acoustic link: each community also runs pAcommsHandler with a simulated WHOI Micro-Modem
# (kelp-modemsim on a pseudo-terminal; the modems share a channel on their own LCM URL); every
# vehicle sends a DCCL FleetStatus (missions/fleet/fleet_status.xml) to the shoreside modem in
# its TDMA slot, the shoreside decodes and acknowledges it; the summary counts them per vehicle
# and the picture shows a comms pulse per message received.
# Runs inside a private network namespace when root (nothing leaves the machine; the viewer's
# page is forwarded to this host's 127.0.0.1, see fleet_private_netns_forward); otherwise on
# the host with ttl=0. After the run (unless KELP_DEMO_HEADLESS=1) the page replays the run's
# shoreside log (kelp-viewer --log: time slider) until Ctrl-C.
#   usage: scripts/demo-fleet.sh [BUILD_DIR]
#   env: DEMO_WARP (10), DEMO_TIMEOUT (75 s wall), DEMO_DIR (build/demo-fleet: missions, logs, picture),
#        DEMO_ACOMMS_LOSS (0: probability that the simulated channel loses a packet / data frame),
#        DEMO_FLEET (missions/fleet/fleet.conf: the vehicles), DEMO_VIEWER_PORT (8080: kelp-viewer's page),
#        DEMO_NO_DEPLOY=1 (do not poke DEPLOY: press the page's DEPLOY button instead),
#        DEMO_NETNS=0 (run on the host instead of a private network namespace; root only),
#        KELP_DEMO_HEADLESS=1 (CI: end after the run; otherwise the replay is served until Ctrl-C)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
B=$(cd "${1:-$ROOT/build}" && pwd)
WARP=${DEMO_WARP:-10}
TIMEOUT=${DEMO_TIMEOUT:-75}
. "$ROOT/scripts/fleet-lib.sh"
[ "${DEMO_NETNS:-1}" = 0 ] && export KELP_IN_NETNS=
[ "${DEMO_NETNS:-1}" = 0 ] || fleet_private_netns_forward "${DEMO_VIEWER_PORT:-8080}" "$0" "$@"
for p in kelp-launch kelp-poke kelp-bridge kelp-plot kelp-viewer kelp-logcheck uSimMarine pNodeReporter pAcommsHandler kelp-modemsim; do
  [ -x "$B/bin/$p" ] || { echo "demo-fleet: $B/bin/$p not built (run make)"; exit 1; }
done
[ -x "$B/bin/pHelmIvP" ] || { echo "demo-fleet: pHelmIvP not built (the helm is not in this tree yet)"; exit 1; }
command -v lcm-logger >/dev/null || { echo "demo-fleet: lcm-logger missing (apt-get install liblcm-bin)"; exit 1; }
unset KELP_LCM_URL   # each community's own LCM_URL must win
W=${DEMO_DIR:-$ROOT/build/demo-fleet}
rm -rf "$W"; mkdir -p "$W"; cd "$W"
M=$ROOT/missions/fleet
FLEET=${DEMO_FLEET:-$M/fleet.conf}
VIEWER_PORT=${DEMO_VIEWER_PORT:-8080}
SHORE_LCM=7680 SHORE_BRIDGE=9200
# the acoustic link: every community runs pAcommsHandler + kelp-modemsim; the simulated modems
# share the acoustic channel on their own LCM URL. Modem 1 is the shoreside gateway, vehicle i
# is modem i+1. TDMA (MAC_FIXED_DECENTRALIZED): one rate-0 slot of ACOMMS_SLOT s per vehicle
# (the shoreside needs none: it only acknowledges, inside the vehicles' slots).
ACOMMS_CHAN="udpm://239.255.76.67:7690?ttl=0"
ACOMMS_SLOT=8
ACOMMS_LOSS=${DEMO_ACOMMS_LOSS:-0}

# ---- generate the missions (nsplug style)
NAMES=(); SLOTS=""
n=0
while IFS='|' read -r name _; do
  name=$(trim "$name"); [ -z "$name" ] || [ "${name:0:1}" = "#" ] && continue
  n=$((n + 1))
  SLOTS+="    slot { src: $((n + 1)) dest: -1 rate: 0 type: SLOT_DATA slot_seconds: $ACOMMS_SLOT }   // $name"$'\n'
done < "$FLEET"
SLOTS=${SLOTS%$'\n'}
ACOMMS=(ACOMMS_CHAN="$ACOMMS_CHAN" ACOMMS_LOSS="$ACOMMS_LOSS" STATUS_XML="$M/fleet_status.xml" MAC_SLOTS="$SLOTS")
i=0
while IFS='|' read -r name lport bport start speed points loiter cw ltime; do
  name=$(trim "$name"); [ -z "$name" ] || [ "${name:0:1}" = "#" ] && continue
  lport=$(trim "$lport"); bport=$(trim "$bport"); start=$(trim "$start"); speed=$(trim "$speed")
  points=$(trim "$points"); loiter=$(trim "$loiter"); cw=$(trim "$cw"); ltime=$(trim "$ltime")
  IFS=, read -r sx sy sh <<< "$start"; IFS=, read -r lx ly lr <<< "$loiter"
  i=$((i + 1)); NAMES+=("$name")
  uc=$(echo "$name" | tr a-z A-Z)
  fill "$M/meta_vehicle.moos" VNAME="$name" VNAME_UC="$uc" MOOS_PORT=$((9000 + i)) WARP="$WARP" LCM_PORT="$lport" \
       START_POS="x=$sx, y=$sy, heading=$sh, speed=0" BRIDGE_PORT="$bport" SHORE_BRIDGE="$SHORE_BRIDGE" \
       START_X="$sx" START_Y="$sy" MODEM_ID=$((i + 1)) PTY="$W/tty_$name" "${ACOMMS[@]}" > "$name.moos"
  fill "$M/meta_vehicle.bhv" VNAME="$name" SPEED="$speed" POINTS="${points//:/ : }" LOITER_TIME="$ltime" CLOCKWISE="$cw" \
       LOITER_X="$lx" LOITER_Y="$ly" LOITER_R="$lr" START_X="$sx" START_Y="$sy" > "$name.bhv"
done < "$FLEET"
[ ${#NAMES[@]} -gt 0 ] || { echo "demo-fleet: no vehicles in $FLEET"; exit 1; }
fill "$M/meta_shoreside.moos" WARP="$WARP" SHORE_LCM="$SHORE_LCM" SHORE_BRIDGE="$SHORE_BRIDGE" VIEWER_PORT="$VIEWER_PORT" \
     PTY="$W/tty_shoreside" "${ACOMMS[@]}" > shoreside.moos

echo "== kelp fleet demo: shoreside + ${#NAMES[@]} vehicles (${NAMES[*]}), MOOSTimeWarp $WARP, acoustic modems 1 (shoreside) to $(( ${#NAMES[@]} + 1 ))"
echo "   missions in $W (generated from missions/fleet)"
# one warped clock for every community and the pokes
export KELP_WARP_EPOCH=$(date +%s.%N)
echo "$KELP_WARP_EPOCH" > warp_epoch   # for pokes from outside: KELP_WARP_EPOCH=$(cat warp_epoch) kelp-poke ...
trap fleet_cleanup EXIT
fleet_start $((TIMEOUT + 10)) "${NAMES[@]}"
# the uField handshake: each vehicle's uFldNodeBroker pings the shoreside (TRY_SHORE_HOST),
# uFldShoreBroker acknowledges and registers the bridges both ways
fleet_wait_handshake "$SHORE_BRIDGE" "${NAMES[@]}" || { echo "demo-fleet: not every vehicle found the shoreside"; exit 1; }
# the page's address on this host: forwarded out of the namespace (KELP_DEMO_PAGE_PORT), or
# the viewer's own port when the demo runs on the host (or inside a test's namespace)
PAGE_URL=http://127.0.0.1:${KELP_DEMO_PAGE_PORT:-$VIEWER_PORT}/
HEADLESS=${KELP_DEMO_HEADLESS:-0}
echo "== kelp-viewer (pMarineViewer role): $PAGE_URL   <- open it in a browser on this machine"
[ "$HEADLESS" = 1 ] || echo "   the demo goes on without waiting; after the run the page replays it until Ctrl-C"
sleep 1
if [ "${DEMO_NO_DEPLOY:-0}" = 1 ]; then
  echo "== DEPLOY: waiting for the page's DEPLOY button (DEMO_NO_DEPLOY=1)"
else
  echo "== DEPLOY: kelp-poke shoreside.moos DEPLOY_ALL:=true MOOS_MANUAL_OVERIDE_ALL:=false (QBRIDGEd to every vehicle)"
  "$B/bin/kelp-poke" shoreside.moos DEPLOY_ALL:=true MOOS_MANUAL_OVERIDE_ALL:=false > poke_deploy.out
fi
t0=$(date +%s)
done_all=0
while :; do
  sleep 4
  el=$(( $(date +%s) - t0 ))
  echo "---- after ${el} s (wall) ----"
  if [ -f vehicles.txt ]; then cat vehicles.txt; else echo "(no vehicle table yet)"; fi
  # (kelp-logcheck exits 1 because pAcommsHandler's structured ACOMMS_*_LCM channels are not kelp vars)
  "$B/bin/kelp-logcheck" shoreside.lcm --print > shoreside.txt 2>/dev/null || true
  awk -v names="${NAMES[*]}" '$2=="pAcommsHandler" && $3=="STATUS_REPORT" {split($4, f, ","); for (i in f) if (f[i] ~ /^name=/) n[substr(f[i], 6)]++; t++}
       END {printf "acoustic: %d FleetStatus received at the shoreside (", t; k = split(names, v, " ")
            for (i = 1; i <= k; i++) printf "%s%s %d", (i > 1 ? ", " : ""), v[i], n[v[i]] + 0; print ")"}' shoreside.txt
  ndone=$(awk '$3 ~ /^MISSION_/ && $4=="complete" {d[$3]=1} END{print length(d)}' shoreside.txt)
  if [ "${ndone:-0}" -ge ${#NAMES[@]} ]; then done_all=1; break; fi
  [ $el -ge "$TIMEOUT" ] && break
done
sleep 1
fleet_stop
echo "== final vehicle table (shoreside viewer)"
cat vehicles.txt 2>/dev/null || true

# ---- the picture (from the shoreside log: every vehicle's reports and drawings came there)
"$B/bin/kelp-plot" shoreside.lcm -o fleet.png -o fleet.svg \
  --title "kelp fleet demo: ${NAMES[*]} (survey, loiter, return; acoustic status to the gateway; MOOSTimeWarp $WARP)" > plot.out || { cat plot.out; exit 1; }

# ---- summary per vehicle: distance (shoreside track), waypoints reached (wptflag WPT_HIT),
# behaviour completions (the helm's completed list), mission time (DEPLOY to MISSION=complete)
echo "== summary"
printf '%-9s %10s %10s %-28s %-34s %s\n' vehicle "dist (m)" "time (s)" "waypoints reached" "behaviours completed" "mission"
ok_all=1
for v in "${NAMES[@]}"; do
  "$B/bin/kelp-logcheck" "$v.lcm" --print > "$v.txt" 2>/dev/null || true
  dist=$(awk -v v="$v" '$1==v && $2=="report" {print $4}' plot.out)
  hits=$(awk '$2=="pHelmIvP" && $3=="WPT_HIT" {split($4, w, ":"); n[w[1]]++; t++} END{printf "%d (survey %d, return %d)", t, n["survey"], n["return"]}' "$v.txt")
  # (24.8's summary writes a field when it changes: the last completed_bhvs= written, its
  # entries "name$time$updates" joined with ':')
  cmpl=$(grep " pHelmIvP IVPHELM_SUMMARY " "$v.txt" | grep -o 'completed_bhvs=[^,]*' | tail -1 | sed 's/^completed_bhvs=//' |
         awk -F: '{for (i = 1; i <= NF; i++) {sub(/\$.*/, "", $i); printf "%s%s", (i > 1 ? ":" : ""), $i}}')
  ncmpl=$(echo "${cmpl:-none}" | awk -F: '$1=="none"{print 0; exit} {print NF}')
  td=$(awk '$3=="DEPLOY" && $4=="true" {print $1; exit}' "$v.txt")
  tm=$(awk '$2=="pHelmIvP" && $3=="MISSION" && $4=="complete" {print $1; exit}' "$v.txt")
  if [ -n "$td" ] && [ -n "$tm" ]; then
    mt=$(awk -v a="$td" -v b="$tm" 'BEGIN{printf "%.0f", b - a}'); state="complete"
  else
    mt="-"; state="NOT complete"; ok_all=0
  fi
  printf '%-9s %10s %10s %-28s %-34s %s\n' "$v" "${dist:--}" "$mt" "$hits" "$ncmpl (${cmpl:-none})" "$state"
done
# ---- the acoustic link per vehicle: DCCL FleetStatus messages queued by the vehicle's
# pAcommsHandler (ACOMMS_OUTGOING_DATA), data packets its modem put on the water ($CCTXD), those
# received and decoded at the shoreside (ACOMMS_INCOMING_DATA from its modem id), data frames
# the shoreside modem lost (kelp-modemsim ACOMMS_SIM_EVENT), acknowledgements back at the
# vehicle (ACOMMS_ACK), expired (ACOMMS_EXPIRE) and still queued when the demo stopped
"$B/bin/kelp-logcheck" shoreside.lcm --print > shoreside.txt 2>/dev/null || true
echo "== acoustic link: DCCL FleetStatus every 25 s -> shoreside modem 1 (ack requested); TDMA ${#NAMES[@]} x $ACOMMS_SLOT s, rate 0; loss $ACOMMS_LOSS"
printf '%-9s %5s %5s %11s %9s %12s %6s %7s %6s  %s\n' vehicle modem sent transmitted received "lost (shore)" acked expired queued "last status decoded at the shoreside"
k=1
for v in "${NAMES[@]}"; do
  k=$((k + 1))
  sent=$(awk '$2=="pAcommsHandler" && $3=="ACOMMS_OUTGOING_DATA"' "$v.txt" | grep -c . || true)
  tx=$(awk -v id=$k '$2=="pAcommsHandler" && $3=="ACOMMS_NMEA_OUT" && $4 ~ "^[$]CCTXD,"id"," {split($4, f, ","); if (length(f[5]) > 4) n++} END{print n+0}' "$v.txt")
  rcv=$(awk -v id=$k '$2=="pAcommsHandler" && $3=="ACOMMS_INCOMING_DATA" && index($0, "base { src: "id" ") {n++} END{print n+0}' shoreside.txt)
  lost=$(awk -v id=$k '$3=="ACOMMS_SIM_EVENT" && $4 ~ "^modem=1,event=lost,kind=data,src="id"," {n++} END{print n+0}' shoreside.txt)
  ack=$(awk '$2=="pAcommsHandler" && $3=="ACOMMS_ACK" {n++} END{print n+0}' "$v.txt")
  exp=$(awk '$2=="pAcommsHandler" && $3=="ACOMMS_EXPIRE" {n++} END{print n+0}' "$v.txt")
  q=$(awk '$2=="pAcommsHandler" && $3=="ACOMMS_QSIZE" {q=$NF} END{print q+0}' "$v.txt")
  last=$(awk -v v="$v" '$2=="pAcommsHandler" && $3=="STATUS_REPORT" && index($4, ",name="v",") {l=$4} END{sub(/^dest=[0-9]*,name=[^,]*,/, "", l); print l}' shoreside.txt)
  printf '%-9s %5s %5s %11s %9s %12s %6s %7s %6s  %s\n' "$v" "$k" "$sent" "$tx" "$rcv" "$lost" "$ack" "$exp" "$q" "${last:--}"
done
awk '$3=="ACOMMS_SIM_EVENT" && $4 ~ /^modem=1,event=lost,kind=data,/ {r = $4; sub(/.*reason=/, "", r); n[r]++; t++}
     END {printf "   the shoreside modem lost %d data frames", t; s = " ("; for (r in n) {printf "%s%s %d", s, r, n[r]; s = ", "}
          print (t ? ")" : "")}' shoreside.txt
# ---- uField comms: node reports relayed by uFldNodeComms (by range) to each vehicle
echo "== uField comms: node reports relayed by uFldNodeComms (comms range 150 m, one per pair per 20 s)"
printf '%-9s %8s %14s\n' vehicle relayed "from (count)"
for v in "${NAMES[@]}"; do
  uc=$(echo "$v" | tr a-z A-Z)
  rel=$(awk -v var="NODE_REPORT_$uc" '$2=="uFldNodeComms" && $3==var' shoreside.txt | grep -c . || true)
  from=$(awk -v var="NODE_REPORT_$uc" '$2=="uFldNodeComms" && $3==var {if (match($4, /NAME=[^,]*/)) n[substr($4, RSTART + 5, RLENGTH - 5)]++}
              END {s = ""; for (k in n) {s = s (s ? ", " : "") k " " n[k]}; print (s ? s : "-")}' shoreside.txt)
  printf '%-9s %8s %14s\n' "$v" "$rel" "$from"
done
echo "   comms pulses drawn: $(awk '$2=="uFldNodeComms" && $3=="VIEW_COMMS_PULSE"' shoreside.txt | grep -c . || true)"
echo "== picture: $W/fleet.png (and fleet.svg); logs: $W/*.lcm"
grep -E "^(vehicle|alpha|bravo|charlie|[a-z]+ +report)" plot.out | head -8
[ $rc_launch -eq 0 ] || echo "demo-fleet: a launcher did not end cleanly (see $W/launch_*.out)"
status=0
[ $done_all -eq 1 ] && [ $ok_all -eq 1 ] && [ $rc_launch -eq 0 ] || status=1
[ "$HEADLESS" = 1 ] && exit $status

# ---- after the run: the same page replays the shoreside log (time slider) until Ctrl-C
"$B/bin/kelp-viewer" --log shoreside.lcm --port "$VIEWER_PORT" shoreside.moos > replay.out 2>&1 &
REPLAY=$!; PIDS+=($REPLAY)
for _ in $(seq 100); do grep -q "^kelp-viewer: replaying" replay.out && break; kill -0 $REPLAY 2>/dev/null || break; sleep 0.1; done
grep -q "^kelp-viewer: replaying" replay.out || { cat replay.out; echo "demo-fleet: the replay did not start"; exit 1; }
echo "== the run's replay (kelp-viewer --log shoreside.lcm): $PAGE_URL   <- reload the page; Ctrl-C ends the demo"
trap 'trap "" INT TERM; kill -INT $REPLAY 2>/dev/null || true' INT TERM
wait $REPLAY || true
echo "== demo over"
exit $status
