/* What the node and shore brokers share: host records (PHI_HOST_INFO, NODE_BROKER_PING,
 * NODE_BROKER_ACK), TRY_SHORE_HOST and BRIDGE lines, and the PMB_REGISTER request kelp-bridge
 * takes (see include/kelp/field.h and apps/kelp-bridge). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/mission.h>
#include "field_int.h"
#include <kelp/util.h>

#define PORT_MAX 65535

int broker_port(const char *v, size_t vl, unsigned *out)
{
    long p;
    if (kelp_util_parse_long(v, vl, &p) < 0 || p < 1 || p > PORT_MAX) return KELP_ERR_PARSE;
    *out = (unsigned)p;
    return KELP_OK;
}

bool broker_bool(const char *v, bool *out)
{
    /* "true" / "false", and 24.8's example form "true  (default)" */
    size_t n = 0;
    while (v[n] && v[n] != ' ' && v[n] != '\t') n++;
    const char *rest = v + n;
    while (*rest == ' ' || *rest == '\t') rest++;
    if (*rest && !kelp_util_strieq_n(rest, strlen(rest), "(default)")) return false;
    if (kelp_util_parse_bool(v, n, out) != KELP_OK) return false;
    return true;
}

typedef struct host_ctx {
    kelp_field_broker_host *h;
    kelp_diag *d;
    unsigned iroute_port;
    bool udp_given;
} host_ctx;

bool field_ip_ok(const char *s, size_t n)
{
    /* 24.8's isValidIPAddress: "localhost" (any case) or four numbers 0..255 */
    if (kelp_util_strieq_n(s, n, "localhost")) return true;
    size_t i = 0;
    for (int part = 0; part < 4; part++) {
        if (part && (i >= n || s[i++] != '.')) return false;
        int v = 0, digits = 0;
        while (i < n && s[i] >= '0' && s[i] <= '9' && digits < 4) v = v * 10 + (s[i++] - '0'), digits++;
        if (digits == 0 || digits > 3 || v > 255) return false;
    }
    return i == n;
}

static int text_to(char *dst, size_t cap, const char *v, size_t vl, kelp_diag *d)
{
    if (field_copy_text(dst, cap, v, vl) < 0) {
        return kelp_fail(d, KELP_ERR_RANGE, "value too long");
    }
    return KELP_OK;
}

/* "H:P" -> port; 0 when it is not one */
static unsigned route_port(const char *v, size_t vl)
{
    size_t c = vl;
    while (c > 0 && v[c - 1] != ':') c--;
    unsigned p = 0;
    if (c == 0 || c == 1 || broker_port(v + c, vl - c, &p) < 0) return 0;
    return p;
}

static int host_pair(void *ctx, const char *k, size_t kl, const char *v, size_t vl)
{
    host_ctx *c = ctx;
    kelp_field_broker_host *h = c->h;
    if (kelp_util_strieq_n(k, kl, "community") || kelp_util_strieq_n(k, kl, "vname"))
        return text_to(h->community, sizeof h->community, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "key")) return text_to(h->key, sizeof h->key, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "hostip_alts")) return text_to(h->alts, sizeof h->alts, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "host") || kelp_util_strieq_n(k, kl, "hostip") || kelp_util_strieq_n(k, kl, "host_ip") ||
        kelp_util_strieq_n(k, kl, "ip"))
        return text_to(h->host, sizeof h->host, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "keyword")) return text_to(h->keyword, sizeof h->keyword, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "status")) return text_to(h->status, sizeof h->status, v, vl, c->d);
    bool db = kelp_util_strieq_n(k, kl, "port") || kelp_util_strieq_n(k, kl, "port_db");
    if (db || kelp_util_strieq_n(k, kl, "port_udp")) {
        if (broker_port(v, vl, db ? &h->port_db : &h->port_udp) < 0) {
            return kelp_fail(c->d, KELP_ERR_PARSE, "bad port");
        }
        if (db) h->have_port_db = true;
        else c->udp_given = h->have_port_udp = true;
        return KELP_OK;
    }
    bool warp = kelp_util_strieq_n(k, kl, "time_warp") || kelp_util_strieq_n(k, kl, "timewarp");
    if (warp || kelp_util_strieq_n(k, kl, "time")) {
        double d;
        if (sim_number(v, vl, &d) < 0 || (warp && !(d > 0))) {
            return kelp_fail(c->d, KELP_ERR_PARSE, warp ? "bad time_warp" : "bad time");
        }
        if (warp) {
            h->warp = d, h->have_warp = true;
            return text_to(h->warp_s, sizeof h->warp_s, v, vl, c->d);
        }
        h->time = d, h->have_time = true;
        return KELP_OK;
    }
    if (kelp_util_strieq_n(k, kl, "pshare_iroutes")) {
        int rc = text_to(h->iroutes, sizeof h->iroutes, v, vl, c->d);
        if (rc < 0) return rc;
        /* 24.8 (HostRecord::setPShareIRoutes): without port_udp so far, what follows the
         * first ':' when it is a number */
        const char *colon = memchr(v, ':', vl);
        unsigned p;
        if (!c->udp_given && colon && broker_port(colon + 1, vl - (size_t)(colon + 1 - v), &p) == 0)
            h->port_udp = p, h->have_port_udp = true, c->udp_given = true;
    }
    if (kelp_util_strieq_n(k, kl, "pshare_iroutes") && !c->iroute_port) {
        /* "localhost:9200&multicast_8": the first unicast route's port */
        size_t a = 0;
        while (a < vl && !c->iroute_port) {
            size_t e = a;
            while (e < vl && v[e] != '&') e++;
            c->iroute_port = route_port(v + a, e - a);
            a = e + 1;
        }
    }
    return KELP_OK; /* other keys (24.8's id, key, ...) are ignored */
}

