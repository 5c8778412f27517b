# kelp-modemsim with a scripted host: two simulated modems 1500 m apart (1 s of travel) on
# pseudo-terminals, a third on TCP; the host side is this script writing $CC... sentences and
# reading the modem's answers in exactly the forms of shared/data/real_nmea_examples.md.
. "$(dirname "$0")/lib.sh"
cd $T
cat > sim.moos <<'EOF'
Community = simtest
ProcessConfig = msim1
{
  AppTick = 50
  modem_id = 1
  pty_link = ./ttyMM1
  position = x=0,y=0,depth=0
  rev_interval = 0
}
ProcessConfig = msim2
{
  AppTick = 50
  modem_id = 2
  pty_link = ./ttyMM2
  x = 1500
  y = 0
  rev_interval = 0
}
ProcessConfig = msim3
{
  AppTick = 50
  modem_id = 3
  tcp_port = 50123
  position = x=0,y=3000
}
EOF
bg $BIN/kelp-modemsim --alias=msim1 sim.moos > m1.out 2>&1
bg $BIN/kelp-modemsim --alias=msim2 sim.moos > m2.out 2>&1
bg $BIN/kelp-modemsim --alias=msim3 sim.moos > m3.out 2>&1
wait_for m1.out "modem 1 on /dev/pts" 5 || { cat m1.out; fail "modem 1 did not start"; }
wait_for m2.out "modem 2 on /dev/pts" 5 || { cat m2.out; fail "modem 2 did not start"; }
wait_for m3.out "listening on TCP port 50123" 5 || { cat m3.out; fail "modem 3 did not start"; }
[ -L ttyMM1 ] && [ -c "$(readlink -f ttyMM1)" ] || fail "ttyMM1 is not a link to a tty"

