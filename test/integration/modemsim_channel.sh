# Two kelp-modemsims in two communities (two LCM URLs) share one acoustic channel on a third URL
# (channel_url); modem 2 follows its vehicle's NODE_REPORT_LOCAL.  A scripted host pings from
# modem 1: the range follows the reported position (3000 m -> 2.0000 s, then 4500 m -> 3.0000 s),
# and a modem on the same URL but without channel_url hears nothing.
. "$(dirname "$0")/lib.sh"
cd $T
base=${KELP_LCM_URL%%\?*}; base=${base%:*}
URL1="$base:$((TEST_PORT + 1))?ttl=0"; URL2="$base:$((TEST_PORT + 2))?ttl=0"; CHAN="$base:$((TEST_PORT + 3))?ttl=0"
unset KELP_LCM_URL
cat > a.moos <<EOF
LCM_URL = $URL1
Community = alpha
ProcessConfig = iModemSim
{
  AppTick = 50
  modem_id = 1
  pty_link = $T/ttyA
  position = x=0,y=0
  channel_url = $CHAN
  rev_interval = 0
}
EOF
cat > b.moos <<EOF
LCM_URL = $URL2
Community = bravo
ProcessConfig = iModemSim
{
  AppTick = 50
  modem_id = 2
  pty_link = $T/ttyB
  x = 0
  y = 3000
  node_report_var = NODE_REPORT_LOCAL
  channel_url = $CHAN
}
ProcessConfig = deaf
{
  AppTick = 50
  modem_id = 3
  pty_link = $T/ttyC
  position = x=0,y=10
}
EOF
bg $BIN/kelp-modemsim --alias=iModemSim a.moos > a.out 2>&1
bg $BIN/kelp-modemsim --alias=iModemSim b.moos > b.out 2>&1
bg $BIN/kelp-modemsim --alias=deaf b.moos > c.out 2>&1
for f in a b c; do wait_for $f.out "on /dev/pts" 5 || { cat $f.out; fail "modem $f did not start"; }; done
exec 3>ttyA
bg cat ttyA > a.raw 2>/dev/null
bg cat ttyB > b.raw 2>/dev/null
bg cat ttyC > c.raw 2>/dev/null
lines() { tr '\r' '\n' < $1 | sed '/^$/d'; }
ping_range() { # expected one-way time
  printf '$CCMPC,1,2\r\n' >&3
  for i in $(seq 1 120); do
    n=$(lines a.raw | grep -c '^\$CAMPR,' || true)
    [ "$n" -ge "$1" ] && break
    sleep 0.1
  done
  lines a.raw | grep '^\$CAMPR,' | sed -n "${1}p"
}
r=$(ping_range 1)
[[ $r == '$CAMPR,2,1,2.0000*'* ]] || { lines a.raw; cat b.out; fail "first range '$r', want 2.0000 s (3000 m)"; }
ok "across communities: $r"
$BIN/kelp-poke b.moos 'NODE_REPORT_LOCAL:=NAME=bravo,TYPE=auv,X=0,Y=4500,SPD=1,HDG=0,DEP=0' > /dev/null
sleep 0.5
r=$(ping_range 2)
[[ $r == '$CAMPR,2,1,3.0000*'* ]] || { lines a.raw; fail "range after NODE_REPORT '$r', want 3.0000 s (4500 m)"; }
ok "after NODE_REPORT_LOCAL: $r"
lines b.raw | grep -q '^\$CAMPA,1,2\*5D$' || fail "modem 2 did not report the pings"
[ -z "$(lines c.raw | grep -v '^\$CAREV')" ] || { lines c.raw; fail "the modem off the channel heard something"; }
grep -q "position x=0.0 y=4500.0" b.out || sleep 2.5
grep -q "position x=0.0 y=4500.0" b.out || { tail -20 b.out; fail "report does not show the new position"; }
ok "shared channel over channel_url"
