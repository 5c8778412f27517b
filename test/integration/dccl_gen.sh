#!/usr/bin/env bash
# kelp-dccl-gen: generated const tables encode exactly like the XML-loaded
# definitions and like `kelp-dccl encode`; kelp-dccl CLI round trips and errors.
set -euo pipefail
BUILD=${BUILD:-$(pwd)/build}
KELP_ROOT=${KELP_ROOT:-$(pwd)}
K=$BUILD/bin/kelp-dccl
G=$BUILD/bin/kelp-dccl-gen
T=$(mktemp -d /tmp/kelp-dccl-gen.XXXXXX)
trap 'rm -rf "$T"' EXIT
NOW=1699963200   # 2023-11-14 12:00:00 UTC
fail() { echo "FAIL: $*"; exit 1; }

cat > "$T/example1.xml" <<'EOF'
<?xml version="1.0" encoding="ASCII" standalone="yes"?>
<message_set>
  <message>
    <name>GoToCommand</name><id>1</id><trigger>publish</trigger>
    <trigger_var mandatory_content="CommandType=GoTo">OUTGOING_COMMAND</trigger_var>
    <size>32</size>
    <header><dest_id><name>Destination</name></dest_id></header>
    <layout>
      <static><name>type</name><value>goto</value></static>
      <int><name>goto_x</name><max>10000</max><min>0</min></int>
      <int><name>goto_y</name><max>10000</max><min>0</min></int>
      <bool><name>lights_on</name></bool>
      <string><moos_var>SPECIAL_INSTRUCTIONS</moos_var><name>new_instructions</name><max_length>10</max_length></string>
      <float><name>goto_speed</name><max>3</max><min>0</min><precision>2</precision></float>
    </layout>
    <on_receipt>
      <publish><publish_var>INCOMING_COMMAND</publish_var><all /></publish>
      <publish><publish_var>SPECIAL_INSTRUCTIONS</publish_var>
        <format>special_instructions=%1%,lights_on=%2%</format>
        <message_var>new_instructions</message_var><message_var>lights_on</message_var></publish>
    </on_receipt>
  </message>
</message_set>
EOF

cat > "$T/alltypes.xml" <<'EOF'
<?xml version="1.0" encoding="UTF-8"?>
<message_set>
  <message>
    <name>ALL_TYPES</name><size>28</size>
    <header><id>30</id><time><name>when</name></time><dest_id><name>to</name></dest_id></header>
    <layout>
      <static><name>kind</name><value>all</value></static>
      <int><name>count</name><max>1000</max><min>0</min></int>
      <float algorithm="angle_0_360"><name>heading</name><max>360</max><min>0</min><precision>2</precision></float>
      <bool><name>ok</name></bool>
      <string><name>note</name><max_length>10</max_length></string>
      <enum><name>mode</name><value>idle</value><value>survey</value><value>home</value></enum>
      <hex><name>raw</name><num_bytes>4</num_bytes></hex>
      <float><name>depth</name><max>6400</max><min>0</min><precision>1</precision><array_length>2</array_length><max_delta>100</max_delta></float>
    </layout>
    <on_receipt><publish><publish_var>ALL_IN</publish_var><all/></publish></on_receipt>
    <queuing><ack>false</ack><ttl>120</ttl><value_base>2</value_base></queuing>
  </message>
</message_set>
EOF

