#!/usr/bin/env bash
# kelp-moos2sql (the iMOOS2SQL role):
#  1. on the fleet demo's shoreside log (scripts/demo-fleet.sh, short run; or $M2S_DEMO_LOG):
#     the database's status / contact / track rows equal the log's NODE_REPORT(_LOCAL),
#     contact-manager and decoded-status postings (kelp-logcheck --print), the schema is at its
#     version with its indexes, WAL; the KML and its NetworkLink file are well-formed XML
#     (xmllint), valid against a KML subset schema, with one Placemark per vehicle;
#  2. live: postings from uTimerScript (node reports, contact reports, status messages), a
#     sqlite3 reader querying all the while (WAL: never fails), then kill -9 mid-stream: the
#     database passes its integrity check, every row is a posting that was made, and the rows
#     reach to shortly before the kill; the program reopens it and appends;
#  3. a version-1 database migrates to version 2; a database of a newer schema is refused.
. "$(dirname "$0")/lib.sh"
for t in sqlite3 xmllint; do command -v $t > /dev/null || fail "$t missing (scripts/deps.sh test)"; done
cd "$T"
M2S=$BIN/kelp-moos2sql
XSD=$KELP_ROOT/test/integration/data/kml_subset.xsd
# postings of a variable set in a --print listing: "time source VAR value"
count() { awk -v re="^($2)\$" '$3 ~ re' "$1" | wc -l; }
STATUS_RE='NODE_REPORT|NODE_REPORT_LOCAL'
CONTACT_RE='CONTACTS_LIST|CONTACTS_ALERTED|CONTACTS_UNALERTED|CONTACTS_RETIRED|CONTACTS_RECAP|CONTACTS_COUNT|CONTACT_CLOSEST|CONTACT_CLOSEST_RANGE|CONTACT_RANGES'
TRACK_RE='STATUS_REPORT|STATUS_SUMMARY|STATUS_REPORT_IN'
rows() { sqlite3 "$1" "SELECT count(*) FROM $2"; }

# ---- 1. the demo's log
log=${M2S_DEMO_LOG:-}
if [ -z "$log" ]; then
  [ -x "$BIN/pHelmIvP" ] || fail "pHelmIvP not built"
  DEMO_DIR=$T/demo DEMO_TIMEOUT=30 KELP_DEMO_HEADLESS=1 "$KELP_ROOT/scripts/demo-fleet.sh" "$BUILD" > demo.out 2>&1 || { tail -20 demo.out; fail "demo-fleet.sh"; }
  log=$T/demo/shoreside.lcm
fi
"$BIN/kelp-logcheck" --print "$log" > log.txt 2> /dev/null || true
ns=$(count log.txt "$STATUS_RE"); nc=$(count log.txt "$CONTACT_RE"); nt=$(count log.txt "$TRACK_RE")
[ "$ns" -gt 100 ] || fail "only $ns node reports in the demo's log"
"$M2S" --log="$log" --db=demo.db --kml=fleet.kml --link=fleet_link.kml > m2s.out || { cat m2s.out; fail "kelp-moos2sql --log: exit $?"; }
cat m2s.out
[ "$(rows demo.db status)" = "$ns" ] || fail "status rows $(rows demo.db status), log has $ns node reports"
[ "$(rows demo.db contact)" = "$nc" ] || fail "contact rows $(rows demo.db contact), log has $nc contact reports"
[ "$(rows demo.db track)" = "$nt" ] || fail "track rows $(rows demo.db track), log has $nt status messages"
# per vehicle too
for v in $(awk -v re="^($STATUS_RE)\$" '$3 ~ re' log.txt | sed -nE 's/.*[ ,]NAME=([^,]*).*/\1/p' | sort -u); do
  a=$(awk -v re="^($STATUS_RE)\$" '$3 ~ re' log.txt | grep -cE "[ ,]NAME=$v(,|\$)")
  b=$(sqlite3 demo.db "SELECT count(*) FROM status WHERE name = '$v'")
  [ "$a" = "$b" ] || fail "$v: $a node reports in the log, $b rows"
done
[ "$(sqlite3 demo.db 'PRAGMA user_version')" = 2 ] || fail "schema version $(sqlite3 demo.db 'PRAGMA user_version')"
[ "$(sqlite3 demo.db 'PRAGMA journal_mode')" = wal ] || fail "not in WAL mode"
idx=$(sqlite3 demo.db "SELECT name FROM sqlite_master WHERE type = 'index' ORDER BY name" | tr '\n' ' ')
[ "$idx" = "contact_name_time contact_time status_name_time status_time track_name_time track_time " ] || fail "indexes: $idx"
sqlite3 demo.db "EXPLAIN QUERY PLAN SELECT * FROM status WHERE name = 'alpha' AND time > 0" | grep -q status_name_time ||
  fail "a per-vehicle query does not use the (name, time) index"