int kelp_field_broker_host_parse(const char *s, kelp_field_broker_host *h, kelp_diag *d)
{
    memset(h, 0, sizeof *h);
    if (!s) {
        return kelp_fail(d, KELP_ERR_PARSE, "no text");
    }
    host_ctx c = { h, d, 0, false };
    /* the pairs; an item without '=' is skipped as 24.8 skips it (a hostip_alts list of two
     * addresses leaves one), but a record must have at least one pair */
    size_t pos = 0, len = strlen(s), il;
    const char *it;
    int rc, pairs = 0;
    while ((rc = field_next_item(s, len, &pos, ',', &it, &il)) == 1) {
        if (!memchr(it, '=', il)) continue;
        rc = field_for_pairs(it, il, ',', host_pair, &c, d);
        if (rc < 0) return rc;
        pairs++;
    }
    if (rc < 0 || !pairs) return kelp_fail(d, KELP_ERR_PARSE, rc < 0 ? "unbalanced quote or brace" : "no key=value pair");
    if (!h->port_udp) h->port_udp = c.iroute_port;
    return KELP_OK;
}

bool kelp_field_broker_host_complete(const kelp_field_broker_host *h)
{
    return h->community[0] && h->host[0] && h->port_udp;
}

bool kelp_field_broker_host_valid(const kelp_field_broker_host *h)
{
    return h->community[0] && field_ip_ok(h->host, strlen(h->host)) && h->have_port_db;
}

/* text with every `what` taken out (24.8's findReplace(s, what, "")) */
static int put_without(char *buf, size_t cap, size_t *n, const char *s, const char *what)
{
    size_t wl = strlen(what);
    for (const char *p = s; *p;) {
        if (wl && strncmp(p, what, wl) == 0) {
            p += wl;
            continue;
        }
        char one[2] = { *p++, 0 };
        if (field_put_str(buf, cap, n, one) < 0) return KELP_ERR_NOSPACE;
    }
    return KELP_OK;
}