cat > "$T/gen_enc.c" <<'EOF'
#include <stdio.h>
#include <string.h>
#include <kelp/edge/dccl.h>
#include GEN_HEADER
static int enc(const kelp_dccl_msgdef *d, kelp_dccl_codec *cx, int argc, char **argv, double now, char *hex)
{
    kelp_dccl_val v[256];
    unsigned cnt[64] = {0};
    uint8_t out[KELP_DCCL_MAX_SIZE];
    size_t n, i;
    int k;
    for (i = 0; i < d->n_slots; i++) kelp_dccl_val_clear(&v[i]);
    for (k = 0; k < argc; k++) {
        char name[64];
        const char *eq = strchr(argv[k], '=');
        int fi;
        snprintf(name, sizeof name, "%.*s", (int)(eq - argv[k]), argv[k]);
        fi = kelp_dccl_field_find(d, name);
        if (fi < 0) return 1;
        if (cnt[fi] < d->fields[fi].array_length) kelp_dccl_val_set_str(&v[d->fields[fi].slot + cnt[fi]], eq + 1);
        cnt[fi]++;
    }
    if (kelp_dccl_encode(cx, d, v, d->n_slots, now, out, sizeof out, &n)) return 1;
    for (i = 0; i < n; i++) sprintf(hex + 2 * i, "%02x", out[i]);
    hex[2 * n] = 0;
    return 0;
}
int main(int argc, char **argv)
{
    kelp_dccl_loaded ld;
    kelp_dccl_mbedtls mb;
    kelp_dccl_codec cx;
    kelp_dccl_alg_entry st[40];
    kelp_dccl_modem_entry me[4];
    kelp_dccl_algs algs;
    kelp_dccl_builtin bi;
    char h1[2 * KELP_DCCL_MAX_SIZE + 1], h2[2 * KELP_DCCL_MAX_SIZE + 1];
    kelp_diag err = {0};
    const kelp_dccl_msgdef *g, *l;
    if (argc < 4) return 2;
    kelp_dccl_algs_init(&algs, st, 40);
    kelp_dccl_builtin_init(&bi, me, 4);
    if (kelp_dccl_algs_add_builtin(&algs, &bi)) return 2;
    kelp_dccl_loaded_init(&ld);
    if (kelp_dccl_load_file(&ld, argv[1], &algs, &err)) { fprintf(stderr, "%s\n", kelp_diag_text(&err)); return 2; }
    g = kelp_dccl_set_find_name(&GEN_SET, argv[2]);
    l = kelp_dccl_set_find_name(&ld.set, argv[2]);
    if (!g || !l) return 3;
    if (g->hash != l->hash || g->n_slots != l->n_slots || g->body_bits != l->body_bits) { fprintf(stderr, "hash/shape differ\n"); return 4; }
    if (kelp_dccl_mbedtls_init(&mb, NULL)) return 2;
    kelp_dccl_codec_init(&cx, 1, &mb.ops, &algs);
    if (enc(g, &cx, argc - 4, argv + 4, atof(argv[3]), h1) || enc(l, &cx, argc - 4, argv + 4, atof(argv[3]), h2)) return 5;
    if (strcmp(h1, h2) != 0) { fprintf(stderr, "generated %s != loaded %s\n", h1, h2); return 6; }
    printf("%s\n", h1);
    kelp_dccl_mbedtls_free(&mb);
    kelp_dccl_loaded_free(&ld);
    return 0;
}
EOF
sed -i 's/#include <string.h>/#include <stdlib.h>\n#include <string.h>/' "$T/gen_enc.c"

# a sanitizer build (make asan) needs the same flags to link
SAN=""
if nm "$BUILD/libkelp_core.a" 2>/dev/null | grep -c __asan_init >/dev/null; then SAN="-fsanitize=address,undefined"; fi

check_gen() { # xml prefix msg fields...
  local xml=$1 prefix=$2 msg=$3; shift 3
  "$G" "$T/$xml" -o "$T" >/dev/null || fail "kelp-dccl-gen $xml"
  grep -q "GENERATED by kelp-dccl-gen" "$T/$prefix.c" || fail "banner"
  gcc -std=c11 $SAN -Wall -Wextra -Werror -I"$KELP_ROOT/include" -I"$T" -DGEN_HEADER="\"$prefix.h\"" -DGEN_SET="${prefix}_set" \
      -o "$T/gen_enc_$prefix" "$T/gen_enc.c" "$T/$prefix.c" "$BUILD/libkelp.a" "$BUILD/libkelp_core.a" \
      -lexpat -lmbedtls -lmbedx509 -lmbedcrypto -lm || fail "compile generated $prefix.c"
  local a b
  a=$("$T/gen_enc_$prefix" "$T/$xml" "$msg" $NOW "$@") || fail "generated/loaded mismatch for $msg"
  b=$("$K" encode --xml "$T/$xml" --msg "$msg" --modem-id 1 --now $NOW "$@") || fail "kelp-dccl encode $msg"
  [ "$a" = "$b" ] || fail "generated $a != kelp-dccl $b"
  echo "ok $msg $a"
}

check_gen example1.xml example1_dccl GoToCommand Destination=3 goto_x=351 goto_y=294 lights_on=true new_instructions=make_toast goto_speed=2.3
check_gen alltypes.xml alltypes_dccl ALL_TYPES to=4 count=999 heading=-90.5 ok=false note=hello mode=home raw=deadBEEF depth=100.5 depth=120.2
check_gen alltypes.xml alltypes_dccl ALL_TYPES raw=00000000 depth=50
# integer bounds in the billions (32- to 64-bit fields) and a <repeat/> message, as tables too
cp "$KELP_ROOT/test/data/dccl/wide.xml" "$T/"
WIDE=(to=4 u32=4000000000 s34=-5000000000 q32=2147483646 stamp=999999999999999 s64=-9200000000000000000
      pos=-123456789.125 ok=true note=hello_kelp mode=survey raw=deadbeef track=-3999999999 track=-999999999 track=1)
check_gen wide.xml wide_dccl WIDE_ALL "${WIDE[@]}"
check_gen wide.xml wide_dccl WIDE_REP big=-5000000000 big=4000000000 big=7 ok=true ok=false
h=$("$K" encode --xml "$T/wide.xml" --msg WIDE_ALL --modem-id 1 --now $NOW "${WIDE[@]}")
"$K" publish --xml "$T/wide.xml" --now $NOW "$h" > "$T/pub.txt" || fail "publish WIDE_ALL"
grep -q '^WIDE_IN=.*,s34=-5000000000,.*,s64=-9200000000000000000,pos=-123456789.125,.*track={-3999999999,-999999999,}$' \
  "$T/pub.txt" || fail "publish WIDE_ALL: $(cat "$T/pub.txt")"
