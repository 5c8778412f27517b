/* kelp helm: the IvPBehavior superclass: general parameters (seed 4.2), utilities (4.5.1). */
#include <math.h>
#include <string.h>
#include <kelp/kv.h>
#include "helm_int.h"

const char *kelp_helm_bhv_state_name(kelp_bhv_state s)
{
    switch (s) {
    case KELP_BHV_IDLE: return "idle";
    case KELP_BHV_RUNNING: return "running";
    case KELP_BHV_ACTIVE: return "active";
    case KELP_BHV_COMPLETED: return "completed";
    case KELP_BHV_NONE: break;
    }
    return "";
}

void bhv_defaults(kelp_bhv *b)
{
    b->pwt = 100.0;
    b->duration = -1;
    b->duration_idle_decay = true;
    b->state_ok = true;
    b->state = KELP_BHV_NONE;
    b->dur_reset_stamp = -1;
}

int kelp_helm_bhv_fail(kelp_bhv *b, const char *why)
{
    if (!b->fail)
        b->fail = why;
    return KELP_ERR_PARSE;
}

bool bhv_parse_true_false(const char *v, bool *out)
{
    if (hx_ieq(v, "true")) {
        *out = true;
        return true;
    }
    if (hx_ieq(v, "false")) {
        *out = false;
        return true;
    }
    return false;
}

void bhv_cond_var(const char *var, size_t len, void *user)
{
    kelp_bhv *b = user;
    if (b->helm)
        (void)helm_need_var(b->helm, var, len);
}

static int add_flag(kelp_bhv *b, kelp_bhv_flag_kind kind, const char *v)
{
    if (b->nflag >= KELP_HELM_MAX_FLAGS)
        return kelp_helm_bhv_fail(b, "too many flags");
    kelp_bhv_flag *f = &b->flag[b->nflag];
    if (!hx_pair(v, &f->p))
        return kelp_helm_bhv_fail(b, "a flag is VAR=value");
    f->kind = kind;
    b->nflag++;
    return 0;
}

static int copy_name(kelp_bhv *b, char *dst, const char *v, bool need)
{
    size_t n = strlen(v);
    if (!hx_varname(v, n))
        return kelp_helm_bhv_fail(b, "bad variable name");
    memcpy(dst, v, n + 1);
    if (need && b->helm)
        (void)helm_need_var(b->helm, v, n);
    return 0;
}

/* A condition line: kept apart so that the condition parser's stack does not add to the frame
 * of the other general parameters. */
KELP_NOINLINE static int add_condition(kelp_bhv *b, const char *v, size_t vn)
{
    if (b->ncond >= KELP_HELM_MAX_CONDS)
        return kelp_helm_bhv_fail(b, "too many conditions");
    if (vn >= KELP_HELM_MAX_COND_LEN)
        return kelp_helm_bhv_fail(b, "condition too long");
    if (kelp_helm_cond_check(v, bhv_cond_var, b) != 0)
        return kelp_helm_bhv_fail(b, "malformed condition");
    memcpy(b->cond[b->ncond++], v, vn + 1);
    return 0;
}

KELP_NOINLINE static int general_param(kelp_bhv *b, const char *p, const char *v);

/* 0 accepted, KELP_ERR_NOTFOUND not a general parameter, KELP_ERR_PARSE malformed. */
int bhv_general_param(kelp_bhv *b, const char *p, const char *v)
{
    if (!strcmp(p, "condition"))
        return add_condition(b, v, strlen(v));
    if (!strcmp(p, "lead_condition") && b->ops == &kelp_bhv_waypoint_ops)
        return helm_wpt_lead_condition(b, v) < 0 ? kelp_helm_bhv_fail(b, "bad value") : 0;
    return general_param(b, p, v);
}