int kelp_field_broker_host_spec(const kelp_field_broker_host *h, const char *time, const char *key, char *buf, size_t cap)
{
    size_t n = 0;
    int rc = field_put_str(buf, cap, &n, "community=");
    if (rc == 0) rc = field_put_str(buf, cap, &n, h->community);
    if (rc == 0 && h->host[0]) rc = field_put_str(buf, cap, &n, ",hostip="), rc = rc ? rc : field_put_str(buf, cap, &n, h->host);
    if (rc == 0 && h->have_port_db) rc = field_put_str(buf, cap, &n, ",port_db="), rc = rc ? rc : field_put_fixed(buf, cap, &n, h->port_db, 0, false);
    if (rc == 0 && h->have_port_udp) rc = field_put_str(buf, cap, &n, ",port_udp="), rc = rc ? rc : field_put_fixed(buf, cap, &n, h->port_udp, 0, false);
    if (rc == 0 && h->iroutes[0]) rc = field_put_str(buf, cap, &n, ",pshare_iroutes="), rc = rc ? rc : field_put_str(buf, cap, &n, h->iroutes);
    if (rc == 0 && h->keyword[0]) rc = field_put_str(buf, cap, &n, ",keyword="), rc = rc ? rc : field_put_str(buf, cap, &n, h->keyword);
    if (rc == 0 && h->alts[0]) {
        /* the host's own address taken out: "<ip>," first, then "<ip>" (filtered in place) */
        rc = field_put_str(buf, cap, &n, ",hostip_alts=");
        if (rc == 0) {
            size_t at = n;
            char pat[KELP_MAX_NAME + 1];
            kelp_util_snprintf(pat, sizeof pat, "%s,", h->host);
            rc = put_without(buf, cap, &n, h->alts, pat);
            if (rc == 0 && h->host[0]) { /* second pass over what the first one wrote */
                size_t end = n, w = at, hl = strlen(h->host);
                for (size_t r = at; r < end;) {
                    if (r + hl <= end && strncmp(buf + r, h->host, hl) == 0) r += hl;
                    else buf[w++] = buf[r++];
                }
                n = w;
                buf[n] = 0;
            }
        }
    }
    if (rc == 0 && h->warp_s[0]) rc = field_put_str(buf, cap, &n, ",timewarp="), rc = rc ? rc : field_put_str(buf, cap, &n, h->warp_s);
    /* 24.8 writes the record's timewarp after status= (HostRecord::getSpec) */
    if (rc == 0 && h->status[0]) rc = field_put_str(buf, cap, &n, ",status="), rc = rc ? rc : field_put_str(buf, cap, &n, h->warp_s);
    if (rc == 0 && time) rc = field_put_str(buf, cap, &n, ",time="), rc = rc ? rc : field_put_str(buf, cap, &n, time);
    if (rc == 0 && key) rc = field_put_str(buf, cap, &n, ",key="), rc = rc ? rc : field_put_str(buf, cap, &n, key);
    return rc < 0 ? KELP_ERR_NOSPACE : KELP_OK;
}

int kelp_field_broker_try_parse_pshare(const char *s, kelp_field_broker_try *t, kelp_diag *d)
{
    /* 24.8 (NodeBroker::handleConfigTryShoreHost, isValidPShareRoute): pshare_route= only */
    memset(t, 0, sizeof *t);
    if (!s) return kelp_fail(d, KELP_ERR_PARSE, "no text");
    size_t pos = 0, len = strlen(s), il;
    const char *it;
    int rc;
    while ((rc = field_next_item(s, len, &pos, ',', &it, &il)) == 1) {
        const char *eq = memchr(it, '=', il);
        size_t kl = eq ? (size_t)(eq - it) : il;
        while (kl && (it[kl - 1] == ' ' || it[kl - 1] == '\t')) kl--;
        if (!eq || !(kl == 12 && strncmp(it, "pshare_route", 12) == 0)) {
            return kelp_fail(d, KELP_ERR_PARSE, "24.8 takes pshare_route=host:port or pshare_route=multicast_N");
        }
        const char *v = eq + 1;
        size_t vl = il - (size_t)(v - it);
        while (vl && (*v == ' ' || *v == '\t')) v++, vl--;
        if (text_to(t->route, sizeof t->route, v, vl, d) < 0) return KELP_ERR_PARSE;
    }
    if (rc < 0) return kelp_fail(d, KELP_ERR_PARSE, "unbalanced quote or brace");
    const char *r = t->route;
    size_t rl = strlen(r);
    const char *colon = strchr(r, ':');
    long ch;
    if (!colon) {
        if (rl > 10 && strncmp(r, "multicast_", 10) == 0 && kelp_util_parse_long(r + 10, rl - 10, &ch) == 0 && ch >= 0)
            return KELP_OK;
        return kelp_fail(d, KELP_ERR_PARSE, "pshare_route is neither host:port nor multicast_N");
    }
    if (strchr(colon + 1, ':') || colon == r || (size_t)(colon - r) >= sizeof t->host ||
        broker_port(colon + 1, strlen(colon + 1), &t->port) < 0 || strpbrk(r, " =")) {
        return kelp_fail(d, KELP_ERR_PARSE, "pshare_route is not host:port");
    }
    memcpy(t->host, r, (size_t)(colon - r));
    t->host[colon - r] = 0;
    return KELP_OK;
}

