# kelp's udpm transport and liblcm talk both ways, short and fragmented: liblcm publishes,
# kelp receives; kelp publishes, liblcm receives; kelp apps publish, lcm-logger records and
# kelp-logcheck decodes every event.
. "$(dirname "$0")/lib.sh"
cd $T
command -v lcm-logger >/dev/null || fail "lcm-logger missing (liblcm-bin)"
P=$BIN/kelp-lcmprobe
# run SENDER RECEIVER N SIZE RATE: every message arrives, every checked byte intact
run() {
  $P recv $2 $3 20 > r.out 2>&1 & local rp=$!; PIDS+=($rp)
  wait_for r.out ready 5 || fail "receiver not ready"
  $P send $1 $3 $4 $5 > s.out 2>&1 || { cat s.out; fail "$1 send failed"; }
  wait $rp || { cat s.out r.out; fail "$1 -> $2, $4 B: incomplete"; }
  grep -q "received $3/$3 .*corrupt 0" r.out || { cat r.out; fail "$1 -> $2, $4 B"; }
  ok "$1 -> $2, $3 x $4 B: $(grep -o 'received [0-9/]*' r.out)"
}
run lcm kelp 2000 100 20000
run lcm kelp 40 200000 40      # 4 LC03 fragments each, channel in fragment 0
# (5000/s: liblcm's receiver keeps the kernel's default buffer, some 270 short datagrams; a
# 15 ms stall of its thread on a busy 2-core host lost a quarter of them at 20000/s, once.
# liblcm's rate is not what is tested here; kelp's own receive rate is, above)
run kelp lcm 2000 100 5000
# (20/s: liblcm's receiver, not kelp, lost one 200 KB message at 40/s beside two other tests)
run kelp lcm 40 200000 20
run kelp kelp 40 200000 40
# kelp apps -> lcm-logger -> kelp-logcheck
printf 'Community = interop\n' > m.moos
lcm-logger --lcm-url="$KELP_LCM_URL" -f run.lcmlog > logger.out 2>&1 & LG=$!; PIDS+=($LG)
sleep 0.5
$BIN/kelp-poke m.moos ALPHA=1 BETA=two GAMMA=3.5 > poke.out 2>&1 || { cat poke.out; fail "kelp-poke"; }
sleep 0.3
kill -INT $LG; wait $LG || true
$BIN/kelp-logcheck run.lcmlog > check.out 2>&1 || { cat check.out; fail "log has undecodable events"; }
for v in ALPHA BETA GAMMA; do grep -qE "^  $v +var_t +1 events" check.out || { cat check.out; fail "$v not in the log"; }; done
ok "lcm-logger recorded kelp's writes; kelp-logcheck decoded $(awk '/kelp-logcheck:/{print $2}' check.out) events"