static int general_param(kelp_bhv *b, const char *p, const char *v)
{
    size_t vn = strlen(v);
    double d;
    if (!strcmp(p, "name") || !strcmp(p, "descriptor")) {
        if (vn == 0 || !hx_copy(b->name, sizeof b->name, v, vn))
            return kelp_helm_bhv_fail(b, "bad name");
        return 0;
    }
    if (!strcmp(p, "us")) {
        if (vn == 0 || !hx_copy(b->us, sizeof b->us, v, vn))
            return kelp_helm_bhv_fail(b, "bad vehicle name");
        return 0;
    }
    if (!strcmp(p, "comms_policy")) {
        /* 24.8's behaviour comms policy: open, lean or dire (it restricts offboard postings,
         * which kelp's behaviours make none of); anything else is refused as 24.8 refuses it */
        if (!hx_ieq(v, "open") && !hx_ieq(v, "lean") && !hx_ieq(v, "dire"))
            return kelp_helm_bhv_fail(b, "comms_policy is open, lean or dire");
        return 0;
    }
    if (!strcmp(p, "pwt") || !strcmp(p, "priority") || !strcmp(p, "priwt")) {
        if (!hx_number(v, vn, &d) || d < 0)
            return kelp_helm_bhv_fail(b, "priority must be a number >= 0");
        b->pwt = d;
        return 0;
    }
    /* flags, each with MOOS-IvP's underscored alias (run_flag, spawnx_flag, ...) */
    static const struct { const char *name; kelp_bhv_flag_kind kind; } flags[] = {
        {"runflag", KELP_FLAG_RUN},       {"idleflag", KELP_FLAG_IDLE},     {"activeflag", KELP_FLAG_ACTIVE},
        {"inactiveflag", KELP_FLAG_INACTIVE}, {"endflag", KELP_FLAG_END}, {"runxflag", KELP_FLAG_RUNX},
        {"spawnxflag", KELP_FLAG_SPAWNX}, {"configflag", KELP_FLAG_CONFIG}, {"spawnflag", KELP_FLAG_SPAWN}};
    for (size_t i = 0; i < sizeof flags / sizeof flags[0]; i++) {
        size_t fl = strlen(flags[i].name) - 4; /* the part before "flag" */
        if (!strcmp(p, flags[i].name) ||
            (!strncmp(p, flags[i].name, fl) && p[fl] == '_' && !strcmp(p + fl + 1, "flag")))
            return add_flag(b, flags[i].kind, v);
    }
    if (!strcmp(p, "templating")) {
        if (!hx_ieq(v, "disallowed") && !hx_ieq(v, "clone") && !hx_ieq(v, "spawn"))
            return kelp_helm_bhv_fail(b, "templating is disallowed, clone or spawn");
        (void)hx_copy(b->templating, sizeof b->templating, v, vn);
        return 0;
    }
    if (!strcmp(p, "max_spawnings")) {
        if (!hx_number(v, vn, &d) || d < 0 || d != floor(d))
            return kelp_helm_bhv_fail(b, "max_spawnings is a whole number >= 0");
        b->max_spawnings = (unsigned long)d;
        return 0;
    }
    if (!strcmp(p, "build_info") || !strcmp(p, "precision")) {
        (void)hx_copy(b->build_info, sizeof b->build_info, v, vn < sizeof b->build_info ? vn : sizeof b->build_info - 1);
        return 0;
    }
    if (!strcmp(p, "updates"))
        return copy_name(b, b->updates, v, true);
    if (!strcmp(p, "duration")) {
        if (hx_ieq(v, "no-time-limit") || !strcmp(v, "-1")) {
            b->duration = -1;
            return 0;
        }
        if (!hx_number(v, vn, &d) || d <= 0)
            return kelp_helm_bhv_fail(b, "duration must be a positive number");
        b->duration = d;
        return 0;
    }
    if (!strcmp(p, "duration_status"))
        return copy_name(b, b->duration_status, v, false);
    if (!strcmp(p, "duration_reset")) {
        kelp_helm_pair *pr = &b->helm->ws_pair; /* workspace (kelp_helm_bhv_set_param checked helm) */
        if (!hx_pair(v, pr))
            return kelp_helm_bhv_fail(b, "duration_reset is VAR=value");
        const char *eq = strchr(v, '=');
        const char *rv = eq + 1;
        size_t rn = strlen(rv);
        hx_trim(&rv, &rn);
        if (!hx_copy(b->duration_reset_val, sizeof b->duration_reset_val, rv, rn))
            return kelp_helm_bhv_fail(b, "duration_reset value too long");
        return copy_name(b, b->duration_reset_var, pr->var, true);
    }
    if (!strcmp(p, "duration_idle_decay")) {
        if (!bhv_parse_true_false(v, &b->duration_idle_decay))
            return kelp_helm_bhv_fail(b, "duration_idle_decay is true or false");
        return 0;
    }
    if (!strcmp(p, "perpetual")) {
        if (!bhv_parse_true_false(v, &b->perpetual))
            return kelp_helm_bhv_fail(b, "perpetual is true or false");
        return 0;
    }
    if (!strcmp(p, "post_mapping")) {
        const char *c = strchr(v, ',');
        if (!c)
            return kelp_helm_bhv_fail(b, "post_mapping is OLD, NEW");
        const char *l = v, *r = c + 1;
        size_t ln = (size_t)(c - v), rn = strlen(r);
        hx_trim(&l, &ln);
        hx_trim(&r, &rn);
        if (!hx_varname(l, ln) || !hx_varname(r, rn))
            return kelp_helm_bhv_fail(b, "post_mapping is OLD, NEW");
        unsigned i;
        for (i = 0; i < b->nmap; i++)
            if (kelp_util_strieq_n(l, ln, b->map_from[i]) && strlen(b->map_from[i]) == ln)
                break;
        if (i == b->nmap) {
            if (b->nmap >= KELP_HELM_MAX_MAPPINGS)
                return kelp_helm_bhv_fail(b, "too many post_mapping lines");
            b->nmap++;
        }
        (void)hx_copy(b->map_from[i], KELP_MAX_NAME, l, ln);
        (void)hx_copy(b->map_to[i], KELP_MAX_NAME, r, rn);
        return 0;
    }
    if (!strcmp(p, "nostarve") || !strcmp(p, "no_starve")) {
        const char *last = strrchr(v, ',');
        if (!last)
            return kelp_helm_bhv_fail(b, "nostarve is VAR, ..., VAR, seconds");
        if (!hx_number(last + 1, strlen(last + 1), &d) || d <= 0)
            return kelp_helm_bhv_fail(b, "nostarve time must be a positive number");
        /* two passes over the list: check every name, then copy (no copy of the table on the stack) */
        unsigned n = 0;
        for (int pass = 0; pass < 2; pass++) {
            n = 0;
            for (const char *s = v; s < last;) {
                const char *c = memchr(s, ',', (size_t)(last - s) + 1);
                const char *w = s;
                size_t wn = (size_t)(c - s);
                hx_trim(&w, &wn);
                if (!hx_varname(w, wn) || n >= KELP_HELM_MAX_INFOVARS)
                    return kelp_helm_bhv_fail(b, "nostarve is VAR, ..., VAR, seconds");
                if (pass)
                    (void)hx_copy(b->starve[n], KELP_MAX_NAME, w, wn);
                n++;
                s = c + 1;
            }
            if (n == 0)
                return kelp_helm_bhv_fail(b, "nostarve names no variable");
        }
        b->nstarve = n;
        b->starve_time = d;
        for (unsigned i = 0; i < n; i++)
            if (b->helm)
                (void)helm_need_var(b->helm, b->starve[i], strlen(b->starve[i]));
        return 0;
    }
    return KELP_ERR_NOTFOUND;
}

