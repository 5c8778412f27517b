# kelp: the pieces every multi-community mission script shares (sourced by
# scripts/demo-fleet.sh and scripts/encounter.sh). A shoreside community and vehicle
# communities on one host, each on its own LCM URL, joined by kelp-bridge through the uField
# brokers. The caller sets B (build dir) and W (work dir) and cds into W.

# re-run the calling script in a private network namespace when root (nothing leaves the
# machine): fleet_private_netns "$0" "$@"
fleet_private_netns() {
  if [ -z "${KELP_IN_NETNS:-}" ] && [ "$(id -u)" -eq 0 ] && command -v unshare >/dev/null; then
    export KELP_IN_NETNS=1
    exec unshare -n "$@"
  fi
  if [ -n "${KELP_IN_NETNS:-}" ]; then
    ip link set lo up; ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true
  fi
}

# the same, with the demo's web page on this host: the script runs in a private network namespace
# (root only; otherwise on the host, where the page already is) and this host's 127.0.0.1:PORT
# (the next free port after it when taken) is forwarded into the namespace's 127.0.0.1:PORT:
# socat listens here and, per connection, starts a socat inside the namespace (nsenter into
# the namespace of the script's process) connected to the page. The fleet stays in its
# namespace; only that one TCP port is reachable, and only from this host. The host side
# exports KELP_DEMO_PAGE_PORT (the port to print), waits for the script, stops the forwarder
# and exits with the script's status; a Ctrl-C reaches the script (same process group), a
# TERM sent to the host side alone is passed on to it.
# usage: fleet_private_netns_forward PORT "$0" "$@"
fleet_private_netns_forward() {
  local port=$1; shift
  if [ -n "${KELP_IN_NETNS:-}" ] || [ "$(id -u)" -ne 0 ] || ! command -v unshare >/dev/null; then
    fleet_private_netns "$@"
    return
  fi
  local p tool
  for tool in socat nsenter ss; do
    command -v $tool >/dev/null || { echo "demo: $tool missing (scripts/deps.sh build installs it)"; exit 1; }
  done
  for p in $(seq "$port" $((port + 20))) ""; do
    [ -n "$p" ] && [ -z "$(ss -Hltn "sport = :$p" 2>/dev/null)" ] && break
  done
  [ -n "$p" ] || { echo "demo: 127.0.0.1:$port..$((port + 20)) all taken on this host (DEMO_VIEWER_PORT=N)"; exit 1; }
  export KELP_IN_NETNS=1 KELP_DEMO_PAGE_PORT=$p
  # (a shell starts a background command with SIGINT ignored: the script gets it back, so a
  # Ctrl-C, which the terminal sends to the whole process group, reaches it)
  env --default-signal=INT unshare -n "$@" &
  local inner=$! rc=0
  socat -lpfleet-forward "TCP-LISTEN:$p,bind=127.0.0.1,reuseaddr,fork" \
        "EXEC:nsenter --net=/proc/$inner/ns/net socat STDIO TCP\:127.0.0.1\:$port" 2>/dev/null &
  local fwd=$!
  trap 'kill -TERM $inner 2>/dev/null || true' TERM
  trap : INT
  wait $inner || rc=$?
  while kill -0 $inner 2>/dev/null; do rc=0; wait $inner || rc=$?; done
  kill $fwd 2>/dev/null || true
  wait $fwd 2>/dev/null || true
  exit $rc
}

trim() { local s=$1; s=${s#"${s%%[![:space:]]*}"}; s=${s%"${s##*[![:space:]]}"}; printf '%s' "$s"; }

# fill $(NAME) macros of a template from the NAME=value arguments that follow it
fill() {
  local text; text=$(<"$1"); shift
  for kv in "$@"; do text=${text//"\$(${kv%%=*})"/${kv#*=}}; done
  printf '%s\n' "$text"
}

# the LCM port of a generated community file
fleet_lcm_port() { sed -n 's/^LCM_URL *= *udpm:\/\/239.255.76.67:\([0-9]*\).*/\1/p' "$1"; }

# start a kelp-record per community (shoreside.moos and NAME.moos for each name given) and a
# kelp-launch per community running for RUN_SECONDS; fills PIDS, LOGGERS and LAUNCH
# usage: fleet_start RUN_SECONDS NAME...
fleet_start() {
  local run=$1; shift
  local c port
  PIDS=(); LOGGERS=(); LAUNCH=()
  for c in shoreside "$@"; do
    port=$(fleet_lcm_port "$c.moos")
    "$B/bin/kelp-record" --lcm-url="udpm://239.255.76.67:$port?ttl=0" -f -q "$c.lcm" > "logger_$c.out" 2>&1 &
    LOGGERS+=($!); PIDS+=($!)
  done
  sleep 0.3
  for c in shoreside "$@"; do
    "$B/bin/kelp-launch" --run-seconds "$run" --log-dir "logs_$c" "$c.moos" > "launch_$c.out" 2>&1 &
    LAUNCH+=($!); PIDS+=($!)
  done
}

# wait until every kelp-bridge listens (a bridge subscribes before it binds), then until the
# shoreside's uFldShoreBroker lists every vehicle as acknowledged. Prints one line; 1 on timeout.
# usage: fleet_wait_handshake SHORE_BRIDGE_PORT NAME...
fleet_wait_handshake() {
  local shore=$1; shift
  local ports i n v t_hs
  ports=$(printf '%s|' "$shore" $(for v in "$@"; do sed -n 's/^ *UDPListen *= *//p' "$v.moos"; done)); ports=${ports%|}
  if command -v ss >/dev/null; then
    for i in $(seq 100); do
      n=$(ss -Huln 2>/dev/null | grep -cE ":($ports) " || true)
      [ "$n" -ge $(( $# + 1 )) ] && break; sleep 0.1
    done
  fi
  t_hs=$(date +%s.%N)
  for i in $(seq 300); do
    n=0
    for v in "$@"; do grep -qE "^$v +127\.0\.0\.1 +ok " logs_shoreside/uFldShoreBroker.log 2>/dev/null && n=$((n + 1)); done
    [ $n -ge $# ] && break; sleep 0.1
  done
  echo "== uField handshake: $n of $# vehicles found the shoreside in $(awk -v a="$t_hs" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b - a}') s (wall); bridges registered by the brokers"
  if [ $n -lt $# ]; then
    tail -30 logs_shoreside/uFldShoreBroker.log
    return 1
  fi
}

# stop the launchers (TERM) and then the loggers; rc_launch=1 when a launcher did not end cleanly
fleet_stop() {
  local p
  for p in "${LAUNCH[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  rc_launch=0
  for p in "${LAUNCH[@]}"; do wait "$p" || rc_launch=1; done
  for p in "${LOGGERS[@]}"; do kill -INT "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  PIDS=()
}

fleet_cleanup() {
  local p
  trap '' INT TERM   # a second Ctrl-C must not cut the cleanup short
  for p in "${PIDS[@]:-}"; do [ -n "$p" ] && kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
