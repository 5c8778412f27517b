/* kelp bridge: route parsing and datagram framing (core). */
#include <math.h>
#include <stdarg.h>
#include <string.h>
#include <kelp/util.h>
#include <kelp/bridge.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include "bus_int.h"

static const char *skip_ws(const char *s)
{
    while (*s == ' ' || *s == '\t') s++;
    return s;
}

/* Copy a comma-separated list inside [...] into names (the n-th at base + n * stride; base
 * NULL: check and count only); returns count or <0. *glob (optional) is set when a name has
 * a '*' or '?'. */
static int bracket_list(const char **ps, char *base, size_t stride, int cap, bool *glob)
{
    const char *s = skip_ws(*ps);
    if (*s != '[') return KELP_ERR_PARSE;
    const char *e = strchr(s, ']');
    if (!e) return KELP_ERR_PARSE;
    int n = 0;
    const char *a = s + 1;
    while (a < e) {
        const char *c = memchr(a, ',', (size_t)(e - a));
        if (!c) c = e;
        const char *x = a, *y = c;
        while (x < y && (*x == ' ' || *x == '\t')) x++;
        while (y > x && (y[-1] == ' ' || y[-1] == '\t')) y--;
        if (y > x) {
            if (n >= cap || (size_t)(y - x) >= KELP_MAX_NAME) return KELP_ERR_RANGE;
            if (glob && (memchr(x, '*', (size_t)(y - x)) || memchr(x, '?', (size_t)(y - x)))) *glob = true;
            if (base) {
                char *name = base + (size_t)n * stride;
                memcpy(name, x, (size_t)(y - x));
                name[y - x] = 0;
            }
            n++;
        }
        a = c + 1;
    }
    *ps = e + 1;
    return n;
}

static int parse_port(const char *s, size_t len, uint16_t *port)
{
    long p;
    if (kelp_util_parse_long(s, len, &p) < 0 || p < 1 || p > 65535) return KELP_ERR_PARSE;
    *port = (uint16_t)p;
    return KELP_OK;
}

