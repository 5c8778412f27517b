# The fleet demo (scripts/demo-fleet.sh, the main job of make demo): shoreside + three vehicle
# communities on separate LCM URLs joined by kelp-bridge. Every vehicle must finish its mission
# (survey waypoints, loiter, return) within the demo's time, the shoreside must have seen all
# three through the bridge, and the picture must be written.
. "$(dirname "$0")/lib.sh"
if [ ! -x "$BIN/pHelmIvP" ]; then echo "SKIP: pHelmIvP not built (the helm is on branch helm)"; exit 0; fi
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
cd $T
start=$(date +%s)
DEMO_DIR=$T/demo DEMO_TIMEOUT=50 "$KELP_ROOT/scripts/demo-fleet.sh" "$BUILD" > demo.out 2>&1 || { tail -40 demo.out; fail "demo-fleet.sh failed"; }
el=$(( $(date +%s) - start ))
sed -n '/^== summary/,$p' demo.out
[ $el -le 60 ] || fail "the demo took ${el}s (more than a minute)"
for v in alpha bravo charlie; do
  line=$(awk -v v="$v" '/^== summary/{s=1} s && $1==v' demo.out)
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
if [ -n "${FLEET_PNG:-}" ]; then cp $T/demo/fleet.png "$FLEET_PNG"; fi
ok "fleet demo in ${el}s: three missions complete, picture written"
