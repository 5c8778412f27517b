/* kelp bridge: route parsing and datagram framing (core). */
#include <string.h>
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
    if (kelp_parse_long(s, len, &p) < 0 || p < 1 || p > 65535) return KELP_ERR_PARSE;
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
    kelp_be_put64(buf + 5, tx->epoch);
    kelp_be_put64(buf + 13, tx->seq + 1);
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
        rc = replay_check(rx, out->community, kelp_be_get64(buf + 5), kelp_be_get64(buf + 13));
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