int kelp_helm_bhv_set_param(kelp_bhv *b, const char *param, const char *value)
{
    if (!b || !b->helm || !param || !value)
        return KELP_ERR_ARG;
    const char *p = param, *v = value;
    size_t pn = strlen(p), vn = strlen(v);
    hx_trim(&p, &pn);
    hx_trim(&v, &vn);
    if (pn && p[0] == '_') {
        p++;
        pn--;
    }
    char *lp = b->helm->ws_pname, *val = b->helm->ws_param;
    if (pn == 0 || pn >= sizeof b->helm->ws_pname)
        return kelp_helm_bhv_fail(b, "bad parameter name");
    for (size_t i = 0; i < pn; i++)
        lp[i] = hx_lower(p[i]);
    lp[pn] = '\0';
    if (!hx_copy(val, sizeof b->helm->ws_param, v, vn))
        return kelp_helm_bhv_fail(b, "value too long");
    int rc = bhv_general_param(b, lp, val);
    if (rc != KELP_ERR_NOTFOUND)
        return rc;
    if (!b->ops->set_param)
        return kelp_helm_bhv_fail(b, "unknown parameter");
    rc = b->ops->set_param(b, lp, val);
    if (rc == KELP_ERR_NOTFOUND)
        return kelp_helm_bhv_fail(b, "unknown parameter");
    if (rc < 0)
        return kelp_helm_bhv_fail(b, "bad value");
    return 0;
}