int kelp_bridge_parse_share(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n, kelp_diag *d)
{
    /* checked first, then (when the routes fit) the two lists are read again into them */
    const char *s = line;
    int ns = bracket_list(&s, NULL, 0, 16, NULL);
    if (ns <= 0) return kelp_fail(d, KELP_ERR_PARSE, "expected [VAR,...] at the start");
    s = skip_ws(s);
    while (*s == '-') s++;
    if (*s != '>') return kelp_fail(d, KELP_ERR_PARSE, "expected '->' after the variable list");
    s = skip_ws(s + 1);
    const char *at = strchr(s, '@');
    if (!at) return kelp_fail(d, KELP_ERR_PARSE, "expected 'community @ host:port'");
    const char *c0 = s, *c1 = at;
    while (c1 > c0 && (c1[-1] == ' ' || c1[-1] == '\t')) c1--;
    if (c1 == c0 || (size_t)(c1 - c0) >= KELP_MAX_NAME) return kelp_fail(d, KELP_ERR_PARSE, "bad community name");
    s = skip_ws(at + 1);
    const char *colon = strchr(s, ':');
    if (!colon) return kelp_fail(d, KELP_ERR_PARSE, "expected host:port");
    const char *h1 = colon;
    while (h1 > s && (h1[-1] == ' ' || h1[-1] == '\t')) h1--;
    if (h1 == s || (size_t)(h1 - s) >= KELP_MAX_NAME) return kelp_fail(d, KELP_ERR_PARSE, "bad host");
    const char *p0 = skip_ws(colon + 1), *p1 = p0;
    while (*p1 >= '0' && *p1 <= '9') p1++;
    uint16_t port;
    if (parse_port(p0, (size_t)(p1 - p0), &port) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad port (1-65535)");
    s = skip_ws(p1);
    int na = 0;
    const char *alias_list = s;
    if (*s == '[') {
        na = bracket_list(&s, NULL, 0, 16, NULL);
        if (na < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad [ALIAS,...] list");
        if (na != ns) return kelp_fail(d, KELP_ERR_PARSE, "alias list length differs from variable list");
    }
    if (*skip_ws(s)) return kelp_fail(d, KELP_ERR_PARSE, "unexpected text at the end");
    if ((size_t)ns > cap) return KELP_ERR_NOSPACE;
    memset(routes, 0, (size_t)ns * sizeof routes[0]);
    s = line;
    (void)bracket_list(&s, routes[0].src, sizeof routes[0], 16, NULL);
    if (na) {
        s = alias_list;
        (void)bracket_list(&s, routes[0].alias, sizeof routes[0], 16, NULL);
    }
    for (int i = 0; i < ns; i++) {
        kelp_bridge_route *r = &routes[i];
        memcpy(r->community, c0, (size_t)(c1 - c0));
        size_t hl = (size_t)(h1 - (skip_ws(at + 1)));
        memcpy(r->host, skip_ws(at + 1), hl);
        r->host[hl] = 0;
        r->port = port;
    }
    *n = (size_t)ns;
    return KELP_OK;
}

int kelp_bridge_parse_register(const char *s, kelp_bridge_route *r, kelp_diag *d)
{
    memset(r, 0, sizeof *r);
    char port[16];
    if (kelp_kv_get(s, ',', "src_var", r->src, sizeof r->src) != 1 || !r->src[0]) return kelp_fail(d, KELP_ERR_PARSE, "missing src_var");
    if (kelp_kv_get(s, ',', "dest_host", r->host, sizeof r->host) != 1 || !r->host[0]) return kelp_fail(d, KELP_ERR_PARSE, "missing dest_host");
    if (kelp_kv_get(s, ',', "dest_port", port, sizeof port) != 1 || parse_port(port, strlen(port), &r->port) < 0) return kelp_fail(d, KELP_ERR_PARSE, "missing or bad dest_port");
    if (kelp_kv_get(s, ',', "dest_community", r->community, sizeof r->community) < 0 ||
        kelp_kv_get(s, ',', "dest_alias", r->alias, sizeof r->alias) < 0) return kelp_fail(d, KELP_ERR_PARSE, "value too long");
    return KELP_OK;
}

void kelp_bridge_tx_init(kelp_bridge_tx *tx, uint64_t epoch)
{
    tx->epoch = epoch;
    tx->seq = 0;
}

void kelp_bridge_rx_init(kelp_bridge_rx *rx, kelp_bridge_peer *peers, size_t cap)
{
    memset(rx, 0, sizeof *rx);
    rx->peers = peers;
    rx->cap = cap;
}

int kelp_bridge_frame(kelp_bridge_tx *tx, const kelp_var *v, const char *as, const uint8_t *key, size_t keylen,
                      kelp_hmac_fn hmac, void *user, uint8_t *buf, size_t cap, size_t *len)
{
    if (!tx || !v || !buf || !len || (keylen && !hmac)) return KELP_ERR_ARG;
    if (cap < KELP_BRIDGE_HDR_LEN) return KELP_ERR_NOSPACE;
    memcpy(buf, KELP_BRIDGE_MAGIC, 4);
    buf[4] = keylen ? KELP_BRIDGE_F_AUTH : 0;
    kelp_util_be_put64(buf + 5, tx->epoch);
    kelp_util_be_put64(buf + 13, tx->seq + 1);
    const char *name = (as && *as) ? as : v->name;
    size_t n = 0;
    /* encode with the alias name and the BRIDGED flag without copying the value */
    int rc = kelp_var_encode_parts(v->time, name, v->source, v->source_aux, v->community, v->kind, v->dval,
                                   v->kind == KELP_VAR_DOUBLE ? NULL : v->sval, v->kind == KELP_VAR_DOUBLE ? 0 : v->slen,
                                   (uint8_t)(v->flags | KELP_VAR_FLAG_BRIDGED), buf + KELP_BRIDGE_HDR_LEN,
                                   cap - KELP_BRIDGE_HDR_LEN, &n);
    if (rc < 0) return rc;
    n += KELP_BRIDGE_HDR_LEN;
    if (keylen) {
        if (cap - n < KELP_BRIDGE_HMAC_LEN) return KELP_ERR_NOSPACE;
        if (hmac(key, keylen, buf, n, buf + n, user) < 0) return KELP_ERR_CRYPTO;
        n += KELP_BRIDGE_HMAC_LEN;
    }
    tx->seq++;
    *len = n;
    return KELP_OK;
}

static kelp_bridge_peer *peer_slot(kelp_bridge_rx *rx, const char *community, bool *fresh)
{
    kelp_bridge_peer *lru = NULL;
    *fresh = false;
    for (size_t i = 0; i < rx->n; i++) {
        if (strcmp(rx->peers[i].community, community) == 0) return &rx->peers[i];
        if (!lru || rx->peers[i].used < lru->used) lru = &rx->peers[i];
    }
    if (rx->cap == 0) return NULL;
    *fresh = true;
    if (rx->n < rx->cap) return &rx->peers[rx->n++];
    rx->evicted++;
    return lru;
}

/* The replay rule; updates the peer only when the datagram is accepted. */
static int replay_check(kelp_bridge_rx *rx, const char *community, uint64_t epoch, uint64_t seq)
{
    bool fresh;
    kelp_bridge_peer *p = peer_slot(rx, community, &fresh);
    if (!p) return KELP_OK;
    if (seq == 0) goto replay;
    if (!fresh && epoch < p->epoch) goto replay;
    if (fresh || epoch > p->epoch) {
        memset(p, 0, sizeof *p);
        size_t cl = strlen(community);
        memcpy(p->community, community, cl < sizeof p->community ? cl : sizeof p->community - 1);
        p->epoch = epoch;
        p->high = seq;
        p->window = 1;
    } else if (seq > p->high) {
        uint64_t d = seq - p->high;
        p->window = d >= KELP_BRIDGE_WINDOW ? 1 : (p->window << d) | 1;
        p->high = seq;
    } else {
        uint64_t d = p->high - seq;
        if (d >= KELP_BRIDGE_WINDOW || (p->window >> d) & 1u) goto replay;
        p->window |= (uint64_t)1 << d;
    }
    p->used = ++rx->tick;
    return KELP_OK;
replay:
    rx->replayed++;
    return KELP_ERR_REPLAY;
}

int kelp_bridge_unframe(kelp_bridge_rx *rx, const uint8_t *buf, size_t len, const uint8_t *key, size_t keylen,
                        kelp_hmac_fn hmac, void *user, kelp_var *out)
{
    if (!buf || !out || (keylen && !hmac)) return KELP_ERR_ARG;
    if (len < 4 || memcmp(buf, KELP_BRIDGE_MAGIC, 4) != 0) return KELP_ERR_PARSE;
    if (len < KELP_BRIDGE_HDR_LEN) return KELP_ERR_TRUNCATED;
    uint8_t flags = buf[4];
    if (flags & ~KELP_BRIDGE_F_AUTH) return KELP_ERR_PARSE;
    size_t body = len - KELP_BRIDGE_HDR_LEN;
    if (flags & KELP_BRIDGE_F_AUTH) {
        if (body < KELP_BRIDGE_HMAC_LEN) return keylen ? KELP_ERR_AUTH : KELP_ERR_TRUNCATED;
        body -= KELP_BRIDGE_HMAC_LEN;
    }
    if (keylen) {
        if (!(flags & KELP_BRIDGE_F_AUTH)) return KELP_ERR_AUTH;
        uint8_t mac[KELP_BRIDGE_HMAC_LEN];
        if (hmac(key, keylen, buf, KELP_BRIDGE_HDR_LEN + body, mac, user) < 0) return KELP_ERR_CRYPTO;
        /* constant-time compare */
        uint8_t d = 0;
        for (size_t i = 0; i < KELP_BRIDGE_HMAC_LEN; i++) d |= (uint8_t)(mac[i] ^ buf[KELP_BRIDGE_HDR_LEN + body + i]);
        if (d) return KELP_ERR_AUTH;
    }
    int rc = kelp_var_decode(buf + KELP_BRIDGE_HDR_LEN, body, out);
    if (rc < 0) return rc;
    if (rx) {
        rc = replay_check(rx, out->community, kelp_util_be_get64(buf + 5), kelp_util_be_get64(buf + 13));
        if (rc < 0) return rc;
    }
    out->flags |= KELP_VAR_FLAG_BRIDGED;
    return KELP_OK;
}

bool kelp_bridge_allowed(const char *allow, const char *name)
{
    if (!allow || !*allow) return true;
    const char *a = allow;
    while (*a) {
        const char *c = strchr(a, ',');
        size_t n = c ? (size_t)(c - a) : strlen(a);
        const char *x = a, *y = a + n;
        while (x < y && (*x == ' ' || *x == '\t')) x++;
        while (y > x && (y[-1] == ' ' || y[-1] == '\t')) y--;
        char pat[KELP_MAX_NAME];
        if (y > x && (size_t)(y - x) < sizeof pat) {
            memcpy(pat, x, (size_t)(y - x));
            pat[y - x] = 0;
            if (kelp_bus_match(pat, name)) return true;
        }
        if (!c) break;
        a = c + 1;
    }
    return false;
}

/* ------------------------------------------------------------------ renaming lists (kelp-canbridge) */

/* One name or a [list] starting at *ps, up to a stop character; names into base + n * stride
 * (NULL: check and count only). Returns the count or <0. */
static int name_or_list(const char **ps, const char *stops, char *base, size_t stride, bool *glob)
{
    const char *s = *ps;
    if (*s == '[') return bracket_list(ps, base, stride, 16, glob);
    const char *e = s;
    while (*e && !strchr(stops, *e)) e++;
    *ps = e;
    if (!(e > s && (size_t)(e - s) < KELP_MAX_NAME)) return KELP_ERR_PARSE;
    if (glob && (memchr(s, '*', (size_t)(e - s)) || memchr(s, '?', (size_t)(e - s)))) *glob = true;
    if (base) {
        memcpy(base, s, (size_t)(e - s));
        base[e - s] = 0;
    }
    return 1;
}

int kelp_bridge_rename_list(const char *line, char *src, char *alias, size_t stride, int *ns_out, int *na_out,
                            bool *glob, kelp_diag *d)
{
    const char *s = skip_ws(line);
    int ns, na = 0;
    *glob = false;
    ns = name_or_list(&s, " \t-", src, stride, glob);
    if (ns <= 0) return kelp_fail(d, KELP_ERR_PARSE, "expected VAR or [VAR,...]");
    s = skip_ws(s);
    if (*s == '-') {
        while (*s == '-') s++;
        if (*s != '>') return kelp_fail(d, KELP_ERR_PARSE, "expected '->'");
        s = skip_ws(s + 1);
        na = name_or_list(&s, " \t", alias, stride, NULL);
        if (na != ns) return kelp_fail(d, KELP_ERR_PARSE, "alias list length differs from variable list");
    }
    if (*skip_ws(s)) return kelp_fail(d, KELP_ERR_PARSE, "unexpected text at the end");
    *ns_out = ns;
    *na_out = na;
    return KELP_OK;
}

int kelp_bridge_parse_rename(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n, kelp_diag *d)
{
    int ns, na;
    bool glob;
    /* checked first, then (when the routes fit) read again into them */
    int rc = kelp_bridge_rename_list(line, NULL, NULL, 0, &ns, &na, &glob, d);
    if (rc) return rc;
    if ((size_t)ns > cap) return KELP_ERR_NOSPACE;
    memset(routes, 0, (size_t)ns * sizeof routes[0]);
    if (na && glob) return kelp_fail(d, KELP_ERR_PARSE, "a glob cannot be renamed");
    (void)kelp_bridge_rename_list(line, routes[0].src, routes[0].alias, sizeof routes[0], &ns, &na, &glob, d);
    *n = (size_t)ns;
    return KELP_OK;
}

/* ---- pShare's model ---- */

/* printf-style text appended at buf + *len (cut to fit; *len counts what was wanted) */
static void bridge_putf(char *buf, size_t cap, size_t *len, const char *fmt, ...) KELP_PRINTF(4, 5);
static void bridge_putf(char *buf, size_t cap, size_t *len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = kelp_util_vsnprintf(buf + (*len < cap ? *len : cap - 1), *len < cap ? cap - *len : 1, fmt, ap);
    va_end(ap);
    if (k > 0) *len += (size_t)k;
}

/* s[0..len) trimmed of blanks */
static void trim_n(const char **s, size_t *len)
{
    while (*len && (**s == ' ' || **s == '\t')) (*s)++, (*len)--;
    while (*len && ((*s)[*len - 1] == ' ' || (*s)[*len - 1] == '\t')) (*len)--;
}

/* one route "host:port[:udp]" or "multicast_N" (optionally "dest:" before it when dest is
 * non-NULL, the shorthand) into r; "@freq" after it is dropped */
static int one_route(const char *s, size_t len, kelp_bridge_route *r, char *dest, kelp_diag *d)
{
    const char *at = memchr(s, '@', len);
    if (at) { /* "@F": F shares per second (24.8: anything not a number is 0, every notification) */
        const char *f = at + 1;
        size_t fl = len - (size_t)(f - s);
        trim_n(&f, &fl);
        double hz;
        r->frequency = kelp_util_parse_finite(f, fl, &hz) == 0 && hz > 0 ? hz : 0;
        len = (size_t)(at - s);
    }
    trim_n(&s, &len);
    const char *part[4];
    size_t pl[4], np = 0, a = 0;
    for (size_t i = 0; i <= len; i++)
        if (i == len || s[i] == ':') {
            if (np == 4) return kelp_fail(d, KELP_ERR_PARSE, "too many parts in a route");
            part[np] = s + a, pl[np++] = i - a;
            a = i + 1;
        }
    for (size_t i = 0; i < np; i++) trim_n(&part[i], &pl[i]);
    const char *last = part[np - 1];
    if (pl[np - 1] > 10 && strncmp(last, "multicast_", 10) == 0) { /* [dest:]multicast_N */
        long ch;
        if (np > (dest ? 2u : 1u) || kelp_util_parse_long(last + 10, pl[np - 1] - 10, &ch) < 0 || ch < 0 || ch > 255)
            return kelp_fail(d, KELP_ERR_PARSE, "bad multicast_N route");
        if (np == 2 && (pl[0] == 0 || pl[0] >= KELP_MAX_NAME)) return kelp_fail(d, KELP_ERR_PARSE, "bad name in a route");
        if (np == 2) memcpy(dest, part[0], pl[0]), dest[pl[0]] = 0;
        r->multicast = true, r->port = (uint16_t)ch, r->host[0] = 0;
        return KELP_OK;
    }
    size_t h = 0; /* [dest:]host:port[:udp] */
    if (np == 4 || (np == 3 && !(pl[2] == 3 && strncmp(part[2], "udp", 3) == 0))) {
        if (!dest || (np == 4 && !(pl[3] == 3 && strncmp(part[3], "udp", 3) == 0)))
            return kelp_fail(d, KELP_ERR_PARSE, "a route is host:port or multicast_N");
        if (pl[0] == 0 || pl[0] >= KELP_MAX_NAME) return kelp_fail(d, KELP_ERR_PARSE, "bad name in a route");
        memcpy(dest, part[0], pl[0]), dest[pl[0]] = 0;
        h = 1;
    }
    if (np < h + 2) return kelp_fail(d, KELP_ERR_PARSE, "a route is host:port or multicast_N");
    if (pl[h] == 0 || pl[h] >= KELP_MAX_NAME) return kelp_fail(d, KELP_ERR_PARSE, "bad host in a route");
    if (parse_port(part[h + 1], pl[h + 1], &r->port) < 0) return kelp_fail(d, KELP_ERR_PARSE, "bad port in a route (1-65535)");
    memcpy(r->host, part[h], pl[h]);
    r->host[pl[h]] = 0;
    r->multicast = false;
    return KELP_OK;
}

/* the '&' list of routes in s[0..len), each filled from proto */
static int route_list(const char *s, size_t len, const kelp_bridge_route *proto, bool shorthand, kelp_bridge_route *routes,
                      size_t cap, size_t *n, kelp_diag *d)
{
    size_t a = 0;
    for (size_t i = 0; i <= len; i++) {
        if (i < len && s[i] != '&') continue;
        const char *it = s + a;
        size_t il = i - a;
        a = i + 1;
        trim_n(&it, &il);
        if (!il) continue;
        if (*n >= cap) return kelp_fail(d, KELP_ERR_NOSPACE, "too many routes");
        kelp_bridge_route *r = &routes[*n];
        *r = *proto;
        char dest[KELP_MAX_NAME] = "";
        if (one_route(it, il, r, shorthand ? dest : NULL, d) < 0) return KELP_ERR_PARSE;
        if (dest[0]) memcpy(r->alias, dest, sizeof dest);
        (*n)++;
    }
    if (!*n) return kelp_fail(d, KELP_ERR_PARSE, "no route");
    return KELP_OK;
}

/* the value of key in a "k=v,k=v" line, in place (no copy: a route list may be long) */
static bool kv_find(const char *line, const char *key, const char **v, size_t *vl)
{
    size_t pos = 0, kl;
    const char *k;
    while (kelp_kv_next(line, ',', &pos, &k, &kl, v, vl) == 1)
        if (kelp_util_strieq_n(k, kl, key)) return true;
    return false;
}

static bool names_route(const char *line)
{
    for (const char *p = line; *p; p++)
        if ((p[0] == 'r' || p[0] == 'R') && kelp_util_strieq_n(p, 5, "route")) return true;
    return false;
}

/* a number-valued key of an output line into *out (left alone when absent or not a number) */
static void kv_number(const char *line, const char *key, double *out)
{
    const char *v;
    size_t vl;
    double x;
    if (kv_find(line, key, &v, &vl) && kelp_util_parse_finite(v, vl, &x) == 0) *out = x;
}

int kelp_bridge_pshare_output(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n, kelp_diag *d)
{
    kelp_bridge_route proto;
    memset(&proto, 0, sizeof proto);
    proto.limited = true, proto.duration = -1, proto.max_shares = -1;
    const char *rv;
    size_t rvl;
    *n = 0;
    if (names_route(line)) { /* src_name=X, dest_name=Y, route=R & R, frequency=F, duration=D, max_shares=M */
        double ms = -1;
        kv_number(line, "frequency", &proto.frequency);
        kv_number(line, "duration", &proto.duration);
        kv_number(line, "max_shares", &ms);
        if (!(proto.frequency > 0)) proto.frequency = 0;
        proto.max_shares = ms >= 0 && ms < 2147483647.0 ? (int)ms : -1;
        int rc = kelp_kv_get(line, ',', "src_name", proto.src, sizeof proto.src);
        if (rc != 1 || !proto.src[0]) return kelp_fail(d, KELP_ERR_PARSE, "src_name is a required field");
        if (kelp_kv_get(line, ',', "dest_name", proto.alias, sizeof proto.alias) < 0) return kelp_fail(d, KELP_ERR_PARSE, "dest_name too long");
        if (!kv_find(line, "route", &rv, &rvl)) return kelp_fail(d, KELP_ERR_PARSE, "route is a required field");
        if (!proto.alias[0]) memcpy(proto.alias, proto.src, sizeof proto.src);
        return route_list(rv, rvl, &proto, false, routes, cap, n, d);
    }
    const char *arrow = strstr(line, "->"); /* X->[Y:]host:port & ... */
    if (!arrow) return kelp_fail(d, KELP_ERR_PARSE, "expected src_name=.., route=.. or X->route");
    const char *src = line;
    size_t sl = (size_t)(arrow - line);
    trim_n(&src, &sl);
    if (!sl || sl >= sizeof proto.src) return kelp_fail(d, KELP_ERR_PARSE, "bad variable name before ->");
    memcpy(proto.src, src, sl);
    memcpy(proto.alias, src, sl);
    return route_list(arrow + 2, strlen(arrow + 2), &proto, true, routes, cap, n, d);
}

int kelp_bridge_pshare_input(const char *line, kelp_bridge_route *routes, size_t cap, size_t *n, char *white, size_t wcap,
                             kelp_diag *d)
{
    kelp_bridge_route proto;
    memset(&proto, 0, sizeof proto);
    const char *rv;
    size_t rvl;
    *n = 0;
    if (!kv_find(line, "route", &rv, &rvl)) return kelp_fail(d, KELP_ERR_PARSE, "route is a required field");
    int rc = route_list(rv, rvl, &proto, false, routes, cap, n, d);
    if (rc < 0 || !white || !wcap) return rc;
    white[0] = 0;
    if (!kv_find(line, "white_list", &rv, &rvl)) return KELP_OK;
    size_t w = 0;
    for (size_t i = 0; i < rvl && w + 1 < wcap; i++)
        if (rv[i] != ' ' && rv[i] != '\t') white[w++] = rv[i] == '&' ? ',' : rv[i];
    white[w] = 0;
    return KELP_OK;
}

bool kelp_bridge_share_active(const kelp_bridge_route *r, const kelp_bridge_share *s, double now)
{
    if (!isfinite(now)) return false;
    if (r->limited) {
        if (r->duration == 0 && s->done < r->max_shares) return true;
        if (r->duration >= 0 && now - s->created > r->duration) return false;
        if (r->max_shares >= 0 && s->done >= r->max_shares) return false;
    }
    /* 1/frequency since the last share; a step back (now before it) shares again */
    return !(r->frequency > 0 && s->done > 0 && now >= s->last_sent && now - s->last_sent < 1.0 / r->frequency);
}

int kelp_bridge_pshare_cmd(const char *s)
{
    char cmd[16];
    if (kelp_kv_get(s, ',', "cmd", cmd, sizeof cmd) != 1) return 0;
    return kelp_util_strieq_n(cmd, strlen(cmd), "output") ? 1 : kelp_util_strieq_n(cmd, strlen(cmd), "input") ? 2 : 0;
}

static void put_addr(char *buf, size_t cap, size_t *len, const kelp_bridge_route *r)
{
    if (r->multicast)
        bridge_putf(buf, cap, len, "%s:%u:multicast_%u", KELP_PSHARE_MCAST_ADDR, KELP_PSHARE_MCAST_PORT + r->port, r->port);
    else
        bridge_putf(buf, cap, len, "%s:%u", r->host, r->port);
}

static int addr_cmp(const kelp_bridge_route *a, const kelp_bridge_route *b)
{
    const char *ha = a->multicast ? KELP_PSHARE_MCAST_ADDR : a->host, *hb = b->multicast ? KELP_PSHARE_MCAST_ADDR : b->host;
    unsigned pa = a->multicast ? KELP_PSHARE_MCAST_PORT + a->port : a->port;
    unsigned pb = b->multicast ? KELP_PSHARE_MCAST_PORT + b->port : b->port;
    int c = strcmp(ha, hb);
    return c ? c : (pa > pb) - (pa < pb);
}

int kelp_bridge_pshare_summary(const kelp_bridge_route *r, size_t n, bool input, char *buf, size_t cap)
{
    size_t len = 0;
    if (!cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    const kelp_bridge_route *prev = NULL;
    for (size_t k = 0; k < n; k++) { /* the next source (output) or address (input) in order */
        const kelp_bridge_route *next = NULL;
        for (size_t i = 0; i < n; i++) {
            int after = !prev ? 1 : input ? addr_cmp(&r[i], prev) : strcmp(r[i].src, prev->src);
            int before = !next ? -1 : input ? addr_cmp(&r[i], next) : strcmp(r[i].src, next->src);
            if (after > 0 && before < 0) next = &r[i];
        }
        if (!next) break;
        prev = next;
        if (input) {
            if (len) bridge_putf(buf, cap, &len, ",");
            put_addr(buf, cap, &len, next);
            continue;
        }
        bridge_putf(buf, cap, &len, "%s%s->", len ? ", " : "", next->src);
        bool first = true;
        for (size_t i = 0; i < n; i++) {
            if (strcmp(r[i].src, next->src) != 0) continue;
            bridge_putf(buf, cap, &len, "%s%s:", first ? "" : " & ", r[i].alias[0] ? r[i].alias : r[i].src);
            put_addr(buf, cap, &len, &r[i]);
            first = false;
        }
    }
    return len + 1 >= cap ? KELP_ERR_NOSPACE : KELP_OK;
}

long kelp_bridge_table_find(const kelp_bridge_route *tab, size_t n, const kelp_bridge_route *r)
{
    for (size_t i = 0; i < n; i++) {
        const kelp_bridge_route *o = &tab[i];
        if (strcmp(o->src, r->src) == 0 && strcmp(o->alias, r->alias) == 0 && strcmp(o->host, r->host) == 0 &&
            o->port == r->port && o->multicast == r->multicast)
            return (long)i;
    }
    return -1;
}

bool kelp_bridge_share_restate(kelp_bridge_route *q, kelp_bridge_share *s, const kelp_bridge_route *r, double now)
{
    q->limited = r->limited, q->frequency = r->frequency, q->duration = r->duration, q->max_shares = r->max_shares;
    *s = (kelp_bridge_share){ .created = now };
    if (!(r->limited && r->duration == 0)) return false;
    q->max_shares = 1, q->duration = INFINITY;
    return true;
}

int kelp_bridge_table_add(kelp_bridge_route *tab, size_t *n, size_t cap, const kelp_bridge_route *r)
{
    if (kelp_bridge_table_find(tab, *n, r) >= 0) return 0;
    if (*n >= cap) return KELP_ERR_NOSPACE;
    tab[(*n)++] = *r;
    return 1;
}
