#!/usr/bin/env bash
# alog2rng on the Indigo log of seed 000 (Listing 26 with the vehicle's NAV_* added) gives the
# seed's table (section 10.4.1) exactly: columns 03 02 01 in first-seen order, a row per burst
# (the third report of the first burst is logged 1 ms later but shares its time=), the _GT
# report left out, NAV_* as of the row; --nav=false drops the last three columns; the same log
# as an LCM log (kelp-alog to-lcm) gives the same ranges, timed from its first posting;
# MOOS-IvP's --nohdr, --delim and --report=flat are taken.
. "$(dirname "$0")/lib.sh"
cd "$T"
A="$KELP_ROOT/test/data/alog/indigo.alog"
printf 'Time\t03\t02\t01\tNAV_X\tNAV_Y\tNAV_HDG\n100.846\t166.7446\t515.6779\t304.6305\t-99.371\t-65.917\t238.000\n160.597\t210.2533\t602.1416\t418.3951\t-198.538\t-130.397\t197.456\n224.844\t163.4205\t558.5143\t433.6937\t-155.744\t-248.991\t159.000\n' > want.txt
"$BIN/alog2rng" "$A" > got.txt || fail "alog2rng exited $?"
diff want.txt got.txt || fail "table differs from the seed's"
"$BIN/alog2rng" --nav=false "$A" > nonav.txt || fail "--nav=false"
cut -f1-4 want.txt | diff - nonav.txt || fail "--nav=false table"
"$BIN/kelp-alog" to-lcm "$A" indigo.lcmlog > /dev/null || fail "to-lcm"
"$BIN/alog2rng" indigo.lcmlog > lcm.txt || fail "alog2rng on the LCM log"
diff <(cut -f2- want.txt) <(cut -f2- lcm.txt) || fail "LCM log: ranges or NAV differ"
[ "$(sed -n 2p lcm.txt | cut -f1)" = 45.149 ] || fail "LCM log: first row at $(sed -n 2p lcm.txt | cut -f1), expected 100.846 - 55.697"
# MOOS-IvP alog2rng's other switches: --nohdr, --delim=space|padded, --report=flat
"$BIN/alog2rng" --nohdr "$A" > nohdr.txt || fail "--nohdr"
tail -n +2 want.txt | diff - nohdr.txt || fail "--nohdr table"
"$BIN/alog2rng" --delim=space "$A" > space.txt || fail "--delim=space"
tr '\t' ' ' < want.txt | diff - space.txt || fail "--delim=space table"
"$BIN/alog2rng" --delim=padded "$A" > padded.txt || fail "--delim=padded"
[ -z "$(sed -n 1p padded.txt)" ] || fail "--delim=padded: a blank line first"
[ "$(sed -n 2p padded.txt)" = "Time       03          02          01          NAV_X      NAV_Y      NAV_HDG" ] || fail "--delim=padded header: $(sed -n 2p padded.txt)"
[ "$(sed -n 3p padded.txt)" = "100.846    166.7446    515.6779    304.6305    -99.371    -65.917    238.000    " ] || fail "--delim=padded row: $(sed -n 3p padded.txt)"
"$BIN/alog2rng" --report=flat --delim=tab "$A" > flat.txt || fail "--report=flat"
[ "$(sed -n 1p flat.txt)" = "$(printf 'Time\tID\tRange')" ] || fail "--report=flat header: $(sed -n 1p flat.txt)"
[ "$(sed -n 4p flat.txt)" = "$(printf '100.847\t01\t304.6305')" ] || fail "--report=flat row: $(sed -n 4p flat.txt)"
[ "$(wc -l < flat.txt)" -eq $(( $(grep -c 'BRS_RANGE_REPORT ' "$A") + 1 )) ] || fail "--report=flat: a row per report"
"$BIN/alog2rng" --vname=nobody "$A" > none.txt && fail "no rows should exit non-zero"
[ "$(wc -l < none.txt)" -eq 1 ] || fail "--vname=nobody printed rows"
ok "seed table reproduced from the .alog and from the LCM log"
