/* kelp commander: send (publications for pAcommsHandler), save files, ack/expiry notes
 * (see include/kelp/commander.h). */
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/commander.h>
#include <kelp/kv.h>
#include <kelp/util.h>

/* the value of "x(lon)N:" or "y(lat)N:" in m, in metres */
static bool find_xy(const kelp_commander_msg *m, char axis, const char *pair, size_t plen, double *metres)
{
    for (unsigned r = 0; r < m->n_rows; r++) {
        const char *v = m->val[r];
        if (v[0] == axis && strncmp(v + 1, axis == 'x' ? "(lon)" : "(lat)", 5) == 0 && strncmp(v + 6, pair, plen) == 0 &&
            v[6 + plen] == ':')
            return kelp_util_parse_finite(v + 7 + plen, strlen(v + 7 + plen), metres) == KELP_OK;
    }
    return false;
}

static bool is_special(const char *v)
{
    return strcmp(v, "_time") == 0 || (v[0] == 'x' && strncmp(v, "x(lon)", 6) == 0) ||
           (v[0] == 'y' && strncmp(v, "y(lat)", 6) == 0);
}

/* the value to send for a row, specials replaced */
static int resolve(const kelp_commander *c, const kelp_commander_msg *m, const char *v, kelp_time now, char *out, size_t cap,
                   kelp_diag *d)
{
    if (strcmp(v, "_time") == 0) {
        (void)kelp_util_snprintf(out, cap, "%.0f", floor(now));
        return KELP_OK;
    }
    if ((v[0] == 'x' && strncmp(v, "x(lon)", 6) == 0) || (v[0] == 'y' && strncmp(v, "y(lat)", 6) == 0)) {
        const char *colon = strchr(v, ':');
        double x, y, lat, lon;
        if (!colon) goto bad;
        size_t plen = (size_t)(colon - v) - 6;
        if (!find_xy(m, 'x', v + 6, plen, &x) || !find_xy(m, 'y', v + 6, plen, &y)) goto bad;
        if (!c->geo || !c->geo->have_origin) {
            return kelp_fail(d, KELP_ERR_PARSE, "x/y special without LatOrigin/LongOrigin");
        }
        kelp_dccl_geo_local2latlon(c->geo, x, y, &lat, &lon);
        (void)kelp_util_fmt_fixed(out, cap, v[0] == 'x' ? lon : lat, 7, true);
        return KELP_OK;
    bad:
        return kelp_fail(d, KELP_ERR_PARSE, "an x(lon)N:/y(lat)N: special without its pair");
    }
    (void)kelp_util_snprintf(out, cap, "%s", v);
    return KELP_OK;
}

static int pub_of(kelp_commander_pub *out, size_t cap, size_t *n, const char *var)
{
    for (size_t i = 0; i < *n; i++)
        if (strcmp(out[i].var, var) == 0) return (int)i;
    if (*n >= cap) return KELP_ERR_NOSPACE;
    (void)kelp_util_snprintf(out[*n].var, sizeof out[*n].var, "%s", var);
    out[*n].val[0] = 0;
    return (int)(*n)++;
}

static int append(kelp_commander_pub *p, const char *key, const char *val)
{
    size_t used = strlen(p->val);
    bool wrap = strchr(val, ',') != NULL;
    int k = kelp_util_snprintf(p->val + used, sizeof p->val - used, "%s%s=%s%s%s", used ? "," : "", key, wrap ? "{" : "",
                          val, wrap ? "}" : "");
    return (k < 0 || (size_t)k >= sizeof p->val - used) ? KELP_ERR_NOSPACE : KELP_OK;
}