# <repeat/> without <format>: one placeholder per field, one publication per index (5 x 3)
h=$("$K" encode --xml "$T/wide.xml" --msg WIDE_REP --modem-id 2 --now $NOW big=-5000000000 big=4000000000 ok=true)
"$K" publish --xml "$T/wide.xml" --now $NOW "$h" > "$T/pub.txt" || fail "publish WIDE_REP: $(cat "$T/pub.txt")"
[ "$(grep -c '^REP_' "$T/pub.txt")" = 15 ] && grep -qx 'REP_PAIR=big=4000000000,ok=' "$T/pub.txt" &&
  grep -qx 'REP_FMT=-5000000000 from 2' "$T/pub.txt" || fail "publish WIDE_REP: $(cat "$T/pub.txt")"
# 8 * 250 bits / 2 bits a copy = 1000 publications of one message
h=$("$K" encode --xml "$T/wide.xml" --msg WIDE_MANY --now $NOW bit=true bit=false)
"$K" publish --xml "$T/wide.xml" --now $NOW "$h" > "$T/pub.txt" || fail "publish WIDE_MANY: $(tail -3 "$T/pub.txt")"
[ "$(grep -c '^MANY=' "$T/pub.txt")" = 1000 ] && [ "$(sed -n 2p "$T/pub.txt")" = MANY=false ] || fail "publish WIDE_MANY"

# the encrypted vector of the seed's GoToCommand (key SHA-256(""), verified with openssl)
h=$("$K" encode --xml "$T/example1.xml" --msg GoToCommand --modem-id 1 --now $NOW Destination=3 goto_x=351 goto_y=294 lights_on=true new_instructions=make_toast goto_speed=2.3)
[ "$h" = 2000aa3002301900cf87ea6b7ee47f21b7777603c7 ] || fail "encrypted vector $h"
"$K" decode --xml "$T/example1.xml" --now $((NOW + 60)) "$h" > "$T/dec.txt"
grep -qx 'message GoToCommand' "$T/dec.txt" && grep -qx 'goto_speed=2.29' "$T/dec.txt" && grep -qx 'Destination=3' "$T/dec.txt" || fail "decode: $(cat "$T/dec.txt")"
[ "$(sed -n 2p "$T/dec.txt")" = "_ccl_id=32" ] || fail "decode order"
"$K" publish --xml "$T/example1.xml" --now $((NOW + 60)) "$h" > "$T/pub.txt"
grep -qx 'SPECIAL_INSTRUCTIONS=special_instructions=make_toast,lights_on=true' "$T/pub.txt" || fail "publish: $(cat "$T/pub.txt")"
# --repeat gives the same single line
[ "$("$K" encode --repeat 50 --xml "$T/example1.xml" --msg GoToCommand --modem-id 1 --now $NOW Destination=3 goto_x=351 goto_y=294 lights_on=true new_instructions=make_toast goto_speed=2.3)" = "$h" ] || fail "--repeat"
[ "$("$K" decode --repeat 50 --xml "$T/example1.xml" --now $((NOW + 60)) "$h" | wc -l)" = 15 ] || fail "decode --repeat"
# FIELD#=NUMBER is a double; plain layout
[ "$("$K" encode --plain --xml "$T/example1.xml" --msg GoToCommand --modem-id 1 --now $NOW 'goto_speed#=2.3')" = 2000aa3002000000000000000000000000000000e6 ] || fail "double input"
# info
"$K" info --xml "$T/alltypes.xml" | grep -q '^message ALL_TYPES id 30 size 28' || fail info
# errors: non-zero exit with a message
! "$K" encode --xml "$T/example1.xml" --msg Nope x=1 2>"$T/e" && grep -q 'unknown message' "$T/e" || fail "unknown message"
! "$K" encode --xml "$T/example1.xml" --msg GoToCommand bogus=1 2>"$T/e" && grep -q 'no field "bogus"' "$T/e" || fail "unknown field"
! "$K" decode --xml "$T/example1.xml" 2000a 2>"$T/e" && grep -q 'wrong hex length' "$T/e" || fail "hex length"
! "$K" decode --xml "$T/example1.xml" 2002aa300230 2>"$T/e" && grep -q 'no message with id 5' "$T/e" || fail "unknown id"
printf '<message_set><message>\n<name>X</name>\n<size>4</size><layout><bool><name>b</name></bool></layout></message></message_set>' > "$T/bad.xml"
! "$K" info --xml "$T/bad.xml" 2>"$T/e" && grep -q 'bad.xml:3: <size> 4 must be larger' "$T/e" || fail "bad xml: $(cat "$T/e")"
! "$K" encode --xml "$T/alltypes.xml" --msg ALL_TYPES raw=12 2>"$T/e" && grep -q 'hex value too short' "$T/e" || fail "hex field"
echo "dccl_gen: all passed"
