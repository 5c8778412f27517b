#!/usr/bin/env bash
# kelp-spy (lcm-spy with kelp's types), installed by scripts/install.sh, watches the Alder
# mission under a virtual X server. kelp-spy takes the bus from the mission file's LCM_URL;
# lcm-spy loads every kelp type (lcmtypes/); its table fills with the mission's channels; a channel of
# unknown type (0_PROBE, kelp-lcmprobe's payload, first in the sorted table) opens an empty
# detail view while the next row, a kelp var_t, opens one with its decoded fields (measured as
# ink: no OCR here); clicking the dval field opens its plot (jchart2d). Screenshots go to
# $BUILD/spy/.
. "$(dirname "$0")/lib.sh"
for c in Xvfb xdotool import identify java; do
  command -v $c > /dev/null || fail "$c missing (scripts/deps.sh test installs it)"
done
[ -f "$BUILD/kelp_types.jar" ] || fail "$BUILD/kelp_types.jar missing (make spy-jar)"
[ -x "$BIN/pHelmIvP" ] || fail "pHelmIvP not built"
SHOTS=$BUILD/spy
mkdir -p "$SHOTS"
rm -f "$SHOTS"/*.png
cd "$T"
P=$T/prefix
out=$(PREFIX=$P "$KELP_ROOT/scripts/install.sh" "$BUILD" 2>&1) || fail "install: $out"
[ -f "$P/share/java/kelp_types.jar" ] || fail "kelp_types.jar not installed"

# which bus: --lcm-url, else $KELP_LCM_URL, else the mission's global LCM_URL, else its
# ServerPort, else the default (the apps' order); checked without a display, where kelp-spy
# says which bus and jar it would use and stops
bus() { env -u DISPLAY KELP_TYPES_JAR=$T/types.jar "$P/bin/kelp-spy" "$@" 2>&1 | sed -n 's/^kelp-spy: \(.*\); types from .*/\1/p'; }
touch types.jar
printf '%s\n' 'ServerHost = localhost' '  serverport = 9123  // a comment' 'ProcessConfig = uXMS' '{' '  LCM_URL = udpm://239.255.76.67:1?ttl=0' '}' > port.moos
printf '%s\n' '// LCM_URL = udpm://239.255.76.67:2?ttl=0' 'LCM_URL = udpm://239.255.76.67:3?ttl=0' 'ServerPort = 9123' > url.moos
[ "$(KELP_LCM_URL="" bus port.moos)" = "udpm://239.255.76.67:9123?ttl=0" ] || fail "ServerPort: $(KELP_LCM_URL="" bus port.moos)"
[ "$(KELP_LCM_URL="" bus url.moos)" = "udpm://239.255.76.67:3?ttl=0" ] || fail "LCM_URL: $(KELP_LCM_URL="" bus url.moos)"
[ "$(KELP_LCM_URL="" bus)" = "udpm://239.255.76.67:7667?ttl=0" ] || fail "default: $(KELP_LCM_URL="" bus)"
[ "$(KELP_LCM_URL="udpm://239.255.76.67:4?ttl=0" bus url.moos)" = "udpm://239.255.76.67:4?ttl=0" ] || fail "KELP_LCM_URL does not win"
[ "$(bus --lcm-url="udpm://239.255.76.67:5?ttl=0" url.moos)" = "udpm://239.255.76.67:5?ttl=0" ] || fail "--lcm-url does not win"
[ "$(bus -l "udpm://239.255.76.67:6?ttl=0")" = "udpm://239.255.76.67:6?ttl=0" ] || fail "-l URL"
env -u DISPLAY "$P/bin/kelp-spy" url.moos > nodisplay.out 2>&1 && fail "kelp-spy ran without a display"
grep -q "no X display" nodisplay.out || fail "no display: $(cat nodisplay.out)"
grep -qF "types from $P/share/java/kelp_types.jar" nodisplay.out || fail "installed kelp-spy did not take the installed jar: $(cat nodisplay.out)"
rc=0; KELP_TYPES_JAR=$T/none.jar "$P/bin/kelp-spy" > missing.out 2>&1 || rc=$?
[ $rc -eq 1 ] && grep -q "KELP_TYPES_JAR=$T/none.jar: no such file" missing.out || fail "missing jar: exit $rc, $(cat missing.out)"
ok "kelp-spy's bus: --lcm-url, \$KELP_LCM_URL, the mission's LCM_URL, its ServerPort, the default"

cp "$KELP_ROOT"/missions/alder/alder.{moos,bhv} .
sed -i "s|^ServerPort *=.*|LCM_URL = $KELP_LCM_URL|" alder.moos
grep -q "^LCM_URL = " alder.moos || fail "could not set LCM_URL in the mission"

# the X server picks a free display and writes its number on fd 3
Xvfb -displayfd 3 -screen 0 1600x1300x24 -nolisten tcp 3> display.txt > xvfb.out 2>&1 & PIDS+=($!)
for _ in $(seq 100); do [ -s display.txt ] && break; sleep 0.1; done
[ -s display.txt ] || { cat xvfb.out; fail "Xvfb did not start"; }
export DISPLAY=:$(cat display.txt)

# the installed launcher, the bus from the mission file (not from $KELP_LCM_URL)
env -u KELP_LCM_URL "$P/bin/kelp-spy" alder.moos > spy.out 2>&1 & PIDS+=($!)
timeout 30 xdotool search --sync --name '^LCM Spy$' > main.id 2> /dev/null || { cat spy.out; fail "no LCM Spy window"; }
main=$(head -1 main.id)
grep -qF "kelp-spy: $KELP_LCM_URL;" spy.out || { cat spy.out; fail "kelp-spy did not take the mission's LCM_URL"; }
ntypes=$(ls "$KELP_ROOT"/lcmtypes/*.lcm | wc -l)
wait_for spy.out "^Found [0-9]+ LCM types" 10 || { cat spy.out; fail "lcm-spy did not report its types"; }
found=$(sed -n 's/^Found \([0-9]*\) LCM types.*/\1/p' spy.out)
[ "$found" -eq "$ntypes" ] || { cat spy.out; fail "lcm-spy found $found LCM types, lcmtypes/ has $ntypes"; }
ok "kelp-spy from the install prefix: the mission's bus, $found kelp types loaded"
# taller, for more rows in the screenshot (Java may size its frame again just after mapping it)
for _ in $(seq 20); do
  xdotool windowsize "$main" 900 1290 2> /dev/null || true
  sleep 0.3
  xdotool getwindowgeometry "$main" 2> /dev/null | grep -q "Geometry: 900x1290" && break
done

# the mission, and a channel no kelp type decodes
"$BIN/kelp-launch" --run-seconds 45 --log-dir logs alder.moos > launch.out 2>&1 & PIDS+=($!)
"$BIN/kelp-lcmprobe" --channel=0_PROBE send kelp 100000 40 5 > probe.out 2>&1 & PIDS+=($!)
sleep 1.5
"$BIN/kelp-poke" alder.moos DEPLOY:=true MOOS_MANUAL_OVERIDE:=false > poke.out || fail "poke DEPLOY"

# ink: the fraction of a picture that is not background (0 = blank)
ink() { identify -format '%[fx:1-mean]' "$1"; }
# lcm-spy's table (sorted by channel): header 20 px, then rows of 16 px; wait until row 20
# (the 21st channel) has a name
row_y() { echo $((27 + 16 * $1)); }
for _ in $(seq 60); do
  import -window "$main" -crop 120x12+2+$(($(row_y 20) - 6)) +repage row20.png 2> /dev/null || true
  [ -f row20.png ] && awk -v i="$(ink row20.png)" 'BEGIN { exit !(i > 0.05) }' && break
  rm -f row20.png; sleep 0.5
done
[ -f row20.png ] || fail "lcm-spy's table did not fill with the mission's channels in 30 s"
import -window root "$SHOTS/spy-main.png"
ok "lcm-spy lists 21+ channels: $SHOTS/spy-main.png"

# move a window once it is mapped (Java places a new frame itself first: no window manager here)
place() { # WIN X Y: until it has stayed there for 0.3 s
  local at=0
  for _ in $(seq 40); do
    if xdotool getwindowgeometry "$1" 2> /dev/null | grep -q "Position: $2,$3 "; then
      at=$((at + 1)); [ $at -ge 2 ] && return 0
    else
      at=0; xdotool windowmove "$1" "$2" "$3" 2> /dev/null || true
    fi
    sleep 0.3
  done
  return 1
}
# open a row's detail view: double-click, then the new window, named after the channel
open_row() { # ROW X Y: prints the new window's id and name
  local before w
  before=$(xdotool search --name '^[0-9A-Z_]+$' 2> /dev/null | sort || true)
  for _ in 1 2 3; do
    xdotool mousemove --window "$main" 60 "$(row_y "$1")" click --repeat 2 --delay 60 1
    for _ in $(seq 20); do
      for w in $(xdotool search --onlyvisible --name '^[0-9A-Z_]+$' 2> /dev/null || true); do
        grep -qx "$w" <<< "$before" && continue
        name=$(xdotool getwindowname "$w")
        [[ "$name" =~ ^[0-9A-Z_]+$ ]] || continue   # xdotool's match ignores case
        place "$w" "$2" "$3" || return 1
        echo "$w $name"; return 0
      done
      sleep 0.25
    done
  done
  return 1
}
read -r cw cname < <(open_row 0 910 0) || fail "double-click on row 0 opened no detail view"
[ "$cname" = 0_PROBE ] || fail "row 0 is $cname, not 0_PROBE"
read -r kw kname < <(open_row 1 910 420) || fail "double-click on row 1 opened no detail view"
# a detail view opens on the channel's last message; wait until it is painted
kink=0
for _ in $(seq 40); do
  sleep 0.5
  import -window "$kw" detail-kelp.png 2> /dev/null || continue
  kink=$(ink detail-kelp.png)
  awk -v i="$kink" 'BEGIN { exit !(i > 0.03) }' && break
done
import -window "$cw" detail-probe.png || fail "no picture of 0_PROBE's view"
cink=$(ink detail-probe.png)
echo "detail views' ink: $kname $kink, 0_PROBE (unknown type) $cink"
awk -v k="$kink" -v c="$cink" 'BEGIN { exit !(k > 0.03 && k > 5 * c) }' ||
  fail "$kname's detail view does not show decoded fields (ink $kink, against $cink for a type lcm-spy cannot decode)"
ok "$kname decoded field by field; 0_PROBE, of no known type, not"

# a field's plot over time (jchart2d): click on dval, the 7th field of var_t (rows are 15 px)
chart=""
for _ in 1 2 3; do
  xdotool mousemove --window "$kw" 520 123 click 1
  chart=$(timeout 5 xdotool search --sync --name '^dval$' 2> /dev/null | head -1) && [ -n "$chart" ] && break
done
[ -n "$chart" ] || { cat spy.out; fail "clicking dval opened no plot"; }
place "$chart" 910 830 || fail "could not move the plot window"
sleep 1.5
grep -q "NoClassDefFoundError\|Exception" spy.out && { cat spy.out; fail "lcm-spy threw"; }
import -window root "$SHOTS/spy-detail.png"
cp detail-kelp.png "$SHOTS/spy-detail-$kname.png"
ok "dval's plot opened; screenshots: $SHOTS/spy-main.png $SHOTS/spy-detail.png $SHOTS/spy-detail-$kname.png"