int kelp_commander_send(const kelp_commander *c, unsigned msg, kelp_time now, kelp_commander_pub *out, size_t cap, size_t *n,
                   kelp_diag *d)
{
    *n = 0;
    if (msg >= c->n_open) return kelp_fail(d, KELP_ERR_ARG, "no such message");
    const kelp_commander_msg *m = &c->open[msg];
    const kelp_dccl_msgdef *def = m->def;
    const char *trig = def->trigger == KELP_DCCL_TRIG_PUBLISH && def->trigger_var && def->trigger_var[0]
                           ? def->trigger_var : NULL;
    /* the other source variables first, in the order their first field comes; the trigger last */
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1 && trig && pub_of(out, cap, n, trig) < 0) return KELP_ERR_NOSPACE;
        for (unsigned r = 0; r < m->n_rows; r++) {
            const kelp_dccl_field *f = kelp_commander_row_field(m, r);
            const char *var = f->src_var ? f->src_var : def->trigger_var;
            /* a special (_time, x(lon)N:, y(lat)N:) becomes a number: a UNIX time or a
             * latitude/longitude with 7 decimals fits in num; any other value is sent as it is */
            char num[64] = "";
            const char *v = m->val[r];
            if (f->type == KELP_DCCL_T_STATIC || !m->val[r][0] || !var) continue;
            if ((pass == 0) == (trig && strcmp(var, trig) == 0)) continue;
            if (is_special(m->val[r])) {
                int rc = resolve(c, m, m->val[r], now, num, sizeof num, d);
                if (rc < 0) return rc;
                v = num;
            }
            int i = pub_of(out, cap, n, var);
            if (i < 0 || append(&out[i], f->src_key ? f->src_key : f->name, v) < 0) return KELP_ERR_NOSPACE;
        }
    }
    if (trig && def->trigger_mandatory && def->trigger_mandatory[0]) {
        kelp_commander_pub *p = &out[*n - 1];
        if (!strstr(p->val, def->trigger_mandatory)) {
            /* "<mandatory>,<val>" built in place */
            size_t ml = strlen(def->trigger_mandatory), vl = strlen(p->val), sep = vl ? 1u : 0u;
            if (ml + sep + vl >= sizeof p->val) return KELP_ERR_NOSPACE;
            memmove(p->val + ml + sep, p->val, vl + 1);
            memcpy(p->val, def->trigger_mandatory, ml);
            if (sep) p->val[ml] = ',';
        }
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ save files */
static bool put(char *out, size_t cap, size_t *at, const char *fmt, ...) KELP_PRINTF(4, 5);
static bool put(char *out, size_t cap, size_t *at, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = *at < cap ? kelp_util_vsnprintf(out + *at, cap - *at, fmt, ap) : -1;
    va_end(ap);
    if (k < 0 || (size_t)k >= cap - *at) return false;
    *at += (size_t)k;
    return true;
}

int kelp_commander_save(const kelp_commander *c, char *out, size_t cap, size_t *len)
{
    size_t at = 0;
    bool ok = put(out, cap, &at, "# kelp-commander saved messages\n");
    for (unsigned i = 0; ok && i < c->n_open; i++) {
        const kelp_commander_msg *m = &c->open[i];
        ok = put(out, cap, &at, "message = %s\n", m->def->name);
        for (unsigned r = 0; ok && r < m->n_rows; r++) {
            const kelp_dccl_field *f = kelp_commander_row_field(m, r);
            if (f->type != KELP_DCCL_T_STATIC && m->val[r][0]) ok = put(out, cap, &at, "%s = %s\n", f->name, m->val[r]);
        }
    }
    if (!ok) return KELP_ERR_NOSPACE;
    if (len) *len = at;
    return KELP_OK;
}

/* the failure rc of input line `line`: the line goes into d (kelp_diag_where) */
static int where(kelp_diag *d, int line, int rc)
{
    (void)kelp_diag_where(d, line, 0);
    return rc;
}

int kelp_commander_load(kelp_commander *c, const char *text, kelp_diag *d)
{
    int msg = -1, line = 0;
    const char *p = text;
    while (*p) {
        const char *e = strchr(p, '\n');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        char *buf = c->line;
        const char *k, *v;
        size_t kl, vl, pos = 0, s = 0;
        line++;
        while (s < n && (p[s] == ' ' || p[s] == '\t' || p[s] == '\r')) s++;
        if (s == n || p[s] == '#') goto next;
        if (n >= sizeof c->line) {
            return where(d, line, kelp_fail(d, KELP_ERR_RANGE, "line too long"));
        }
        memcpy(buf, p, n);
        buf[n] = 0;
        if (kelp_kv_next(buf, '\n', &pos, &k, &kl, &v, &vl) != 1) {
            return where(d, line, kelp_fail(d, KELP_ERR_PARSE, "not \"key = value\""));
        }
        ((char *)k)[kl] = 0; /* both point into buf */
        ((char *)v)[vl] = 0;
        if (strcmp(k, "message") == 0) {
            msg = kelp_commander_open(c, v);
            if (msg < 0) {
                (void)kelp_fail(d, msg, msg == KELP_ERR_NOSPACE ? "too many open messages" : "no such message in the loaded XML");
                return where(d, line, msg);
            }
        } else {
            int row = msg < 0 ? -1 : kelp_commander_row(&c->open[msg], k);
            if (msg < 0) {
                return where(d, line, kelp_fail(d, KELP_ERR_PARSE, "a field before any \"message = NAME\" line"));
            }
            if (row < 0) {
                return where(d, line, kelp_fail(d, KELP_ERR_NOTFOUND, "no such field in this message"));
            }
            int rc = kelp_commander_set(c, (unsigned)msg, (unsigned)row, v, d);
            if (rc < 0) return where(d, line, rc);
        }
    next:
        p += n;
        if (*p) p++;
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ acks and expiries */
int kelp_commander_ack_note(const kelp_commander *c, bool ack, const char *text, kelp_time now, char *out, size_t cap)
{
    static const char *const MON[12] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                        "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};
    const char *o = strstr(text, "orig_msg {");
    const char *z = strrchr(text, '}');
    kelp_acomms_msg msg;
    if (!o || !z || z < o + 10) return KELP_ERR_PARSE;
    o += 10;
    if (kelp_acomms_parse_data(o, (size_t)(z - o), &msg, NULL) < 0) return KELP_ERR_PARSE;
    unsigned id;
    const kelp_dccl_msgdef *def = NULL;
    if (kelp_dccl_peek_id(msg.data, msg.len, &id) == KELP_OK && c->set) def = kelp_dccl_set_find_id(c->set, id);
    char name[KELP_DCCL_MAX_NAME];
    if (def)
        (void)kelp_util_snprintf(name, sizeof name, "%s", def->name);
    else
        (void)kelp_util_snprintf(name, sizeof name, "%s", msg.len && msg.data[0] == KELP_DCCL_CCL_ID ? "(unknown DCCL)" : "CCL");
    int64_t secs = (int64_t)floor(now), days = kelp_util_floor_div(secs, 86400), year;
    int64_t tod = secs - days * 86400;
    unsigned mon, day;
    kelp_util_civil_from_days(days, &year, &mon, &day);
    int k = kelp_util_snprintf(out, cap, "Message %s from queue: %s\n for destination: %d\n at time: %04lld-%s-%02u %02d:%02d:%02d",
                          ack ? "acknowledged" : "expired", name, msg.dest, (long long)year, MON[(mon - 1) % 12], day,
                          (int)(tod / 3600), (int)(tod / 60 % 60), (int)(tod % 60));
    return (k < 0 || (size_t)k >= cap) ? KELP_ERR_NOSPACE : KELP_OK;
}