# a sentence with its checksum
cs() { local s=$1 x=0 i; for ((i = 1; i < ${#s}; i++)); do x=$((x ^ $(printf '%d' "'${s:i:1}"))); done; printf '%s*%02X' "$s" $x; }
# host writes go through fds 3/4/5; what the modems answer is collected by background readers
# (bash's own read on a tty turns the modem's CR into LF, so it is not used)
exec 3>ttyMM1 4>ttyMM2
bg cat ttyMM1 > h1.raw 2>/dev/null
bg cat ttyMM2 > h2.raw 2>/dev/null
declare -A SEEN=([h1]=0 [h2]=0 [h3]=0)
# expect LOG PATTERN [SECONDS]: the next line of LOG (after the last one matched) matching PATTERN
expect() {
  local log=$1 pat=$2 end=$((SECONDS + ${3:-5})) hit
  while [ $SECONDS -le $end ]; do
    hit=$(tr '\r' '\n' < $log.raw | sed '/^$/d' | tail -n +$((SEEN[$log] + 1)) | grep -nE -m1 "$pat" || true)
    if [ -n "$hit" ]; then
      SEEN[$log]=$((SEEN[$log] + ${hit%%:*}))
      LAST=${hit#*:}
      return 0
    fi
    sleep 0.05
  done
  echo "--- $log:"; tr '\r' '\n' < $log.raw | sed '/^$/d'; return 1
}
send() { printf '%s\r\n' "$2" >&$1; }

# power-on message first
expect h1 '^\$CAREV,[0-9]{6},INIT,0\.93\.0\.52\*[0-9A-F]{2}$' || fail "no \$CAREV,INIT"
# clock, SRC, queries (real example 3: $CACFG,SRC,1*33)
now=$(date -u +%Y,%-m,%-d,%-H,%-M,%-S)
send 3 "$(cs "\$CCCLK,$now")"
expect h1 '^\$CACLK,' || fail "no \$CACLK"
send 3 "$(cs '$CCCFG,SRC,1')"
expect h1 '^\$CACFG,SRC,1\*33$' || fail "no \$CACFG,SRC,1*33"
send 3 '$CCCFQ,SRC'
expect h1 '^\$CACFG,SRC,1\*33$' || fail "no answer to \$CCCFQ,SRC"
send 4 "$(cs '$CCCFG,SRC,2')"
expect h2 '^\$CACFG,SRC,2\*30$' || fail "modem 2: no \$CACFG,SRC,2"
ok "clock and NVRAM"

# two-way ping over 1500 m: $CAMPA,1,2*5D at 2 (real example 6), $CAMPR,2,1,1.0000 at 1
send 3 '$CCMPC,1,2'
expect h1 '^\$CAMPC,1,2\*' || fail "no \$CAMPC echo"
expect h2 '^\$CAMPA,1,2\*5D$' 5 || fail "no \$CAMPA at modem 2"
expect h1 '^\$CAMPR,' 6 || fail "no \$CAMPR at modem 1"
[ "$LAST" = "$(cs '$CAMPR,2,1,1.0000')" ] || fail "ranging reply $LAST, want 1.0000 s one way"
ok "ping: $LAST"

# a rate-0 data cycle with ack: 1 -> 2
send 3 "$(cs '$CCCYC,0,1,2,0,1,1')"
expect h1 '^\$CACYC,0,1,2,0,1,1\*' || fail "no \$CACYC echo"
expect h1 '^\$CADRQ,[0-9]{6},1,2,1,32,1\*' || fail "no \$CADRQ"
send 3 "$(cs '$CCTXD,1,2,1,2000aa30023002c0093cdac2d6cabee8dec2e6e8e7')"
expect h1 '^\$CATXD,1,2,1,21\*' || fail "no \$CATXD"
expect h2 '^\$CACYC,0,1,2,0,1,1\*' 5 || fail "modem 2 did not hear the cycle init"
expect h2 '^\$CARXD,1,2,1,1,2000aa30023002c0093cdac2d6cabee8dec2e6e8e7\*' 8 || fail "modem 2 did not receive the frame"
expect h1 '^\$CAACK,2,1,1,1\*' 5 || fail "no \$CAACK at modem 1"
tr '\r' '\n' < h1.raw | grep -qE '^\$CATXF,21\*67$' || fail "no \$CATXF,21 for the data"
ok "data cycle with ack"

# garbage and a bad checksum are answered with $CAERR, and the modem keeps working
send 3 'hello modem'
expect h1 '^\$CAERR,[0-9]{6},NMEA,1,' || fail "no \$CAERR for garbage"
send 3 '$CCCFQ,SRC*00'
expect h1 '^\$CAERR,[0-9]{6},NMEA,2,BAD_CHECKSUM\*' || fail "no \$CAERR for a bad checksum"
send 3 '$CCCFQ,SRC'
expect h1 '^\$CACFG,SRC,1\*33$' || fail "modem stopped answering after bad input"
ok "bad input"

# the TCP modem (3000 m from modem 1) hears modem 1's ping and answers its own host over TCP
exec 5<>/dev/tcp/127.0.0.1/50123
bg sh -c 'exec cat <&5' > h3.raw
send 5 "$(cs '$CCCFG,SRC,3')"
expect h3 '^\$CACFG,SRC,3\*' || fail "TCP modem did not answer"
send 3 '$CCMPC,1,3'
expect h3 '^\$CAMPA,1,3\*' 6 || fail "TCP modem did not hear the ping"
expect h1 '^\$CAMPR,3,1,2\.0000\*' 8 || fail "no 2.0000 s range to the TCP modem"
ok "TCP modem: $LAST"

exec 3>&- 4>&- 5>&-
# the status var and report
kill ${PIDS[0]} ${PIDS[1]}
sleep 0.5
grep -q "lost: random 0 collision 0" m2.out || { cat m2.out; fail "unexpected losses at modem 2"; }
grep -q "heard: cycle_init 1 data 1 (1 frames)" m2.out || { cat m2.out; fail "modem 2 report"; }
[ ! -e ttyMM1 ] || fail "pty link not removed at exit"
ok "kelp-modemsim on ptys and TCP"