int broker_pshare_cmd(const kelp_field_sink *out, const char *src, const char *dest, const char *route, char *last,
                      size_t cap)
{
    /* 24.8's PSHARE_CMD (NodeBroker::postPShareCommand, ShoreBroker::makeBridgeRequest) */
    size_t n = 0;
    if (!last || cap < 16) return KELP_ERR_NOSPACE;
    int rc = field_put_str(last, cap, &n, "cmd=output,src_name=");
    if (rc == 0) rc = field_put_str(last, cap, &n, src);
    if (rc == 0) rc = field_put_str(last, cap, &n, ",dest_name=");
    if (rc == 0) rc = field_put_str(last, cap, &n, dest);
    if (rc == 0) rc = field_put_str(last, cap, &n, ",route=");
    if (rc == 0) rc = field_put_str(last, cap, &n, route);
    if (rc < 0) {
        last[0] = 0;
        return rc;
    }
    out->publish(out->ctx, "PSHARE_CMD", true, last, 0);
    return 1;
}

void broker_block(char *buf, size_t cap, size_t *n, bool *full, const char *label, const char *msg, size_t maxlen,
                  char sep)
{
    /* 24.8's ACBlock: the items of msg (split at sep) joined into lines of up to maxlen
     * characters, a broken line ending in ','; lines after the first under the label's width */
    size_t ll = strlen(label), len = strlen(msg), pos = 0, line = 0;
    if (!msg[0]) {
        broker_put(buf, cap, n, full, "%s", label);
        return;
    }
    while (pos <= len) {
        size_t e = pos;
        while (e < len && msg[e] != sep) e++;
        size_t il = e - pos;
        if (line == 0) broker_put(buf, cap, n, full, "%s%.*s", label, (int)il, msg + pos), line = il;
        else if (line + 1 + il <= maxlen) broker_put(buf, cap, n, full, "%c%.*s", sep, (int)il, msg + pos), line += 1 + il;
        else broker_put(buf, cap, n, full, ",\n%*s%.*s", (int)ll, "", (int)il, msg + pos), line = il;
        pos = e + 1;
        if (e >= len) break;
    }
    broker_put(buf, cap, n, full, "\n");
}

void broker_table(char *buf, size_t cap, size_t *n, bool *full, unsigned ncols, unsigned nrows, unsigned header_rows,
                  broker_cell_fn cell, const void *ctx)
{
    field_actable(buf, cap, n, full, ncols, nrows, header_rows, 2, 0, cell, ctx);
}

void field_actable(char *buf, size_t cap, size_t *n, bool *full, unsigned ncols, unsigned nrows, unsigned header_rows,
                   unsigned sep, unsigned right, broker_cell_fn cell, const void *ctx)
{
    /* 24.8's ACTable: columns as wide as their widest cell, `sep` blanks apart, a dashed line
     * after the header rows, trailing blanks removed, no newline after the last row */
    enum { MAXC = FIELD_ACTABLE_MAX_COLS };
    static const char dashes[] = "--------------------------------------------------------------------------------";
    size_t w[MAXC] = { 0 };
    char tmp[64];
    if (ncols > MAXC) return;
    for (unsigned r = 0; r < nrows; r++)
        for (unsigned c = 0; c < ncols; c++) {
            size_t l = strlen(cell(ctx, r, c, tmp, sizeof tmp));
            if (l > w[c]) w[c] = l;
        }
    for (unsigned r = 0; r <= nrows; r++) {
        bool dash = r == header_rows;
        unsigned src = r > header_rows ? r - 1 : r;
        if (!dash && src >= nrows) break;
        size_t start = *n;
        for (unsigned c = 0; c < ncols; c++) {
            if (dash)
                broker_put(buf, cap, n, full, "%.*s", (int)(w[c] < sizeof dashes - 1 ? w[c] : sizeof dashes - 1), dashes);
            else if (right & (1u << c))
                broker_put(buf, cap, n, full, "%*s", (int)w[c], cell(ctx, src, c, tmp, sizeof tmp));
            else
                broker_put(buf, cap, n, full, "%-*s", (int)w[c], cell(ctx, src, c, tmp, sizeof tmp));
            if (c + 1 < ncols) broker_put(buf, cap, n, full, "%*s", (int)sep, "");
        }
        while (*n > start && *n < cap && buf[*n - 1] == ' ') buf[--*n] = 0;
        if (r < nrows) broker_put(buf, cap, n, full, "\n");
    }
}

