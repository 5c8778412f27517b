#!/usr/bin/env bash
# The conformance suite: replay recorded runs of the real MOOS-IvP 24.8 apps on kelp and compare.
#
#   test/conformance/run.sh [SCENARIO ...]        (make conformance; default: every scenario)
#
# For each scenario of the recordings (below), and of kelp's own recordings of the real apps in
# test/conformance/kelp-24.8 (vehicle runs; with the default recordings only): the .moos file
# and the files it names beside it (a Behaviors = .bhv) are copied unchanged and, unless the
# mission has its own, an ANTLER block is appended (one Run = line per ProcessConfig block,
# under its 24.8 name: kelp-launch maps names such as uSimMarineV22 or pShare to kelp's
# programs); in its own private network namespace (loopback only, ttl=0, its
# own port) conform-driver joins, then kelp-launch starts the apps (their start-up posts are
# heard on a loaded host too); the driver starts the script with a one-app mission's app at the
# recorded phase of its iterations and the recorded uptime (compare.py --phase), plays the .scn
# script and records kelp's transcript. The scenarios run side by side in two batches (the recordings', then kelp's own), then
# compare.py compares each transcript with the recording, figure by figure, and prints the
# table. Output: $BUILD/conformance/<scenario>.{jsonl,meta.json,launch.log}, report.txt.
# Exit status: 0 when every gated scenario agrees except for the differences listed in
# docs/CONFORMANCE.md.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
BUILD=${BUILD:-$root/build}
# the recordings: $KELP_CONF_DIR, else the shared copy beside the project when there is one,
# else the project's own copy (test/conformance/moos-ivp-24.8, transcripts gzipped)
CONF=${KELP_CONF_DIR:-}
if [ -z "$CONF" ]; then
  CONF=$root/test/conformance/moos-ivp-24.8
  [ -d "$root/../shared/conformance/moos-ivp-24.8/missions" ] && CONF=$(cd "$root/../shared/conformance/moos-ivp-24.8" && pwd)
