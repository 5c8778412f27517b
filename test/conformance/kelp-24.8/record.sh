#!/usr/bin/env bash
# Record a golden transcript of a kelp-owned vehicle scenario on the REAL MOOS-IvP 24.8 apps (not
# run by the tests: it needs a MOOS-IvP build).
#
#   record.sh SCENARIO MOOS_BIN PLOGGER [PORT]
#
# The scenario's .moos is copied with its files (the .bhv), its port set to PORT and a pLogger
# block appended (everything logged, MarkDataType, LogAuxSrc); MOOSDB and each app of its
# ANTLER block start as `<app> <file>.moos --alias=<app> --moos_suicide_disable`; `settle`
# seconds later the .scn's `at` posts are made with uPokeDB at their script times (warped);
# after `duration` every process is stopped and alog2golden.py writes golden/SCENARIO.jsonl and
# .meta.json. Only `warp`, `duration`, `settle` and `at T str|dbl VAR VALUE` lines are played.
set -u
here=$(cd "$(dirname "$0")" && pwd)
scn=$1 BIN=$2 PLOGGER=$3 PORT=${4:-9101}
W=$(mktemp -d /tmp/record-$scn.XXXXXX)
cp "$here/missions/$scn.moos" "$W/"
for f in "$here/missions/$scn".*; do case "$f" in *.moos|*.scn) ;; *) cp "$f" "$W/" ;; esac; done
cd "$W"
sed -i "s/^ServerPort *=.*/ServerPort = $PORT/; s/^ServerHost *=.*/ServerHost = 127.0.0.1/" "$scn.moos"
cat >> "$scn.moos" <<'EOF'

ProcessConfig = pLogger
{
  AppTick   = 10
  CommsTick = 10
  File = RUN
  PATH = ./
  FileTimeStamp = false
  AsyncLog = true
  WildCardLogging = true
  LogAuxSrc = true
  MarkDataType = true
  DoublePrecision = 12
}
EOF
warp=$(awk '$1=="warp"{print $2}' "$here/missions/$scn.scn")
dur=$(awk '$1=="duration"{print $2}' "$here/missions/$scn.scn")
settle=$(awk '$1=="settle"{print $2}' "$here/missions/$scn.scn")
pids=()
"$BIN/MOOSDB" "$scn.moos" > MOOSDB.out 2>&1 & pids+=($!)
sleep 0.5
"$PLOGGER" "$scn.moos" --alias=pLogger > pLogger.out 2>&1 & pids+=($!)
for a in $(sed -n 's/^ *Run *= *\([A-Za-z0-9_]*\).*/\1/p' "$scn.moos" | grep -v MOOSDB); do
  "$BIN/$a" "$scn.moos" --alias=$a --moos_suicide_disable > $a.out 2>&1 & pids+=($!)
done
sleep "$settle"
start=$(date +%s.%N)
# the script's posts, at their times (one uPokeDB per time: a connection takes a while)
awk '$1=="at" {v = $5; for (i = 6; i <= NF; i++) v = v " " $i; a[$2] = a[$2] " " $4 ($3 == "str" ? ":=" : "=") v}
     END {for (t in a) print t a[t]}' "$here/missions/$scn.scn" | sort -n | while read -r t posts; do
  now=$(date +%s.%N)
  d=$(awk -v s="$start" -v n="$now" -v t="$t" -v w="$warp" 'BEGIN{d = s + t / w - n; print (d > 0 ? d : 0)}')
  sleep "$d"
  # shellcheck disable=SC2086
  "$BIN/uPokeDB" "$scn.moos" $posts > /dev/null 2>&1
done
sleep "$(awk -v d="$dur" -v w="$warp" -v s="$start" -v n="$(date +%s.%N)" 'BEGIN{x = s + d / w + 1 - n; print (x > 0 ? x : 0)}')"
for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null; done
sleep 1
for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
wait 2>/dev/null
python3 "$here/alog2golden.py" RUN/RUN.alog "$here/missions/$scn.scn" "$here/golden/$scn.jsonl" "$here/golden/$scn.meta.json"
echo "recorded in $W"
