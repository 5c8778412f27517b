#!/usr/bin/env bash
# A scripted WHOI Micro-Modem for integration tests: socat runs it on the far side of a pty
#   socat pty,raw,echo=0,link=$T/ttyA EXEC:"bash fake_modem.sh $T"
# It reads $CC... lines (delimited by \r) on stdin and answers on stdout as a modem does:
#   $CCCLK -> $CACLK (same fields), $CCCFG,X -> $CACFG,X, $CCCFQ -> $CACFG,SRC,1 + $CACFG,DTO,2,
#   $CCCYC -> $CACYC + $CADRQ (frame 1), $CCTXD -> $CATXD (+ $CAACK when ACK=1 and data).
# Everything is logged to $T/modem.log ("> " in, "< " out); the hex of every $CCTXD to
# $T/txd.log.  "silent" in $T/mode: read but never answer.  Lines appended to $T/inject are
# sent verbatim (garbage, $CARXD ...).  Sentences from shared/data/real_nmea_examples.md.
T=$1
cks() { local s=$1 c=0 i o; for ((i = 0; i < ${#s}; i++)); do printf -v o '%d' "'${s:i:1}"; c=$((c ^ o)); done; printf '%02X' $c; }
say() { printf '$%s*%s\r\n' "$1" "$(cks "$1")"; echo "< \$$1" >> "$T/modem.log"; }
handle() {
  local line=${1#$'\n'} body
  [ -n "$line" ] || return 0
  echo "> $line" >> "$T/modem.log"
  [ "$(cat "$T/mode" 2>/dev/null)" = silent ] && return 0
  body=${line#\$}; body=${body%%\**}
  case $body in
    CCCLK,*) say "CACLK,${body#CCCLK,}" ;;
    CCCFG,*) say "CACFG,${body#CCCFG,}" ;;
    CCCFQ,*) say "CACFG,SRC,1"; say "CACFG,DTO,2" ;;
    CCCYC,*) IFS=, read -r _ cmd a1 a2 rate ack nf <<< "$body"
             say "CACYC,$cmd,$a1,$a2,$rate,$ack,$nf"
             say "CADRQ,$(date -u +%H%M%S),$a1,$a2,$ack,32,1" ;;
    CCTXD,*) IFS=, read -r _ s d ack hex <<< "$body"
             echo "$hex" >> "$T/txd.log"
             say "CATXD,$s,$d,$ack,$(( ${#hex} / 2 ))"
             [ "$ack" = 1 ] && [ -n "$hex" ] && say "CAACK,$d,$s,1,1" ;;
  esac
}
echo "modem up" >> "$T/modem.log"
buf=""; sent=0
while :; do
  if IFS= read -r -t 0.1 -d $'\r' part; then
    handle "$buf$part"; buf=""
  else
    rc=$?; buf+=$part
    [ $rc -gt 128 ] || break   # EOF: the pty went away
  fi
  if [ -f "$T/inject" ]; then
    n=$(wc -l < "$T/inject")
    while [ $sent -lt $n ]; do sent=$((sent + 1)); l=$(sed -n "${sent}p" "$T/inject"); printf '%s\r\n' "$l"; echo "< $l" >> "$T/modem.log"; done
  fi
done
echo "modem gone" >> "$T/modem.log"