ok "demo log: $ns status, $nc contact, $nt track rows, as in the log; schema 2, WAL, indexes"
for f in fleet.kml fleet_link.kml; do
  xmllint --noout "$f" || fail "$f is not well-formed"
  xmllint --noout --schema "$XSD" "$f" 2> xsd.err || { cat xsd.err; fail "$f does not validate against the KML subset"; }
done
vehicles=$(sqlite3 demo.db "SELECT DISTINCT name FROM status ORDER BY name" | tr '\n' ' ')
pm=$(xmllint --xpath "//*[local-name()='Placemark']/*[local-name()='name']/text()" fleet.kml | tr '\n' ' ' | sed 's/ *$/ /')
[ "$pm" = "$vehicles" ] || fail "placemarks '$pm', vehicles '$vehicles'"
[ "$(xmllint --xpath "count(//*[local-name()='Placemark'])" fleet.kml)" -ge 3 ] || fail "fewer than three placemarks"
[ "$(xmllint --xpath "string(//*[local-name()='href'])" fleet_link.kml)" = fleet.kml ] || fail "link href"
ok "KML: placemarks $pm(well-formed, valid against the subset schema); the NetworkLink file too"

# ---- 2. live, a reader all the while, kill -9 mid-stream
cat > live.moos <<'M'
Community = shoreside
ServerPort = 9000
MOOSTimeWarp = 1
LatOrigin = 43.825300
LongOrigin = -70.330400
ProcessConfig = uTimerScript
{
  AppTick = 40
  event = var=NODE_REPORT, val="NAME=alpha,TYPE=UUV,X=$[X],Y=5,SPD=1.5,HDG=90,MODE=SURVEY", time=0.02
  event = var=NODE_REPORT, val="NAME=bravo,TYPE=UUV,X=-10,Y=$[X],SPD=1,HDG=180", time=0.04
  event = var=CONTACTS_LIST, val="alpha,bravo", time=0.06
  event = var=CONTACTS_RECAP, val="vname=alpha,range=$[X],age=0.5 # vname=bravo,range=12.5,age=0.2", time=0.08
  event = var=STATUS_REPORT, val="name=charlie,nav_x=$[X],nav_y=-20,heading=45,speed=1.2", time=0.1
  rand_var = varname=X, min=0, max=100, key=at_post
  reset_time = all-posted
}
ProcessConfig = iMOOS2SQL
{
  AppTick = 4
  DATABASE = live.db
  KML_FILE = live.kml
  KML_LINK_FILE = live_link.kml
  KML_PERIOD = 0.5
  COMMIT_PERIOD = 0.25
}
M
bg "$BIN/kelp-record" -q --lcm-url="$KELP_LCM_URL" -f live.lcmlog
sleep 0.5
"$M2S" live.moos > live.out 2>&1 & M2S_PID=$!
PIDS+=($M2S_PID)
# the schema is there before the reader starts (a loaded machine may take longer than 0.5 s)
for _ in $(seq 100); do
  [ "$(sqlite3 live.db "SELECT count(*) FROM sqlite_master WHERE name = 'status'" 2> /dev/null)" = 1 ] && break
  sleep 0.1
done
bg "$BIN/uTimerScript" live.moos > uts.out 2>&1
# the reader: a query every 50 ms while the writer writes; any failure is recorded
( while :; do sqlite3 live.db "SELECT count(*), max(time) FROM status; SELECT count(*) FROM track" > /dev/null 2>> reader.err ||
    echo "query failed" >> reader.err; sleep 0.05; done ) & READER=$!
PIDS+=($READER)
# kill while it writes, once enough is in (4 s here; a loaded host may take longer, up to 30 s)
sleep 4
for _ in $(seq 260); do
  [ "$(rows live.db status 2>/dev/null || echo 0)" -gt 50 ] && [ "$(rows live.db contact 2>/dev/null || echo 0)" -gt 50 ] &&
    [ "$(rows live.db track 2>/dev/null || echo 0)" -gt 20 ] && break
  sleep 0.1
done
kill_time=$(date +%s.%N)
kill -9 $M2S_PID
wait $M2S_PID 2> /dev/null || true
kill $READER 2> /dev/null || true
sleep 0.5
for p in "${PIDS[@]}"; do kill -INT "$p" 2> /dev/null || true; done
wait 2> /dev/null || true
PIDS=()
[ ! -s reader.err ] || { head -5 reader.err; fail "a reader failed while the writer wrote"; }
[ "$(sqlite3 live.db 'PRAGMA integrity_check')" = ok ] || fail "integrity check after kill -9"
"$BIN/kelp-logcheck" --print live.lcmlog > live.txt 2> /dev/null || true
s=$(rows live.db status); c=$(rows live.db contact); t=$(rows live.db track)
[ "$s" -gt 50 ] && [ "$c" -gt 50 ] && [ "$t" -gt 20 ] || fail "after the kill: status $s, contact $c, track $t rows"
# every row is a posting that was made (no torn or invented rows)
awk '$3 == "NODE_REPORT" { $1 = $2 = $3 = ""; print substr($0, 4) }' live.txt | sort > posted.txt
sqlite3 live.db "SELECT report FROM status" | sort > stored.txt
[ -z "$(comm -13 posted.txt stored.txt)" ] || fail "rows that were never posted: $(comm -13 posted.txt stored.txt | head -2)"
# nothing committed is lost: every node report posted up to 1 s before the kill is there (commits every 0.25 s; slack for a loaded machine)
early=$(awk -v k="$kill_time" '$3 == "NODE_REPORT" && $1 < k - 1.0' live.txt | wc -l)
[ "$s" -ge "$early" ] || fail "$s status rows, but $early node reports were posted 1 s before the kill"
last=$(sqlite3 live.db "SELECT max(time) FROM status")
awk -v l="$last" -v k="$kill_time" 'BEGIN { exit !(l > k - 1.0) }' || fail "the last row ($last) is long before the kill ($kill_time)"
xmllint --noout --schema "$XSD" live.kml 2> /dev/null || fail "live.kml (x/y reports, datum) does not validate"
pm=$(xmllint --xpath "//*[local-name()='Placemark']/*[local-name()='name']/text()" live.kml | tr '\n' ' ')
[ "$pm" = "alpha bravo charlie " ] || fail "live placemarks: '$pm'"
ok "kill -9 mid-stream: $s status, $c contact, $t track rows intact (integrity ok), the last $(awk -v l="$last" -v k="$kill_time" 'BEGIN{printf "%.2f", k - l}') s before the kill; reader never failed"
# the live run's log (with contact reports, which the demo has none of): rows = postings, all kinds
"$M2S" --log=live.lcmlog --db=fresh.db --kml= > fresh.out || { cat fresh.out; fail "kelp-moos2sql --log=live.lcmlog"; }
for k in status:$STATUS_RE contact:$CONTACT_RE track:$TRACK_RE; do
  n=$(count live.txt "${k#*:}")
  [ "$n" -gt 20 ] && [ "$(rows fresh.db ${k%%:*})" = "$n" ] || fail "${k%%:*}: $(rows fresh.db ${k%%:*}) rows, $n postings in the live log"
done
ok "the live run's log: status, contact and track rows equal its postings"
"$M2S" --log=live.lcmlog --db=live.db --kml= > again.out || { cat again.out; fail "reopening the killed database"; }
[ "$(rows live.db status)" -gt "$s" ] || fail "nothing appended after reopening"
ok "the killed database reopens and takes more rows"

# ---- 3. migrations: a version-1 database (no time indexes) is brought to version 2, its rows
# kept; a database of a newer schema is refused
cp demo.db old.db
sqlite3 old.db "DROP INDEX status_time; DROP INDEX contact_time; DROP INDEX track_time; PRAGMA user_version = 1"
"$M2S" --log=live.lcmlog --db=old.db --kml= > old.out || { cat old.out; fail "migrating a version-1 database"; }
[ "$(sqlite3 old.db 'PRAGMA user_version')" = 2 ] || fail "version-1 database left at $(sqlite3 old.db 'PRAGMA user_version')"
[ "$(sqlite3 old.db "SELECT count(*) FROM sqlite_master WHERE type = 'index'")" = 6 ] || fail "migration 2 did not add the indexes"
[ "$(rows old.db status)" -gt "$ns" ] || fail "rows lost or none added in the migrated database"
ok "a version-1 database migrates to version 2 with its rows"
sqlite3 new.db "PRAGMA user_version = 99"
rc=0; "$M2S" --log=live.lcmlog --db=new.db --kml= > new.out 2> new.err || rc=$?
[ $rc -eq 1 ] && grep -q "newer" new.err || fail "a version-99 database: exit $rc, $(cat new.err)"
ok "a database of a newer schema is refused"