typedef struct try_ctx {
    kelp_field_broker_try *t;
    kelp_diag *d;
    bool route, multicast;
} try_ctx;

static int try_pair(void *ctx, const char *k, size_t kl, const char *v, size_t vl)
{
    try_ctx *c = ctx;
    kelp_field_broker_try *t = c->t;
    if (kelp_util_strieq_n(k, kl, "host_ip") || kelp_util_strieq_n(k, kl, "hostip"))
        return text_to(t->host, sizeof t->host, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "community")) return text_to(t->community, sizeof t->community, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "port_udp")) {
        if (broker_port(v, vl, &t->port) < 0) {
            return kelp_fail(c->d, KELP_ERR_PARSE, "bad port_udp");
        }
        return KELP_OK;
    }
    if (kelp_util_strieq_n(k, kl, "pshare_route") || kelp_util_strieq_n(k, kl, "route")) {
        c->route = true;
        if (vl >= 9 && kelp_util_strieq_n(v, 9, "multicast")) {
            c->multicast = true;
            return KELP_OK;
        }
        size_t colon = vl;
        while (colon > 0 && v[colon - 1] != ':') colon--;
        if (colon < 2 || broker_port(v + colon, vl - colon, &t->port) < 0) {
            return kelp_fail(c->d, KELP_ERR_PARSE, "pshare_route is not host:port");
        }
        return text_to(t->host, sizeof t->host, v, colon - 1, c->d);
    }
    return kelp_fail(c->d, KELP_ERR_PARSE, "unknown key");
}

int kelp_field_broker_try_parse(const char *s, kelp_field_broker_try *t, kelp_diag *d)
{
    memset(t, 0, sizeof *t);
    if (!s) {
        return kelp_fail(d, KELP_ERR_PARSE, "no text");
    }
    try_ctx c = { t, d, false, false };
    int rc = field_for_pairs(s, strlen(s), ',', try_pair, &c, d);
    if (rc < 0) return rc;
    if (c.multicast) {
        return kelp_fail(d, KELP_ERR_UNSUPPORTED, "a multicast route (kelp-bridge sends unicast UDP only)");
    }
    if (!t->host[0] || !t->port) {
        return kelp_fail(d, KELP_ERR_PARSE, !t->host[0] ? "no host_ip" : "no port_udp");
    }
    if (strpbrk(t->host, " ,=") || strpbrk(t->community, " ,=")) {
        return kelp_fail(d, KELP_ERR_PARSE, "host or community holds a space, ',' or '='");
    }
    return KELP_OK;
}

/* a MOOS variable name: one word without ',' or '=' */
static bool var_ok(const char *s)
{
    return s[0] && !strpbrk(s, " \t,=");
}

typedef struct bridge_ctx {
    kelp_field_broker_bridge *b;
    kelp_diag *d;
} bridge_ctx;

static int bridge_pair(void *ctx, const char *k, size_t kl, const char *v, size_t vl)
{
    bridge_ctx *c = ctx;
    if (kelp_util_strieq_n(k, kl, "src")) return text_to(c->b->src, sizeof c->b->src, v, vl, c->d);
    if (kelp_util_strieq_n(k, kl, "alias")) return text_to(c->b->alias, sizeof c->b->alias, v, vl, c->d);
    return kelp_fail(c->d, KELP_ERR_PARSE, "unknown key (src=, alias=)");
}

int kelp_field_broker_bridge_parse(const char *s, kelp_field_broker_bridge *b, kelp_diag *d)
{
    memset(b, 0, sizeof *b);
    if (!s) {
        return kelp_fail(d, KELP_ERR_PARSE, "no text");
    }
    bridge_ctx c = { b, d };
    int rc = field_for_pairs(s, strlen(s), ',', bridge_pair, &c, d);
    if (rc < 0) return rc;
    if (!b->alias[0]) memcpy(b->alias, b->src, sizeof b->alias);
    if (!var_ok(b->src) || !var_ok(b->alias)) {
        return kelp_fail(d, KELP_ERR_PARSE, "src (and alias) must be one variable name");
    }
    return KELP_OK;
}