/* ---------------------------------------------------------------- utilities */

void kelp_helm_bhv_set_complete(kelp_bhv *b)
{
    helm_post_flags(b, KELP_FLAG_END);
    helm_post_flags(b, KELP_FLAG_INACTIVE);
    if (b->perpetual || b->completed)
        return;
    b->completed = true;
    if (b->ops->on_complete)
        b->ops->on_complete(b);
}

void bhv_use_subdomain(kelp_bhv *b, const char *vars)
{
    kelp_ivp_domain d;
    if (kelp_ivp_domain_sub(&b->helm->cfg.domain, vars, &d) == 0)
        b->dom = d;
    else
        kelp_ivp_domain_init(&b->dom);
}

int kelp_helm_bhv_add_info_vars(kelp_bhv *b, const char *names)
{
    const char *s = names;
    int rc = 0;
    while (*s) {
        const char *c = strchr(s, ',');
        size_t n = c ? (size_t)(c - s) : strlen(s);
        const char *w = s;
        hx_trim(&w, &n);
        if (n) {
            unsigned i;
            for (i = 0; i < b->ninfovars; i++)
                if (strlen(b->infovars[i]) == n && !memcmp(b->infovars[i], w, n))
                    break;
            if (i == b->ninfovars) {
                if (!hx_varname(w, n) || b->ninfovars >= KELP_HELM_MAX_INFOVARS)
                    rc = KELP_ERR_NOSPACE;
                else
                    (void)hx_copy(b->infovars[b->ninfovars++], KELP_MAX_NAME, w, n);
            }
            if (b->helm)
                (void)helm_need_var(b->helm, w, n);
        }
        if (!c)
            break;
        s = c + 1;
    }
    return rc;
}

bool kelp_helm_bhv_buf_double(const kelp_bhv *b, const char *var, double *out)
{
    return kelp_helm_ib_double(&b->helm->ib, var, out);
}

bool kelp_helm_bhv_buf_string(const kelp_bhv *b, const char *var, char *buf, size_t cap)
{
    return kelp_helm_ib_string(&b->helm->ib, var, buf, cap);
}

double kelp_helm_bhv_buf_time(const kelp_bhv *b, const char *var)
{
    return kelp_helm_ib_time(&b->helm->ib, var);
}

double kelp_helm_bhv_buf_now(const kelp_bhv *b)
{
    return b->helm->ib.curr_time;
}

unsigned kelp_helm_bhv_buf_ndeltas(const kelp_bhv *b, const char *var)
{
    return kelp_helm_ib_ndeltas(&b->helm->ib, var);
}

bool kelp_helm_bhv_buf_delta(const kelp_bhv *b, const char *var, unsigned k, double *dval, const char **sval)
{
    return kelp_helm_ib_delta(&b->helm->ib, var, k, dval, sval);
}

static const char *mapped(const kelp_bhv *b, const char *var)
{
    for (unsigned i = 0; i < b->nmap; i++)
        if (!strcmp(b->map_from[i], var))
            return b->map_to[i];
    return var;
}

const char *helm_bhv_var(const kelp_bhv *b, const char *var)
{
    return mapped(b, var);
}

static void post(kelp_bhv *b, const char *var, bool is_str, const char *s, double d, const char *key)
{
    if (!b->helm || !var)
        return;
    var = mapped(b, var);
    if (hx_ieq(var, "silent"))
        return;
    helm_queue_post(b->helm, b, var, is_str, s, d, key);
}

void kelp_helm_bhv_post_string(kelp_bhv *b, const char *var, const char *val, const char *key)
{
    post(b, var, true, val ? val : "", 0, key);
}

void kelp_helm_bhv_post_double(kelp_bhv *b, const char *var, double val, const char *key)
{
    post(b, var, false, NULL, val, key);
}

