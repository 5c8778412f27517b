#!/usr/bin/env bash
# The encounter mission (missions/encounter): vehicles on crossing, head-on and overtaking
# tracks, each with pContactMgrV20 and the collision-avoidance template; contacts learned
# through the shoreside (uFldNodeComms relays every vehicle's node reports to the others).
# At the end: each pair's closest approach (kelp-plot --closest on the shoreside log), the
# avoidance behaviours each helm spawned and removed, and a picture.
#   usage: scripts/encounter.sh [--no-avoid] [CONF] [BUILD_DIR]
#          CONF: missions/encounter/pair.conf (default) or five.conf
#          --no-avoid: the same mission with AVOID=false (the template never spawns)
#   env: ENC_WARP (10), ENC_TIMEOUT (60 s wall), ENC_DIR (build/encounter-<conf>[-noavoid])
# Exit 0 when every vehicle reached its goal.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
ARGS=("$@")
AVOID=true
[ "${1:-}" = "--no-avoid" ] && { AVOID=false; shift; }
CONF=$(readlink -f "${1:-$ROOT/missions/encounter/pair.conf}")
B=$(cd "${2:-$ROOT/build}" && pwd)
WARP=${ENC_WARP:-10}
TIMEOUT=${ENC_TIMEOUT:-60}
. "$ROOT/scripts/fleet-lib.sh"
fleet_private_netns "$0" "${ARGS[@]}"
for p in kelp-launch kelp-poke kelp-bridge kelp-plot kelp-logcheck kelp-record uSimMarine pNodeReporter pHelmIvP \
         pContactMgrV20 uFldNodeBroker uFldShoreBroker uFldNodeComms pHostInfo; do
  [ -x "$B/bin/$p" ] || { echo "encounter: $B/bin/$p not built (run make)"; exit 1; }
done
unset KELP_LCM_URL
M=$ROOT/missions/encounter
base=$(basename "$CONF" .conf)
W=${ENC_DIR:-$ROOT/build/encounter-$base$([ $AVOID = true ] || echo -noavoid)}
rm -rf "$W"; mkdir -p "$W"; cd "$W"
SHORE_LCM=7780 SHORE_BRIDGE=9300

NAMES=()
i=0
while IFS='|' read -r name lport bport start speed goal; do
  name=$(trim "$name"); [ -z "$name" ] || [ "${name:0:1}" = "#" ] && continue
  lport=$(trim "$lport"); bport=$(trim "$bport"); start=$(trim "$start"); speed=$(trim "$speed"); goal=$(trim "$goal")
  IFS=, read -r sx sy sh <<< "$start"
  i=$((i + 1)); NAMES+=("$name")
  fill "$M/meta_vehicle.moos" VNAME="$name" VNAME_UC="$(echo "$name" | tr a-z A-Z)" MOOS_PORT=$((9000 + i)) WARP="$WARP" \
       LCM_PORT="$lport" START_POS="x=$sx, y=$sy, heading=$sh, speed=0" BRIDGE_PORT="$bport" SHORE_BRIDGE="$SHORE_BRIDGE" \
       > "$name.moos"
  fill "$M/meta_vehicle.bhv" VNAME="$name" SPEED="$speed" GOAL="$goal" AVOID="$AVOID" > "$name.bhv"
done < "$CONF"
[ ${#NAMES[@]} -ge 2 ] || { echo "encounter: fewer than two vehicles in $CONF"; exit 1; }
fill "$M/meta_shoreside.moos" WARP="$WARP" SHORE_LCM="$SHORE_LCM" SHORE_BRIDGE="$SHORE_BRIDGE" > shoreside.moos

echo "== kelp encounter ($base): ${NAMES[*]}; avoidance $AVOID; MOOSTimeWarp $WARP; missions in $W"
export KELP_WARP_EPOCH=$(date +%s.%N)
trap fleet_cleanup EXIT
fleet_start $((TIMEOUT + 10)) "${NAMES[@]}"
fleet_wait_handshake "$SHORE_BRIDGE" "${NAMES[@]}" || { echo "encounter: not every vehicle found the shoreside"; exit 1; }
sleep 1
"$B/bin/kelp-poke" shoreside.moos DEPLOY_ALL:=true MOOS_MANUAL_OVERIDE_ALL:=false > poke_deploy.out
t0=$(date +%s)
done_all=0
while :; do
  sleep 2
  "$B/bin/kelp-logcheck" shoreside.lcm --print > shoreside.txt 2>/dev/null || true
  ndone=$(awk '$3 ~ /^MISSION_/ && $4=="complete" {d[$3]=1} END{print length(d)}' shoreside.txt)
  if [ "${ndone:-0}" -ge ${#NAMES[@]} ]; then done_all=1; break; fi
  [ $(( $(date +%s) - t0 )) -ge "$TIMEOUT" ] && break
done
sleep 1
fleet_stop

"$B/bin/kelp-plot" --closest shoreside.lcm -o encounter.png -o encounter.svg \
  --title "kelp encounter ($base): avoidance $AVOID, closest approach of each pair" > plot.out || { cat plot.out; exit 1; }
echo "== closest approach of each pair (shoreside node reports)"
grep '^closest ' plot.out | sed 's/^closest /   /'
echo "== avoidance behaviours per vehicle (spawned / removed), mission"
for v in "${NAMES[@]}"; do
  "$B/bin/kelp-logcheck" "$v.lcm" --print > "$v.txt" 2>/dev/null || true
  sp=$(awk '$2=="pHelmIvP" && $3=="IVPHELM_LIFE_EVENT" && /btype=BHV_AvoidCollision/ && /event=spawn/' "$v.txt" | grep -c . || true)
  rm=$(awk '$2=="pHelmIvP" && $3=="IVPHELM_LIFE_EVENT" && /btype=BHV_AvoidCollision/ && /event=death/' "$v.txt" | grep -c . || true)
  ms=$(awk '$2=="pHelmIvP" && $3=="MISSION" {m=$4} END{print m ? m : "-"}' "$v.txt")
  al=$(awk '$2=="pContactMgrV20" && $3=="CONTACT_INFO"' "$v.txt" | grep -c . || true)
  printf '   %-9s alerts %3s  spawned %3s  removed %3s  mission %s\n' "$v" "$al" "$sp" "$rm" "$ms"
done
echo "== picture: $W/encounter.png"
[ $done_all -eq 1 ]
