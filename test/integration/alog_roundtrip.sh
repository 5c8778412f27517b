#!/usr/bin/env bash
# kelp-alog: a log recorded from a short real run (uTimerScript posting a string with a
# number in it, a double and a numeric-looking string; kelp-poke posting from this community
# and from another) converts to a MOOS .alog and back to an LCM log with the same postings:
#  - with --exact --mark-types, identical (time, source, variable, kind, value), and the
#    second .alog is the first line for line (communities kept as source@community);
#  - with pLogger's defaults (5 decimals, no type marks), the same postings with numbers
#    equal to 1e-5 and numeric strings read back as numbers, as MOOS tools read them.
. "$(dirname "$0")/lib.sh"
cd "$T"
cat > a.moos <<'M'
Community = alpha
ServerPort = 9000
MOOSTimeWarp = 1
ProcessConfig = uTimerScript
{
  AppTick = 10
  event = var=REQ, val="name=archie,range=$[X]", time=0.2
  event = var=NUM, val={$[X]*2}, time=0.4
  event = var=NUMSTR, val="12.5", time=0.6
  rand_var = varname=X, min=0, max=100, key=at_post
  reset_time = all-posted
  seed = 3
}
M
sed 's/Community = alpha/Community = bravo/' a.moos > b.moos
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f run.lcmlog
sleep 0.5
bg "$BIN/uTimerScript" a.moos
sleep 1
"$BIN/kelp-poke" a.moos NAV_X=-99.371 NAV_Y=-65.917 NOTE:="two  spaces, trailing" > /dev/null || fail "poke alpha"
"$BIN/kelp-poke" b.moos NAV_HDG=238 > /dev/null || fail "poke bravo"
sleep 1
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print run.lcmlog > run.txt || fail "run log undecodable"
n=$(wc -l < run.txt)
[ "$n" -ge 20 ] || fail "only $n postings recorded"
# exact
"$BIN/kelp-alog" to-alog --exact --mark-types run.lcmlog x.alog > /dev/null || fail "to-alog --exact"
"$BIN/kelp-alog" to-lcm x.alog x.lcmlog > /dev/null || fail "to-lcm (exact)"
"$BIN/kelp-logcheck" --print x.lcmlog > x.txt || fail "converted log undecodable"
diff run.txt x.txt > x.diff || { head x.diff; fail "exact round trip differs"; }
"$BIN/kelp-alog" to-alog --exact --mark-types x.lcmlog x2.alog > /dev/null || fail "to-alog again"
diff <(grep -v -e '^%% LOG FILE' -e '^%% FILE OPENED' x.alog) <(grep -v -e '^%% LOG FILE' -e '^%% FILE OPENED' x2.alog) \
  || fail ".alog -> LCM -> .alog is not the same file"
grep -q ' kelp-poke@bravo ' x.alog || fail "the bravo posting is not marked source@community"
grep -q '^%% COMMUNITY *alpha' x.alog || fail "no community in the banner"
grep -qE '^[0-9.]+ +NOTE +kelp-poke +S:two  spaces, trailing $' x.alog || fail "string line: $(grep ' NOTE ' x.alog)"
# pLogger's defaults
"$BIN/kelp-alog" to-alog run.lcmlog d.alog > /dev/null || fail "to-alog"
head -1 d.alog | grep -qx '%\{59\}' || fail "banner: $(head -1 d.alog)"
grep -qE '^%% LOGSTART +[0-9]+\.[0-9]+$' d.alog || fail "no LOGSTART line"
grep -qE '^[0-9]+\.[0-9]{5} +NAV_X +kelp-poke +-99\.37100 +$' d.alog || fail "double line: $(grep ' NAV_X ' d.alog)"
"$BIN/kelp-alog" to-lcm d.alog d.lcmlog > /dev/null || fail "to-lcm"
"$BIN/kelp-logcheck" --print d.lcmlog > d.txt || fail "default round trip undecodable"
# same postings: time to 1e-4 (5 decimals of the time column), numbers to 1e-5, text equal
paste -d '\n' run.txt d.txt | awk '
  NR % 2 == 1 { t = $1; s = $2; v = $3; $1 = $2 = $3 = ""; val = substr($0, 4); next }
  { t2 = $1; s2 = $2; v2 = $3; $1 = $2 = $3 = ""; val2 = substr($0, 4);
    d = t - t2; if (d < 0) d = -d
    if (s != s2 || v != v2 || d > 1e-3) { print "posting " NR/2 ": " t " " s " " v " vs " t2 " " s2 " " v2; bad = 1; next }
    if (val == val2) next
    if (val ~ /^-?[0-9.e+-]+$/ && val2 ~ /^-?[0-9.e+-]+$/) { e = val - val2; if (e < 0) e = -e; if (e <= 1e-5) next }
    print "posting " NR/2 " (" v "): " val " vs " val2; bad = 1 }
  END { exit bad }' > d.diff || { head d.diff; fail "default round trip differs"; }
[ "$(wc -l < d.txt)" -eq "$n" ] || fail "$(wc -l < d.txt) postings after the default round trip, $n before"
grep -q ' NUMSTR 12.5$' d.txt || fail "NUMSTR should read back as the number 12.5"
ok "$n postings: identical after .alog (--exact) and back; equal to 1e-5 with pLogger's 5 decimals"
