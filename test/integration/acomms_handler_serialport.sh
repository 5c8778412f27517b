#!/usr/bin/env bash
# pAcommsHandler through libserialport itself (not the termios fallback) on a socat pty, with the
# platform notes' test shim (test/shim/pty_shim.c, LD_PRELOAD, this test only): the link reports
# the libserialport back end, the start-up sequence runs and a queued CCL message goes out as
# $CCTXD (seed example 1's bytes 02 02 03 04, here to modem 2 with an ack) and is acknowledged.
. "$(dirname "$0")/lib.sh"
# stdbuf (and the pty shim) are LD_PRELOADs: let an ASan build (make asan) accept them
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
cd "$T"
command -v socat >/dev/null || fail "socat not installed"
cc -shared -fPIC -o pty_shim.so "$KELP_ROOT/test/shim/pty_shim.c" -ldl || fail "cannot build the shim"
cp "$KELP_ROOT/test/shim/fake_modem.sh" .
echo normal > mode
socat pty,raw,echo=0,link="$T/ttyA" EXEC:"bash $T/fake_modem.sh $T" 2>socat.err & PIDS+=($!)
for _ in $(seq 50); do [ -e ttyA ] && break; sleep 0.1; done
cat > mm.moos <<X
Community = mm1
ProcessConfig = pAcommsHandler
{
  modem_id: 1
  driver_type: DRIVER_WHOI_MICROMODEM
  driver_cfg { serial_port: "$T/ttyA" serial_baud: 19200 [MicroModemConfig.reset_nvram]: true }
  mac_cfg { type: MAC_FIXED_DECENTRALIZED slot { src: 1 dest: 2 rate: 0 type: SLOT_DATA slot_seconds: 2 } }
  queue_cfg { queue { key { type: QUEUE_CCL id: 2 } in_pubsub_var: "IN_TEST_32B" out_pubsub_var: "OUT_TEST_32B" name: "TEST" } }
}
X
LD_PRELOAD="$T/pty_shim.so" stdbuf -oL "$BIN/pAcommsHandler" --verbose mm.moos > h.out 2>&1 & H=$!; PIDS+=($H)
wait_for h.out 'modem link up: serial .* 19200 8N1 \(libserialport\)' 10 || { cat h.out; fail "libserialport did not open the pty"; }
wait_for modem.log '^> \$CCCFQ,ALL' 10 || { cat modem.log; fail "no start-up"; }
grep -q '^> \$CCCFG,ALL,0\*' modem.log || fail "reset_nvram true but no \$CCCFG,ALL,0"
# ALL,0 comes before SRC (acomms.md 9.12)
[ "$(grep -n 'CCCFG,ALL,0' modem.log | cut -d: -f1)" -lt "$(grep -n 'CCCFG,SRC,1' modem.log | cut -d: -f1)" ] || fail "order"
# the seed's value has no base.dest (broadcast: Goby 1.1 then never asks for an ack); address it
"$BIN/kelp-poke" mm.moos 'OUT_TEST_32B:=base { dest: 2 } data: "\002\002\003\004"' > /dev/null
wait_for modem.log '^> \$CCTXD,1,2,1,02020304\*' 10 || { tail modem.log; tail -20 h.out; fail "no \$CCTXD,1,2,1,02020304"; }
wait_for h.out 'ack from 2 for TEST' 5 || { tail -20 h.out; fail "no ack"; }
ok "libserialport (shim) opened the pty; CFG ALL,0 before SRC; \$CCTXD,1,2,1,02020304 acked"
