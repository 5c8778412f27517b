/* pHostInfo's logic: the host's addresses (found by the edge) in, PHI_HOST_* out (see
 * include/kelp/field.h). */
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/mission.h>
#include <kelp/util.h>
#include "field_int.h"

static void copy(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = 0;
}

void kelp_field_hostinfo_cfg_default(kelp_field_hostinfo_cfg *c)
{
    memset(c, 0, sizeof *c);
    copy(c->community, sizeof c->community, "kelp");
    c->warp = 1;
    copy(c->default_ip, sizeof c->default_ip, "localhost");
}

void kelp_field_hostinfo_init(kelp_field_hostinfo *h, const kelp_field_hostinfo_cfg *cfg)
{
    memset(h, 0, sizeof *h);
    h->cfg = *cfg;
    h->post_due = true;
}

/* a dotted quad of four numbers 0..255 */
static bool quad_ok(const char *s)
{
    return !kelp_util_strieq(s, "localhost") && field_ip_ok(s, strlen(s));
}

static int rank(const char *ifname, char *label, size_t cap)
{
    if (!strncmp(ifname, "eth", 3) || !strncmp(ifname, "en", 2)) {
        copy(label, cap, "LINUX_ETHERNET");
        return 0;
    }
    if (!strncmp(ifname, "wlan", 4) || !strncmp(ifname, "wl", 2)) {
        copy(label, cap, "LINUX_WIFI");
        return 1;
    }
    size_t i = 0;
    for (; ifname[i] && i + 1 < cap; i++) {
        char c = ifname[i];
        label[i] = (char)(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
    }
    label[i] = 0;
    return 2;
}

void kelp_field_hostinfo_set(kelp_field_hostinfo *h, const char *const *ifnames, const char *const *ips, unsigned n)
{
    h->naddr = 0;
    for (int pass = 0; pass < 3; pass++)
        for (unsigned i = 0; i < n && h->naddr < KELP_HOSTINFO_MAX_ADDRS; i++) {
            char label[32];
            if (!ifnames[i] || !ips[i] || !quad_ok(ips[i]) || !strncmp(ips[i], "127.", 4)) continue;
            if (rank(ifnames[i], label, sizeof label) != pass) continue;
            kelp_hostinfo_addr *a = &h->addr[h->naddr++];
            copy(a->source, sizeof a->source, label);
            copy(a->ip, sizeof a->ip, ips[i]);
            copy(a->ifname, sizeof a->ifname, ifnames[i]);
        }
    h->post_due = true;
    h->redetect = false;
}

/* PSHARE_INPUT_SUMMARY "localhost:9000:udp,1.2.3.4:2000:multicast_23" as MOOS-IvP 24.8's
 * pHostInfo carries it in pshare_iroutes: a "host:port[:udp]" route is host:port, a
 * "host:port:<other>" route is <other> (multicast_23), anything else is dropped; '&' joins them */
static void iroutes(const char *s, char *out, size_t cap)
{
    size_t n = 0, pos = 0, len = strlen(s), il;
    const char *it;
    out[0] = 0;
    while (field_next_item(s, len, &pos, ',', &it, &il) == 1) {
        const char *c1 = memchr(it, ':', il);
        if (!c1) continue;
        const char *c2 = memchr(c1 + 1, ':', il - (size_t)(c1 + 1 - it));
        size_t hl = (size_t)(c1 - it), pl = (size_t)((c2 ? c2 : it + il) - c1 - 1);
        const char *proto = c2 ? c2 + 1 : "udp";
        size_t prl = c2 ? il - (size_t)(c2 + 1 - it) : 3;
        char host[16];
        long port;
        bool host_ok = kelp_util_strieq_n(it, hl, "localhost");
        if (!host_ok && hl < sizeof host) {
            memcpy(host, it, hl);
            host[hl] = 0;
            host_ok = quad_ok(host);
        }
        if (!host_ok || prl == 0 || memchr(proto, ':', prl) || kelp_util_parse_long(c1 + 1, pl, &port) < 0) continue;
        size_t keep = kelp_util_strieq_n(proto, prl, "udp") ? hl + 1 + pl : prl;
        const char *from = kelp_util_strieq_n(proto, prl, "udp") ? it : proto;
        if (n + (n ? 1 : 0) + keep + 1 > cap) break;
        if (n) out[n++] = '&';
        memcpy(out + n, from, keep);
        n += keep;
        out[n] = 0;
    }
}

int kelp_field_hostinfo_mail(kelp_field_hostinfo *h, const char *var, bool is_string, const char *sval, double dval)
{
    if (!strcmp(var, "HOST_INFO_REQUEST")) {
        h->redetect = h->post_due = true;
        h->requests++;
        return 1;
    }
    if (!strcmp(var, "PMB_UDP_LISTEN")) {
        double p = dval;
        if (is_string && (!sval || kelp_util_parse_double(sval, strlen(sval), &p) < 0)) return KELP_ERR_PARSE;
        if (!(p >= 1 && p <= 65535)) return KELP_ERR_RANGE;
        h->port_udp = p; /* in PHI_HOST_INFO from the next post (24.8 waits too) */
        return 1;
    }
    if (!strcmp(var, "PSHARE_INPUT_SUMMARY")) {
        if (!is_string || !sval) return KELP_ERR_PARSE;
        iroutes(sval, h->iroutes, sizeof h->iroutes); /* posted with the next post, as 24.8 */
        return 1;
    }
    return 0;
}

int kelp_field_hostinfo_iterate(kelp_field_hostinfo *h, const kelp_field_sink *out)
{
    /* 24.8 (HostInfo::Iterate): at the first iteration, after HOST_INFO_REQUEST, and every
     * tenth iteration */
    h->iterations++;
    if (!h->post_due && h->iterations % 10 != 0) return 0;
    h->post_due = false;
    const char *best = h->cfg.default_ip;
    /* PREFER_INTERFACE: an interface name (any case), or 24.8's "wifi" for the wireless one */
    bool wifi = kelp_util_strieq(h->cfg.prefer_if, "wifi");
    for (unsigned i = 0; i < h->naddr && best == h->cfg.default_ip; i++)
        if (h->cfg.prefer_if[0] &&
            (kelp_util_strieq(h->addr[i].ifname, h->cfg.prefer_if) || (wifi && !strcmp(h->addr[i].source, "LINUX_WIFI"))))
            best = h->addr[i].ip;
    if (best == h->cfg.default_ip && h->naddr) best = h->addr[0].ip;
    if (h->cfg.force_ip[0]) best = h->cfg.force_ip;
    copy(h->best, sizeof h->best, best);
    char *all = h->ws_all, *verbose = h->ws_verbose;
    const size_t all_cap = sizeof h->ws_all, verbose_cap = sizeof h->ws_verbose;
    all[0] = verbose[0] = 0;
    size_t na = 0, nv = 0;
    if (h->cfg.force_ip[0]) { /* 24.8: the forced address alone */
        kelp_util_snprintf(all, all_cap, "%s", h->cfg.force_ip);
        kelp_util_snprintf(verbose, verbose_cap, "USER_HARD_CONFIGURED=%s", h->cfg.force_ip);
    }
    for (unsigned i = 0; i < h->naddr && !h->cfg.force_ip[0]; i++) {
        bool seen = false;
        for (unsigned k = 0; k < i; k++) seen = seen || !strcmp(h->addr[k].ip, h->addr[i].ip);
        if (!seen) na += (size_t)kelp_util_snprintf(all + na, all_cap - na, "%s%s", na ? "," : "", h->addr[i].ip);
        nv += (size_t)kelp_util_snprintf(verbose + nv, verbose_cap - nv, "%s%s=%s", nv ? "," : "", h->addr[i].source,
                               h->addr[i].ip);
    }
    out->publish(out->ctx, "PHI_HOST_IP", true, h->best, 0);
    out->publish(out->ctx, "PHI_HOST_IP_ALL", true, all, 0); /* "" when nothing was found (A17) */
    out->publish(out->ctx, "PHI_HOST_IP_VERBOSE", true, verbose, 0);
    char port[24]; /* the ports are posted as strings, as 24.8's pHostInfo posts them */
    if (h->cfg.port_db > 0) {
        kelp_util_snprintf(port, sizeof port, "%.0f", h->cfg.port_db);
        out->publish(out->ctx, "PHI_HOST_PORT_DB", true, port, 0);
    }
    if (h->port_udp > 0) { /* the seed's pMOOSBridge port (PMB_UDP_LISTEN) */
        kelp_util_snprintf(port, sizeof port, "%.0f", h->port_udp);
        out->publish(out->ctx, "PHI_HOST_PORT_UDP", true, port, 0);
    }
    /* 24.8's host record (HostRecord::getSpec), "localhost" anywhere in it read as our address */
    kelp_field_broker_host *rec = &h->ws_rec;
    memset(rec, 0, sizeof *rec);
    copy(rec->community, sizeof rec->community, h->cfg.community);
    copy(rec->host, sizeof rec->host, h->best);
    copy(rec->alts, sizeof rec->alts, all);
    if (h->cfg.port_db > 0) rec->port_db = (unsigned)h->cfg.port_db, rec->have_port_db = true;
    size_t wn = 0;
    if (field_put_fixed(rec->warp_s, sizeof rec->warp_s, &wn, h->cfg.warp, 1, true) < 0) rec->warp_s[0] = 0;
    copy(rec->iroutes, sizeof rec->iroutes, h->iroutes);
    const char *colon = strchr(h->iroutes, ':');
    unsigned p;
    if (h->port_udp > 0) rec->port_udp = (unsigned)h->port_udp, rec->have_port_udp = true;
    else if (colon && broker_port(colon + 1, strlen(colon + 1), &p) == 0) rec->port_udp = p, rec->have_port_udp = true;
    char *spec = h->ws_spec, *info = h->ws_info;
    if (kelp_field_broker_host_spec(rec, NULL, NULL, spec, sizeof h->ws_spec) < 0) return 0;
    size_t m = 0;
    info[0] = 0;
    for (const char *q = spec; *q;) {
        if (strncmp(q, "localhost", 9) == 0 && h->best[0]) {
            field_putf(info, sizeof h->ws_info, &m, "%s", h->best);
            q += 9;
        } else
            field_putf(info, sizeof h->ws_info, &m, "%c", *q++);
    }
    out->publish(out->ctx, "PHI_HOST_INFO", true, info, 0);
    h->posts++;
    return 1;
}

int kelp_field_hostinfo_report(const kelp_field_hostinfo *h, char *buf, size_t cap)
{
    /* 24.8's report (HostInfo::buildReport) */
    size_t n = 0;
    bool full = false;
    if (!buf || !cap) return KELP_ERR_NOSPACE;
    buf[0] = 0;
    char port[24] = "";
    if (h->cfg.port_db > 0) kelp_util_snprintf(port, sizeof port, "%.0f", h->cfg.port_db);
    broker_put(buf, cap, &n, &full, "\n  PHI_HOST_IP:          %s%s\n", h->best,
               h->best[0] && strcmp(h->best, h->cfg.default_ip) != 0 ? ""
               : h->cfg.force_ip[0]                                 ? "DEFAULT HOSTIP FORCED"
                                                                    : "DEFAULT HOSTIP USED");
    broker_block(buf, cap, &n, &full, "  PHI_HOST_IP_ALL:      ", h->ws_all, 42, ',');
    broker_put(buf, cap, &n, &full, "\n");
    broker_block(buf, cap, &n, &full, "  PHI_HOST_IP_VERBOSE:  ", h->ws_verbose, 42, ',');
    broker_put(buf, cap, &n, &full, "\n  PHI_HOST_PORT:        %s\n  PHI_PSHARES_IROUTES:  %s\n  HOSTNAME util(Linux): \n", port,
               h->iroutes);
    broker_block(buf, cap, &n, &full, "  PHI_HOST_INFO:        ", h->ws_info, 42, ',');
    return full ? KELP_ERR_NOSPACE : KELP_OK;
}