fi
[ -d "$CONF/missions" ] || { echo "conformance: no recordings at $CONF (set KELP_CONF_DIR)"; exit 2; }
OUT=$BUILD/conformance
mkdir -p "$OUT"
scenarios=("$@")
if [ ${#scenarios[@]} -eq 0 ]; then
  for f in "$CONF"/missions/*.scn; do scenarios+=("$(basename "$f" .scn)"); done
  if [ -z "${KELP_CONF_DIR:-}" ]; then
    for f in "$root"/test/conformance/kelp-24.8/missions/*.scn; do [ -f "$f" ] && scenarios+=("$(basename "$f" .scn)"); done
  fi
fi

# the kelp-owned scenarios (vehicle runs of the real apps recorded for kelp): run beside the
# recordings' unless a recordings directory or scenarios are named
OWN=$root/test/conformance/kelp-24.8
# where a scenario's files are: the recordings, else kelp's own
conf_of() {
  if [ -f "$CONF/missions/$1.scn" ]; then echo "$CONF"; elif [ -f "$OWN/missions/$1.scn" ]; then echo "$OWN"; fi
}

# one scenario, inside its own network namespace (re-entered through unshare)
if [ "${1:-}" = --inside ]; then
  scn=$2 port=$3 SC=$4
  ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo 2>/dev/null
  W=$(mktemp -d /tmp/kelp-conf-$scn.XXXXXX)
  cp "$SC/missions/$scn.moos" "$W/$scn.moos"
  # the files the mission names beside it (a Behaviors = .bhv, ...), copied unchanged
  sed -n 's/^[^=/]*=[[:space:]]*\([^[:space:],@~]*\)[[:space:]]*$/\1/p' "$SC/missions/$scn.moos" | sort -u |
    while read -r f; do
      case "$f" in */*|.*|"") continue ;; esac
      [ -f "$SC/missions/$f" ] && cp "$SC/missions/$f" "$W/$f"
    done
  # an ANTLER block of the mission's own is kept (its Run = lines name 24.8's apps, which
  # kelp-launch maps); without one, one Run = line per ProcessConfig block
  if ! grep -qiE '^[[:space:]]*ProcessConfig[[:space:]]*=[[:space:]]*ANTLER[[:space:]]*$' "$W/$scn.moos"; then
    {
      echo
      echo "// appended by kelp's conformance runner: launch every block of this mission"
      echo "ProcessConfig = ANTLER"
      echo "{"
      echo "  MSBetweenLaunches = 100"
      echo "  Run = MOOSDB @ NewConsole = false"
      sed -n 's/^[[:space:]]*ProcessConfig[[:space:]]*=[[:space:]]*\([A-Za-z0-9_]*\).*/\1/p' "$SC/missions/$scn.moos" |
        grep -v '^ANTLER$' | while read -r app; do echo "  Run = $app @ NewConsole = false"; done
      echo "}"
    } >> "$W/$scn.moos"
  fi
  export KELP_LCM_URL="udpm://239.255.76.67:$port?ttl=0"
  # the driver joins first and the apps start once it has (it touches $W/.joined): what the
  # apps post as they start is heard however loaded the host, as in the recordings
  # and starts its script at the phase of the app's iterations the recording has
  phase=$(python3 "$here/compare.py" --phase "$SC" "$scn")
  (cd "$W" && export KELP_CONF_JOINED="$W/.joined" KELP_CONF_PHASE="$phase" && exec "$BUILD/test/conform-driver" "$SC/missions/$scn.scn" "$W/$scn.moos" \
    "$OUT/$scn.jsonl" "$OUT/$scn.meta.json") > "$OUT/$scn.driver.log" 2>&1 &
  dp=$!
  for _ in $(seq 200); do [ -e "$W/.joined" ] || ! kill -0 $dp 2>/dev/null && break; sleep 0.05; done
  # a one-app mission whose recorded uptime at t0 is shorter than the driver's settle (the
  # recorded app's first iteration came ~0.9 s after its start: compare.py --phase) starts that
  # much later, so that kelp's app can be as young at t0 as the recorded one was
  lag=$(awk -v up="$(echo "$phase" | awk '{print $4}')" '$1=="settle"{s=$2} $1=="warp"{w=$2}
        END{if(up==""||w<=0){print 0; exit} d=s+0.1-up/w; print (d>0?d:0)}' "$SC/missions/$scn.scn")
  sleep "$lag"
  (cd "$W" && exec "$BUILD/bin/kelp-launch" "$scn.moos") > "$OUT/$scn.launch.log" 2>&1 &
  lp=$!
  wait $dp
  rc=$?
  kill -INT $lp 2>/dev/null; wait $lp 2>/dev/null
  cp "$W"/*.log "$OUT/" 2>/dev/null || true
  rm -rf "$W"
  exit $rc
fi

start=$(date +%s)
for scn in "${scenarios[@]}"; do [ -n "$(conf_of "$scn")" ] || { echo "conformance: no scenario $scn"; exit 2; }; done
# batches, each side by side (they mostly wait on MOOS time): the recordings' scenarios, then
# kelp's own that are reported, then kelp's own that are gated (the vehicle runs); one batch
# at a time keeps a 2-core host from slipping the apps' iterations
fail=0
i=0
gated() { python3 "$here/compare.py" --gated "$1"; }
# KELP_CONF_SKIP_REPORTED (CI): leave out kelp's own scenarios that gate nothing
if [ -n "${KELP_CONF_SKIP_REPORTED:-}" ]; then
  kept=()
  for scn in "${scenarios[@]}"; do
    if [ "$(conf_of "$scn")" = "$OWN" ] && ! gated "$scn"; then continue; fi
    kept+=("$scn")
  done
  scenarios=("${kept[@]}")
fi
for part in "$CONF" "$OWN:reported" "$OWN:gated"; do
  sc=${part%%:*} kind=${part#"$sc"}
  batch=()
  for scn in "${scenarios[@]}"; do
    [ "$(conf_of "$scn")" = "$sc" ] || continue
    if [ "$kind" = ":reported" ]; then gated "$scn" && continue; fi
    if [ "$kind" = ":gated" ]; then gated "$scn" || continue; fi
    batch+=("$scn")
  done
  [ ${#batch[@]} -gt 0 ] || continue
  echo "conformance: ${#batch[@]} scenarios side by side (recordings: $sc)"
  pids=()
  for scn in "${batch[@]}"; do
    rm -f "$OUT/$scn.jsonl" "$OUT/$scn.meta.json"
    port=$((7300 + i)); i=$((i + 1))
    if [ "$(id -u)" -eq 0 ]; then unshare -n bash "$0" --inside "$scn" "$port" "$sc" &
    else unshare -rn bash "$0" --inside "$scn" "$port" "$sc" & fi
    pids+=($!)
  done
  for k in "${!pids[@]}"; do
    if ! wait "${pids[$k]}"; then echo "conformance: ${batch[$k]}: the run failed (see $OUT/${batch[$k]}.driver.log)"; fail=1; fi
  done
done
echo "conformance: runs done in $(( $(date +%s) - start )) s"
# compared per recordings directory: the recordings', then kelp's own
rc=0
: > "$OUT/report.txt"
for sc in "$CONF" "$OWN"; do
  list=()
  for scn in "${scenarios[@]}"; do [ "$(conf_of "$scn")" = "$sc" ] && list+=("$scn"); done
  [ ${#list[@]} -gt 0 ] || continue
  python3 "$here/compare.py" --golden "$sc" --kelp "$OUT" --allow "$root/docs/CONFORMANCE.md" --open "$here/open.txt" \
    ${KELP_CONF_WRITE_OPEN:+--write-open "$KELP_CONF_WRITE_OPEN.part"} "${list[@]}" | tee -a "$OUT/report.txt"
  [ "${PIPESTATUS[0]}" -eq 0 ] || rc=1
  [ -n "${KELP_CONF_WRITE_OPEN:-}" ] && cat "$KELP_CONF_WRITE_OPEN.part" >> "$KELP_CONF_WRITE_OPEN.all" && rm -f "$KELP_CONF_WRITE_OPEN.part"
done
[ -n "${KELP_CONF_WRITE_OPEN:-}" ] && mv "$KELP_CONF_WRITE_OPEN.all" "$KELP_CONF_WRITE_OPEN"
[ $fail -eq 0 ] && [ "$rc" -eq 0 ]
