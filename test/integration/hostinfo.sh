#!/usr/bin/env bash
# pHostInfo in a network namespace with two interfaces of its own (a wireless-named one first,
# an ethernet-named one second): PHI_HOST_IP is the ethernet address, the other is listed too,
# the loopback is not; PHI_HOST_INFO is MOOS-IvP 24.8's record (hostip_alts: the other
# addresses); the seed's PMB_UDP_LISTEN adds port_udp to it; an address added later appears
# after HOST_INFO_REQUEST.
. "$(dirname "$0")/lib.sh"
cd "$T"
# veth pairs (the dummy driver may be missing); the peers carry no address
iface() { ip link add "$1" type veth peer name "x$1"; ip addr add "$2" dev "$1"; ip link set "$1" up; ip link set "x$1" up; }
iface wlan5 10.77.0.5/24
iface eth7 10.88.0.7/24
# the bus stays on the loopback with a loopback source (else the reverse-path filter drops it)
ip route replace 224.0.0.0/4 dev lo src 127.0.0.1
cat > h.moos <<'M'
ServerPort = 9123
Community = alpha
MOOSTimeWarp = 4
ProcessConfig = pHostInfo
{
  AppTick = 4
  temp_file_dir = ./
}
M
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f h.lcmlog
sleep 0.5
bg "$BIN/pHostInfo" h.moos
sleep 1
"$BIN/kelp-poke" h.moos PMB_UDP_LISTEN=9200 > poke1.out 2>&1 || fail "poke: $(cat poke1.out)"
sleep 0.5
iface eth8 10.99.0.8/24
"$BIN/kelp-poke" h.moos HOST_INFO_REQUEST:=true > /dev/null
sleep 1
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print h.lcmlog > h.txt || fail "log undecodable"
first() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); print; exit}' h.txt; }
last() { awk -v v="$1" '$3==v {sub(/^[^ ]+ [^ ]+ [^ ]+ /, ""); x=$0} END{print x}' h.txt; }
[ "$(first PHI_HOST_IP)" = 10.88.0.7 ] || fail "PHI_HOST_IP $(first PHI_HOST_IP), expected the ethernet 10.88.0.7"
[ "$(first PHI_HOST_IP_ALL)" = "10.88.0.7,10.77.0.5" ] || fail "PHI_HOST_IP_ALL $(first PHI_HOST_IP_ALL)"
[ "$(first PHI_HOST_IP_VERBOSE)" = "LINUX_ETHERNET=10.88.0.7,LINUX_WIFI=10.77.0.5" ] || fail "verbose $(first PHI_HOST_IP_VERBOSE)"
[ "$(first PHI_HOST_PORT_DB)" = 9123 ] || fail "PHI_HOST_PORT_DB $(first PHI_HOST_PORT_DB)"
[ "$(first PHI_HOST_INFO)" = "community=alpha,hostip=10.88.0.7,port_db=9123,hostip_alts=10.77.0.5,timewarp=4" ] || fail "info $(first PHI_HOST_INFO)"
last PHI_HOST_INFO | grep -q "port_udp=9200" || fail "port_udp missing: $(last PHI_HOST_INFO)"
[ "$(last PHI_HOST_IP_ALL)" = "10.88.0.7,10.99.0.8,10.77.0.5" ] || fail "after HOST_INFO_REQUEST: $(last PHI_HOST_IP_ALL)"
ok "PHI_HOST_IP $(first PHI_HOST_IP); after the request $(last PHI_HOST_IP_ALL); $(last PHI_HOST_INFO)"

# MOOS-IvP 24.8 spells the defaults default_host_ip / default_host_ip_force too
cat > f.moos <<'M'
ServerPort = 9124
Community = bravo
ProcessConfig = pHostInfo
{
  AppTick = 4
  default_host_ip_force = 10.1.2.3
}
M
bg "$BIN/kelp-record" --lcm-url="$KELP_LCM_URL" -f f.lcmlog
sleep 0.5
rc=0
timeout -s INT 2 "$BIN/pHostInfo" f.moos > f.out 2>&1 || rc=$?
[ $rc -eq 0 ] || [ $rc -eq 124 ] || { cat f.out; fail "pHostInfo exited $rc"; }
grep -q "Configuration warnings: 0" f.out || { cat f.out; fail "default_host_ip_force not accepted"; }
for p in "${PIDS[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait 2>/dev/null || true
PIDS=()
"$BIN/kelp-logcheck" --print f.lcmlog > f.txt || fail "log f undecodable"
[ "$(awk '$3=="PHI_HOST_IP" {print $4; exit}' f.txt)" = 10.1.2.3 ] || fail "default_host_ip_force: $(grep PHI_HOST_IP f.txt)"
ok "default_host_ip_force = 10.1.2.3 gives PHI_HOST_IP 10.1.2.3"