void kelp_helm_bhv_post_bool(kelp_bhv *b, const char *var, bool val, const char *key)
{
    post(b, var, true, val ? "true" : "false", 0, key);
}

void kelp_helm_bhv_post_int(kelp_bhv *b, const char *var, double val, const char *key)
{
    post(b, var, false, NULL, floor(val + 0.5), key);
}

static void post_msg_key(kelp_bhv *b, const char *var, const char *msg, const char *key)
{
    if (!b->helm)
        return;
    char *buf = b->helm->ws_bhv.msg;
    size_t n = strlen(b->name), m = strlen(msg);
    if (n + 2 + m + 1 > sizeof b->helm->ws_bhv.msg)
        m = sizeof b->helm->ws_bhv.msg - n - 3;
    memcpy(buf, b->name, n);
    buf[n] = ':';
    buf[n + 1] = ' ';
    memcpy(buf + n + 2, msg, m);
    buf[n + 2 + m] = '\0';
    post(b, var, true, buf, 0, key);
}

static void post_msg(kelp_bhv *b, const char *var, const char *msg)
{
    post_msg_key(b, var, msg, "repeatable");
}

void kelp_helm_bhv_post_retract(kelp_bhv *b, const char *msg)
{
    if (msg && *msg)
        post_msg_key(b, "BHV_WARNING", msg, "retract");
}

void kelp_helm_bhv_post_warning(kelp_bhv *b, const char *msg)
{
    if (msg && *msg)
        post_msg(b, "BHV_WARNING", msg);
}

void kelp_helm_bhv_post_error(kelp_bhv *b, const char *msg)
{
    post_msg(b, "BHV_ERROR", msg ? msg : "");
    b->state_ok = false;
}

#define HINT_SET(dst, src) ((void)hx_copy((dst), sizeof(dst), (src), strlen(src)))

void bhv_hints_default(kelp_bhv_hints *h)
{
    HINT_SET(h->vertex_color, "dodger_blue");
    HINT_SET(h->edge_color, "white");
    HINT_SET(h->label_color, "white");
    HINT_SET(h->nextpt_color, "yellow");
    HINT_SET(h->nextpt_lcolor, "aqua");
    h->vertex_size = 3;
    h->edge_size = 1;
    h->nextpt_vertex_size = 5;
}

int bhv_set_hints(kelp_bhv_hints *h, const char *v)
{
    size_t pos = 0, kl, vl;
    const char *k, *val;
    int rc;
    while ((rc = kelp_kv_next(v, ',', &pos, &k, &kl, &val, &vl)) == 1) {
        char key[32], value[24];
        if (!hx_copy(key, sizeof key, k, kl) || !hx_copy(value, sizeof value, val, vl) || !vl)
            continue;
        for (char *c = key; *c; c++)
            *c = hx_lower(*c);
        double d;
        bool num = hx_number(value, vl, &d) && d >= 0;
        if (!strcmp(key, "vertex_size") && num)
            h->vertex_size = d;
        else if (!strcmp(key, "edge_size") && num)
            h->edge_size = d;
        else if (!strcmp(key, "nextpt_vertex_size") && num)
            h->nextpt_vertex_size = d;
        else if (!strcmp(key, "vertex_color"))
            HINT_SET(h->vertex_color, value);
        else if (!strcmp(key, "edge_color"))
            HINT_SET(h->edge_color, value);
        else if (!strcmp(key, "label_color"))
            HINT_SET(h->label_color, value);
        else if (!strcmp(key, "nextpt_color"))
            HINT_SET(h->nextpt_color, value);
        else if (!strcmp(key, "nextpt_lcolor"))
            HINT_SET(h->nextpt_lcolor, value);
    }
    return rc < 0 ? KELP_ERR_PARSE : 0;
}

int bhv_set_suffix(char *suffix, size_t cap, const char *v)
{
    const char *t = v[0] == '_' ? v + 1 : v;
    size_t n = strlen(t);
    if (n + 2 > cap || strpbrk(t, " ,="))
        return KELP_ERR_PARSE;
    if (n == 0) {
        suffix[0] = 0;
        return 0;
    }
    suffix[0] = '_';
    memcpy(suffix + 1, t, n + 1);
    return 0;
}
