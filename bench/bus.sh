# make bench: kelp bus vs raw liblcm, same run, same datagrams (104 bytes), two processes,
# inside a private network namespace (loopback multicast, ttl=0).
set -uo pipefail
BIN=${BUILD:-build}/bin
if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ]; then
  export KELP_IN_NETNS=1
  exec unshare -n bash "$0" "$@"
fi
if [ -n "${KELP_IN_NETNS:-}" ]; then
  ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true
fi
export KELP_LCM_URL="udpm://239.255.76.67:7799?ttl=0"
T=$(mktemp -d)
burst() { # $1 = "" or "raw-"
  "$BIN/kelp-busperf" ${1}sub 10000 30 > "$T/sub" 2>&1 & local sp=$!
  for i in $(seq 50); do grep -q ready "$T/sub" && break; sleep 0.1; done
  "$BIN/kelp-busperf" ${1}pub 10000 32 | sed 's/^/  /'
  wait $sp; sed 's/^/  /' "$T/sub"
}
echo "burst of 10,000 messages (publisher -> subscriber, separate processes):"
burst ""
burst "raw-"
echo "round trip (ping -> pong -> ping), 5000 sequential:"
for m in "" "raw-"; do
  "$BIN/kelp-busperf" ${m}pong 60 > /dev/null & pp=$!
  sleep 0.5
  "$BIN/kelp-busperf" ${m}ping 5000 | sed 's/^/  /'
  kill $pp 2>/dev/null; wait $pp 2>/dev/null
done
rm -rf "$T"