int broker_add_bridge(kelp_field_broker_bridge *list, unsigned *n, const char *src, const char *alias, kelp_diag *d)
{
    for (unsigned i = 0; i < *n; i++)
        if (strcmp(list[i].src, src) == 0 && strcmp(list[i].alias, alias) == 0) return 1; /* listed already */
    if (*n >= KELP_BROKER_MAX_BRIDGES) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many bridges (KELP_BROKER_MAX_BRIDGES)");
    }
    if (strlen(src) >= KELP_MAX_NAME || strlen(alias) >= KELP_MAX_NAME || !var_ok(src) || !var_ok(alias)) {
        return kelp_fail(d, KELP_ERR_PARSE, "not a variable name");
    }
    memcpy(list[*n].src, src, strlen(src) + 1);
    memcpy(list[*n].alias, alias, strlen(alias) + 1);
    (*n)++;
    return 1;
}

int broker_register(const kelp_field_sink *out, const char *src, const char *community, const char *host,
                    unsigned port, const char *alias, char *last, size_t cap)
{
    /* built where the caller keeps the last registration (no second 512-byte buffer on the
     * stack); a registration too long for it is not posted and leaves that text empty */
    char lbuf[1], *msg = last && cap >= KELP_BROKER_MSG ? last : lbuf;
    const size_t mcap = msg == last ? cap : sizeof lbuf;
    size_t n = 0;
    int rc = field_put_str(msg, mcap, &n, "src_var=");
    if (rc == 0) rc = field_put_str(msg, mcap, &n, src);
    if (rc == 0 && community) rc = field_put_str(msg, mcap, &n, ",dest_community=");
    if (rc == 0 && community) rc = field_put_str(msg, mcap, &n, community);
    if (rc == 0) rc = field_put_str(msg, mcap, &n, ",dest_host=");
    if (rc == 0) rc = field_put_str(msg, mcap, &n, host);
    if (rc == 0) rc = field_put_str(msg, mcap, &n, ",dest_port=");
    if (rc == 0) rc = field_put_fixed(msg, mcap, &n, port, 0, false);
    if (rc == 0) rc = field_put_str(msg, mcap, &n, ",dest_alias=");
    if (rc == 0) rc = field_put_str(msg, mcap, &n, alias);
    if (rc < 0) {
        if (msg == last) last[0] = 0;
        return rc;
    }
    out->publish(out->ctx, "PMB_REGISTER", true, msg, 0);
    return 1;
}

int broker_host_format(const kelp_field_broker_host *h, const char *keyword, double warp, kelp_time now, const char *status,
                       char *buf, size_t cap)
{
    size_t n = 0;
    int rc = field_put_str(buf, cap, &n, "community=");
    if (rc == 0) rc = field_put_str(buf, cap, &n, h->community);
    if (rc == 0) rc = field_put_str(buf, cap, &n, ",host=");
    if (rc == 0) rc = field_put_str(buf, cap, &n, h->host);
    if (rc == 0 && h->port_db) rc = field_put_str(buf, cap, &n, ",port=");
    if (rc == 0 && h->port_db) rc = field_put_fixed(buf, cap, &n, h->port_db, 0, false);
    if (rc == 0) rc = field_put_str(buf, cap, &n, ",port_udp=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, h->port_udp, 0, false);
    if (rc == 0 && keyword[0]) rc = field_put_str(buf, cap, &n, ",keyword=");
    if (rc == 0 && keyword[0]) rc = field_put_str(buf, cap, &n, keyword);
    if (rc == 0) rc = field_put_str(buf, cap, &n, ",time_warp=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, warp, 6, true);
    if (rc == 0) rc = field_put_str(buf, cap, &n, ",time=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, now, 2, true);
    if (rc == 0 && status) rc = field_put_str(buf, cap, &n, ",status=");
    if (rc == 0 && status) rc = field_put_str(buf, cap, &n, status);
    return rc;
}

bool broker_same_host(const kelp_field_broker_host *a, const kelp_field_broker_host *b)
{
    return strcmp(a->community, b->community) == 0 && strcmp(a->host, b->host) == 0 && a->port_db == b->port_db &&
           a->port_udp == b->port_udp && a->have_warp == b->have_warp && (!a->have_warp || a->warp == b->warp);
}

void broker_put(char *buf, size_t cap, size_t *n, bool *full, const char *fmt, ...)
{
    if (*n >= cap) {
        *full = true;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    int w = kelp_util_vsnprintf(buf + *n, cap - *n, fmt, ap);
    va_end(ap);
    if (w < 0 || (size_t)w >= cap - *n) {
        *full = true;
        *n = cap;
    } else
        *n += (size_t)w;
}
