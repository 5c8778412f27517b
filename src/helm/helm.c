/* kelp helm: the helm engine (HelmIvP + BehaviorSet + HelmEngine of MOOS-IvP, re-written):
 * behaviour set, .bhv loading, the per-iteration call sequence, the duplicate filter and the
 * decision. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

#define AUX_INIT "HELM_VAR_INIT"

void kelp_helm_config_default(kelp_helm_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    kelp_ivp_domain_init(&cfg->domain);
    cfg->start_engaged = false; /* HelmIvP: parked until an override lifts, or start_engaged */
    cfg->allow_park = true;
}

int kelp_helm_config_add_domain(kelp_helm_config *cfg, const char *spec, kelp_diag *d)
{
    const char *tok[6];
    size_t len[6];
    int nt = 0;
    for (const char *s = spec;; s++) {
        const char *c = strchr(s, ':');
        const char *e = c ? c : s + strlen(s);
        while (s < e && (*s == ' ' || *s == '\t')) s++;
        const char *t = e;
        while (t > s && (t[-1] == ' ' || t[-1] == '\t')) t--;
        if (nt == 6) break;
        tok[nt] = s, len[nt++] = (size_t)(t - s);
        if (!c) break;
        s = c;
    }
    double lo, hi;
    long pts;
    char name[KELP_MAX_NAME];
    if (nt < 4 || nt > 5 || len[0] == 0 || len[0] >= sizeof name)
        return kelp_fail(d, KELP_ERR_PARSE, "expected name:low:high:points[:optional]");
    if (kelp_util_parse_double(tok[1], len[1], &lo) || kelp_util_parse_double(tok[2], len[2], &hi) ||
        kelp_util_parse_long(tok[3], len[3], &pts) || pts < 1 || pts > 100000)
        return kelp_fail(d, KELP_ERR_PARSE, "bad low, high or points (1..100000)");
    if (nt == 5 && (len[4] != 8 || strncmp(tok[4], "optional", 8) != 0))
        return kelp_fail(d, KELP_ERR_PARSE, "the fifth field may only be 'optional'");
    memcpy(name, tok[0], len[0]);
    name[len[0]] = 0;
    unsigned v = cfg->domain.dim;
    int rc = kelp_ivp_domain_add(&cfg->domain, name, lo, hi, (uint32_t)pts);
    if (rc < 0)
        return kelp_diag_set(d, rc, NULL); /* the text: kelp_err_str(rc) */
    cfg->optional[v] = nt == 5;
    return KELP_OK;
}

int helm_fail(kelp_helm *h, int line, int code, ...)
{
    if (h->diag.code != KELP_OK)
        return code;
    (void)kelp_diag_set(&h->diag, code, NULL);
    (void)kelp_diag_where(&h->diag, line, 0);
#ifndef KELP_NO_ERRMSG
    va_list ap;
    size_t n = 0;
    va_start(ap, code);
    for (const char *s = va_arg(ap, const char *); s; s = va_arg(ap, const char *))
        for (; *s && n + 1 < sizeof h->diag.msg; s++)
            h->diag.msg[n++] = *s;
    va_end(ap);
    h->diag.msg[n] = '\0';
#endif
    return code;
}

int helm_need_var(kelp_helm *h, const char *name, size_t n)
{
    if (!hx_varname(name, n))
        return KELP_ERR_ARG;
    for (unsigned i = 0; i < h->nneed; i++)
        if (strlen(h->need[i]) == n && !memcmp(h->need[i], name, n))
            return 0;
    if (h->nneed >= KELP_HELM_MAX_VARS)
        return KELP_ERR_NOSPACE;
    (void)hx_copy(h->need[h->nneed++], KELP_MAX_NAME, name, n);
    return 0;
}

const char *kelp_helm_next_new_var(kelp_helm *h)
{
    if (h->nneed_reported >= h->nneed)
        return NULL;
    return h->need[h->nneed_reported++];
}

int kelp_helm_init(kelp_helm *h, const kelp_helm_config *cfg, const kelp_helm_mem *mem)
{
    if (!h || !cfg || !mem)
        return KELP_ERR_ARG;
    memset(h, 0, sizeof *h);
    h->cfg = *cfg;
    if (!h->cfg.types)
        h->cfg.types = kelp_bhv_builtin_types;
    h->mem = *mem;
    kelp_helm_ib_init(&h->ib);
    h->engaged = cfg->start_engaged;
    (void)helm_need_var(h, "MOOS_MANUAL_OVERIDE", 19);
    (void)helm_need_var(h, "MOOS_MANUAL_OVERRIDE", 20);
    (void)helm_need_var(h, "IVPHELM_REJOURNAL", 17); /* a full IVPHELM_SUMMARY next time */
    /* the platform model (TURN_RATE) reads the navigation whatever the behaviours need */
    static const char *const nav[4] = {"NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"};
    for (int i = 0; i < 4; i++)
        (void)helm_need_var(h, nav[i], strlen(nav[i]));
    if (cfg->other_override[0]) (void)helm_need_var(h, cfg->other_override, strlen(cfg->other_override));
    strcpy(h->rep.allstop, "clear");
    h->completed_pending_posted = -1;
    return 0;
}

kelp_bhv *kelp_helm_find(kelp_helm *h, const char *name)
{
    for (unsigned i = 0; i < h->nbhv; i++)
        if (!strcmp(h->bhv[i].name, name))
            return &h->bhv[i];
    return NULL;
}

int kelp_helm_add(kelp_helm *h, const char *type, kelp_bhv **out)
{
    const kelp_bhv_ops *ops = NULL;
    for (const kelp_bhv_ops *const *t = h->cfg.types; *t; t++)
        if (hx_ieq((*t)->type, type)) {
            ops = *t;
            break;
        }
    if (!ops)
        return KELP_ERR_NOTFOUND;
    if (h->nbhv >= KELP_HELM_MAX_BHVS)
        return KELP_ERR_NOSPACE;
    kelp_bhv *b = &h->bhv[h->nbhv];
    memset(b, 0, sizeof *b);
    b->ops = ops;
    b->helm = h;
    (void)hx_copy(b->type, sizeof b->type, ops->type, strlen(ops->type));
    (void)hx_copy(b->name, sizeof b->name, ops->type, strlen(ops->type));
    memcpy(b->us, h->cfg.us, sizeof b->us);
    b->dom = h->cfg.domain;
    b->uid = ++h->next_uid;
    h->bhv_cnt_ever++;
    bhv_defaults(b);
    if (ops->init)
        ops->init(b);
    h->nbhv++;
    if (out)
        *out = b;
    return 0;
}

int kelp_helm_add_init(kelp_helm *h, const char *var, const char *value, bool defer)
{
    if (h->ninit >= KELP_HELM_MAX_INIT)
        return KELP_ERR_NOSPACE;
    kelp_helm_pair *p = &h->init[h->ninit];
    size_t n = strlen(var);
    const char *v = var;
    hx_trim(&v, &n);
    if (!hx_varname(v, n) || !hx_pair_value(value, strlen(value), p))
        return KELP_ERR_PARSE;
    (void)hx_copy(p->var, sizeof p->var, v, n);
    h->init_defer[h->ninit] = defer;
    h->ninit++;
    (void)helm_need_var(h, p->var, strlen(p->var));
    return 0;
}

/* "initialize VAR = value[, VAR2 = value2 ...]": key holds "initialize VAR". */
KELP_NOINLINE static int load_init(kelp_helm *h, const kelp_mission_node *nd)
{
    const char *k = nd->key + 10; /* strlen("initialize") */
    size_t kn = nd->klen - 10;
    bool defer = false;
    if (kn && *k == '_') {
        defer = true;
        k++;
        kn--;
    }
    hx_trim(&k, &kn);
    char var[KELP_MAX_NAME], *val = h->ws_upd.val; /* (the update workspace: idle while loading) */
    if (!hx_varname(k, kn) || !hx_copy(var, sizeof var, k, kn) || !hx_copy(val, sizeof h->ws_upd.val, nd->val, nd->vlen))
        return helm_fail(h, nd->line, KELP_ERR_PARSE, "bad initialize line", HX_END);
    /* split further pairs: a comma followed by a piece holding '=' starts a new pair */
    char *s = val;
    for (;;) {
        char *c = s, *cut = NULL;
        while ((c = strchr(c, ',')) != NULL) {
            char *nc = strchr(c + 1, ','), *eq = strchr(c + 1, '=');
            if (eq && (!nc || eq < nc)) {
                cut = c;
                break;
            }
            c++;
        }
        if (cut)
            *cut = '\0';
        if (kelp_helm_add_init(h, var, s, defer) < 0)
            return helm_fail(h, nd->line, KELP_ERR_PARSE, "bad initialize value for ", var, HX_END);
        if (!cut)
            break;
        kelp_helm_pair *pr = &h->ws_pair; /* (a workspace: idle while loading) */
        if (!hx_pair(cut + 1, pr))
            return helm_fail(h, nd->line, KELP_ERR_PARSE, "bad initialize pair", HX_END);
        char *eq = strchr(cut + 1, '=');
        memcpy(var, pr->var, sizeof var);
        s = eq + 1;
    }
    return 0;
}

int kelp_helm_load_bhv(kelp_helm *h, const kelp_mission *m)
{
    for (size_t i = 0; i < m->nnodes; i++) {
        const kelp_mission_node *nd = &m->nodes[i];
        if (nd->parent >= 0)
            continue;
        if (nd->kind == KELP_MN_PARAM && nd->klen >= 10 && kelp_util_strieq_n(nd->key, 10, "initialize") &&
            (nd->klen == 10 || nd->key[10] == '_' || hx_is_space(nd->key[10]))) {
            int rc = load_init(h, nd);
            if (rc < 0)
                return rc;
            continue;
        }
        if (nd->kind == KELP_MN_BLOCK && nd->klen > 4 && kelp_util_strieq_n(nd->key, 3, "set") && hx_is_space(nd->key[3])) {
            int rc = helm_mode_load(h, m, i);
            if (rc < 0)
                return rc;
            continue;
        }
        if (nd->kind == KELP_MN_BLOCK && kelp_util_strieq_n(nd->key, nd->klen, "Behavior")) {
            char *type = h->ws_key; /* the helm's workspace, not the stack */
            if (!hx_copy(type, sizeof h->ws_key, nd->val, nd->vlen))
                return helm_fail(h, nd->line, KELP_ERR_PARSE, "behaviour type too long", HX_END);
            kelp_bhv *b;
            int rc = kelp_helm_add(h, type, &b);
            if (rc == KELP_ERR_NOTFOUND)
                return helm_fail(h, nd->line, KELP_ERR_PARSE, "unknown behaviour type ", type, HX_END);
            if (rc < 0)
                return helm_fail(h, nd->line, rc, "too many behaviours (KELP_HELM_MAX_BHVS)", HX_END);
            b->line = nd->line;
            for (size_t j = i + 1; j < m->nnodes; j++) {
                const kelp_mission_node *c = &m->nodes[j];
                if (c->parent != (int)i)
                    continue;
                char *key = h->ws_key, *val = h->ws_upd.val; /* (idle while loading; the type is done with) */
                if (c->kind != KELP_MN_PARAM)
                    return helm_fail(h, c->line, KELP_ERR_PARSE, "expected parameter = value", HX_END);
                if (!hx_copy(key, sizeof h->ws_key, c->key, c->klen) || !hx_copy(val, sizeof h->ws_upd.val, c->val, c->vlen))
                    return helm_fail(h, c->line, KELP_ERR_PARSE, "parameter or value too long", HX_END);
                b->fail = NULL;
                if (kelp_helm_bhv_set_param(b, key, val) < 0) {
                    return helm_fail(h, c->line, KELP_ERR_PARSE, "behaviour ", b->name, ": bad parameter ", key, " (",
                                     b->fail ? b->fail : "rejected", ")", HX_END);
                }
            }
            continue;
        }
        char *key = h->ws_key;
        if (!hx_copy(key, sizeof h->ws_key, nd->key, nd->klen))
            key[0] = '\0';
        return helm_fail(h, nd->line, KELP_ERR_PARSE, "unexpected line in a behaviour file: ", key, HX_END);
    }
    return 0;
}

int kelp_helm_configured(kelp_helm *h)
{
    for (unsigned i = 0; i < h->nbhv; i++) {
        kelp_bhv *b = &h->bhv[i];
        b->fail = NULL;
        if (b->ops->params_done && b->ops->params_done(b) < 0) {
            return helm_fail(h, b->line, KELP_ERR_PARSE, "behaviour ", b->name, ": ", b->fail ? b->fail : "bad configuration",
                             HX_END);
        }
        if (b->dom.dim == 0)
            return helm_fail(h, b->line, KELP_ERR_STATE, "behaviour ", b->name,
                             ": null IvP domain (the helm Domain lacks a variable it decides)", HX_END);
        if (!kelp_ivp_domain_is_sub(&b->dom, &h->cfg.domain))
            return helm_fail(h, b->line, KELP_ERR_STATE, "behaviour ", b->name, ": domain is not a sub-domain of the helm domain", HX_END);
    }
    int rc = helm_templates_extract(h);
    if (rc < 0)
        return helm_fail(h, 0, rc, "too many spawn templates (KELP_HELM_MAX_TEMPLATES)", HX_END);
    return 0;
}

static void sink_post(kelp_helm *h, const char *var, bool is_str, const char *s, double d, const char *aux,
                      bool retract)
{
    if (!h->cfg.sink)
        return;
    kelp_helm_post p = {var, is_str, is_str ? s : NULL, is_str ? 0 : d, aux, retract};
    h->cfg.sink(&p, h->cfg.user);
}

static void sink(kelp_helm *h, const char *var, bool is_str, const char *s, double d, const char *aux)
{
    sink_post(h, var, is_str, s, d, aux, false);
}

void helm_sink(kelp_helm *h, const char *var, bool is_str, const char *s, double d, const char *aux)
{
    sink(h, var, is_str, s, d, aux);
}

void helm_life_event(kelp_helm *h, const char *bname, const char *btype, const char *event, const char *seed)
{
    char *buf = h->ws_upd.msg, it[24]; /* the update workspace: idle between updates */
    const size_t cap = sizeof h->ws_upd.msg;
    double ht = h->ib.curr_time - h->first_iter_time;
    size_t n = hx_cat(buf, cap, "iter=0", HX_END);
    if (ht > 0) {
        char tm[40];
        hx_fmt_fixed(tm, sizeof tm, ht, 2);
        n += hx_cat(buf + n, cap - n, ",time=", tm, HX_END);
    }
    n += hx_cat(buf + n, cap - n, ", bname=", bname, ", btype=", btype, ", event=", event, HX_END);
    if (seed && *seed)
        n += hx_cat(buf + n, cap - n, ", seed=", seed, HX_END);
    hx_fmt_ulong(it, sizeof it, h->dec_iter);
    hx_cat(buf + n, cap - n, ",iter=", it, HX_END);
    sink(h, "IVPHELM_LIFE_EVENT", true, buf, 0, NULL);
}

/* "course,0,359,360:speed,0,4,21" (IVPHELM_DOMAIN, the summary's ivpdomain) */
static void helm_domain_string(const kelp_ivp_domain *dom, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    for (unsigned d = 0; d < dom->dim; d++) {
        const kelp_ivp_var *v = &dom->var[d];
        char lo[32], hi[32], pt[24];
        hx_fmt_double(lo, sizeof lo, v->low);
        hx_fmt_double(hi, sizeof hi, v->high);
        hx_fmt_ulong(pt, sizeof pt, v->points);
        n += hx_cat(buf + n, cap - n, d ? ":" : "", v->name, ",", lo, ",", hi, ",", pt, HX_END);
    }
}

static void flush_posts(kelp_helm *h);

static void post_init(kelp_helm *h, const kelp_helm_pair *p)
{
    if (p->is_str)
        hx_ignore(kelp_helm_ib_set_string(&h->ib, p->var, p->sval, h->ib.curr_time, false));
    else
        hx_ignore(kelp_helm_ib_set_double(&h->ib, p->var, p->dval, h->ib.curr_time, false));
    sink(h, p->var, p->is_str, p->sval, p->dval, AUX_INIT);
}

static void post_mode(kelp_helm *h, const char *var, const char *val)
{
    sink(h, var, true, val, 0, "HELM_MODE"); /* 24.8's source aux for a mode variable */
}

void kelp_helm_start(kelp_helm *h, kelp_time now)
{
    h->t0 = now;
    h->started = true;
    h->ib.curr_time = 0;
    char *buf = h->ws_out.buf; /* the postings workspace: idle until the first iteration posts */
    const size_t cap = sizeof h->ws_out.buf;
    buf[0] = 0; /* HelmIvP posts the mode set at start, empty without mode declarations */
    if (h->nmodes)
        helm_mode_describe(h, buf, cap);
    sink(h, "IVPHELM_MODESET", true, buf, 0, NULL);
    helm_domain_string(&h->cfg.domain, buf, cap);
    sink(h, "IVPHELM_DOMAIN", true, buf, 0, NULL);
    /* one spawn event per behaviour of the files: posted by the first decision (24.8) */
    h->startup_events_pending = true;
    /* each behaviour's BHV_SETTINGS (onSetParamComplete): 24.8 calls it at start-up, and the
     * messages wait in the behaviour until the first engaged iteration posts them (with that
     * iteration's aux) */
    h->config_pending = true;
    /* onHelmStart: behaviours, then templates (their alert requests) */
    for (unsigned i = 0; i < h->nbhv; i++)
        if (h->bhv[i].ops->on_helm_start)
            h->bhv[i].ops->on_helm_start(&h->bhv[i]);
    for (unsigned i = 0; i < h->ntmpl; i++)
        if (h->tmpl[i].ops->on_helm_start)
            h->tmpl[i].ops->on_helm_start(&h->tmpl[i]);
    flush_posts(h);
    for (unsigned i = 0; i < h->ninit; i++)
        if (!h->init_defer[i])
            post_init(h, &h->init[i]);
}

typedef struct varset {
    char *buf;
    size_t cap;
    unsigned n;
} varset;

/* a name into a comma-joined list kept in ascending order, once (a std::set's order) */
static void set_add(const char *var, size_t len, void *user)
{
    varset *l = user;
    char name[KELP_MAX_NAME];
    if (!hx_copy(name, sizeof name, var, len))
        return;
    char *p = l->buf;
    while (*p) {
        const char *e = strchr(p, ',');
        size_t pl = e ? (size_t)(e - p) : strlen(p);
        int c = strncmp(p, name, pl < len ? pl : len);
        if (c == 0 && pl == len)
            return;
        if (c > 0 || (c == 0 && pl > len))
            break;
        p += pl + (e ? 1 : 0);
    }
    size_t used = strlen(l->buf), add = len + 1;
    if (used + add + 1 > l->cap)
        return;
    size_t at = (size_t)(p - l->buf);
    bool last = at >= used;
    memmove(p + add, p, used - at + 1);
    if (last && used) { /* after the last name: ",name" */
        p[0] = ',';
        memcpy(p + 1, name, len);
    } else {
        memcpy(p, name, len);
        p[len] = ',';
    }
    if (!used)
        p[len] = 0;
    l->n++;
}

/* HelmIvP's lists of what the behaviours listen to, as each drive iteration posts them:
 * IVPHELM_UPDATEVARS (BehaviorSet::getUpdateVarSummary: "name=VAR" of each behaviour with
 * updates, by name) when it changes, IVPHELM_STATEVARS (getStateSpaceVars: the variables of
 * the conditions and of the run, runx, idle, end, active and inactive flags, in order) when it
 * grows; neither while empty */
KELP_NOINLINE static void post_listen_vars(kelp_helm *h)
{
    char *buf = h->ws_out.buf;
    const size_t cap = sizeof h->ws_out.buf;
    buf[0] = 0;
    size_t n = 0;
    bool done[KELP_HELM_MAX_BHVS] = { false };
    for (unsigned k = 0; k < h->nbhv; k++) { /* by name: the next smallest each time */
        int pick = -1;
        for (unsigned i = 0; i < h->nbhv; i++)
            if (!done[i] && h->bhv[i].updates[0] && (pick < 0 || strcmp(h->bhv[i].name, h->bhv[pick].name) < 0))
                pick = (int)i;
        if (pick < 0)
            break;
        done[pick] = true;
        n += hx_cat(buf + n, cap - n, n ? "," : "", h->bhv[pick].name, "=", h->bhv[pick].updates, HX_END);
    }
    if (buf[0] && strcmp(buf, h->updatevars_posted) != 0 && n < sizeof h->updatevars_posted) {
        memcpy(h->updatevars_posted, buf, n + 1);
        sink(h, "IVPHELM_UPDATEVARS", true, buf, 0, NULL);
    }
    buf[0] = 0;
    varset l = { buf, cap, 0 };
    for (unsigned i = 0; i < h->nbhv; i++) {
        const kelp_bhv *b = &h->bhv[i];
        for (unsigned c = 0; c < b->ncond; c++)
            hx_ignore(kelp_helm_cond_check(b->cond[c], set_add, &l));
        for (unsigned f = 0; f < b->nflag; f++) {
            kelp_bhv_flag_kind k = b->flag[f].kind;
            if (k == KELP_FLAG_RUN || k == KELP_FLAG_RUNX || k == KELP_FLAG_IDLE || k == KELP_FLAG_END ||
                k == KELP_FLAG_ACTIVE || k == KELP_FLAG_INACTIVE)
                set_add(b->flag[f].p.var, strlen(b->flag[f].p.var), &l);
        }
    }
    if (l.n > h->statevars_posted) {
        h->statevars_posted = l.n;
        sink(h, "IVPHELM_STATEVARS", true, buf, 0, NULL);
    }
}

static bool override_mail(kelp_helm *h, const char *var, const char *v)
{
    if (strcmp(var, "MOOS_MANUAL_OVERIDE") != 0 && strcmp(var, "MOOS_MANUAL_OVERRIDE") != 0 &&
        (!h->cfg.other_override[0] || strcmp(var, h->cfg.other_override) != 0))
        return false;
    if (v && hx_ieq(v, "false"))
        h->engaged = true;
    else if (v && hx_ieq(v, "true") && h->cfg.allow_park)
        h->engaged = false;
    return true;
}

void kelp_helm_mail_double(kelp_helm *h, const char *var, double v)
{
    if (!strcmp(var, "IVPHELM_REJOURNAL"))
        h->rejournal = true;
    if (override_mail(h, var, NULL))
        return;
    if (kelp_helm_ib_set_double(&h->ib, var, v, h->ib.curr_time, true) == 0)
        h->ib.var[kelp_helm_ib_find(&h->ib, var)].pending = true;
}

void kelp_helm_mail_string(kelp_helm *h, const char *var, const char *v)
{
    if (override_mail(h, var, v))
        return;
    if (!strcmp(var, "IVPHELM_REJOURNAL"))
        h->rejournal = true;
    if (kelp_helm_ib_set_string(&h->ib, var, v, h->ib.curr_time, true) == 0)
        h->ib.var[kelp_helm_ib_find(&h->ib, var)].pending = true;
}

/* ---------------------------------------------------------------- postings */

static uint32_t qstr(kelp_helm *h, const char *s, bool *ok)
{
    size_t n = strlen(s) + 1;
    if (h->qpool_used + n > sizeof h->qpool) {
        *ok = false;
        return 0;
    }
    memcpy(h->qpool + h->qpool_used, s, n);
    uint32_t off = (uint32_t)h->qpool_used;
    h->qpool_used += n;
    return off;
}

void helm_queue_post(kelp_helm *h, const kelp_bhv *b, const char *var, bool is_str, const char *sval, double dval,
                     const char *key)
{
    if (h->nq >= KELP_HELM_MAX_POSTS) {
        h->posts_dropped++;
        return;
    }
    kelp_helm_qpost *q = &h->q[h->nq];
    bool ok = true;
    size_t mark = h->qpool_used;
    q->bhv = (uint16_t)(b >= h->bhv && b < h->bhv + KELP_HELM_MAX_BHVS ? (size_t)(b - h->bhv)
                                                                        : KELP_HELM_MAX_BHVS + (size_t)(b - h->tmpl));
    q->is_str = is_str;
    q->dval = dval;
    q->repeatable = key && !strcmp(key, "repeatable");
    q->var = qstr(h, var, &ok);
    q->sval = qstr(h, is_str ? sval : "", &ok);
    q->key = qstr(h, key && !q->repeatable ? key : "", &ok);
    if (!ok) {
        h->qpool_used = mark;
        h->posts_dropped++;
        return;
    }
    h->nq++;
}

void helm_expand_macros(const kelp_bhv *b, const char *in, char *out, size_t cap, bool *solo)
{
    size_t n = 0;
    unsigned found = 0;
    bool other = false;
    if (solo) *solo = false;
    if (!cap) return;
    if (!b) {
        out[0] = '\0';
        return;
    }
    while (*in && n + 1 < cap) {
        char *val = out + n; /* a macro's value is written in place (no copy on the stack) */
        size_t room = cap - n;
        const char *end = NULL;
        bool have = false;
        if (in[0] == '$' && (in[1] == '[' || in[1] == '(')) {
            end = strchr(in + 2, in[1] == '[' ? ']' : ')');
            if (end) {
                const char *m = in + 2;
                size_t ml = (size_t)(end - m);
                const char *g = NULL;
                char *num = b->helm ? b->helm->ws_macro : NULL; /* the helm's workspace, not the stack */
                if (ml == 7 && !strncmp(m, "OWNSHIP", ml)) g = b->us;
                else if (ml == 7 && !strncmp(m, "BHVNAME", ml)) g = b->name;
                else if (ml == 7 && !strncmp(m, "BHVTYPE", ml)) g = b->type;
                else if (ml == 3 && !strncmp(m, "PWT", ml)) {
                    if (num) {
                        hx_fmt_x(num, sizeof b->helm->ws_macro, b->pwt, 3);
                        g = num;
                    }
                } else if (ml == 3 && !strncmp(m, "UTC", ml) && b->helm) {
                    hx_fmt_x(num, sizeof b->helm->ws_macro, b->helm->t0 + kelp_helm_bhv_buf_now(b), 3);
                    g = num;
                } else if (num && ((ml == 12 && !strncmp(m, "DUR_RUN_TIME", ml)) ||
                                   (ml == 13 && !strncmp(m, "DUR_IDLE_TIME", ml)))) {
                    hx_fmt_x(num, sizeof b->helm->ws_macro, m[4] == 'R' ? b->dur_run_total : b->dur_idle_total, 3);
                    g = num;
                }
                if (g) have = hx_copy(val, room, g, strlen(g));
                else if (b->ops == &kelp_bhv_avoid_collision_ops) have = helm_avoid_macro(b, m, ml, val, room);
                else if (b->ops == &kelp_bhv_waypoint_ops) have = helm_wpt_macro(b, m, ml, val, room);
                else if (ml == 7 && !strncmp(m, "CONTACT", ml)) have = hx_copy(val, room, "", 0);
            }
        }
        if (!have) {
            other = true;
            out[n++] = *in++;
            continue;
        }
        found++;
        n += strlen(val);
        in = end + 1;
    }
    out[n] = '\0';
    if (solo) *solo = found == 1 && !other;
}

void helm_post_flag_string(kelp_bhv *b, const char *var, const char *sval, const char *key)
{
    if (!b->helm)
        return;
    char *val = b->helm->ws_flag; /* the value is queued (copied) before anything else posts */
    bool solo;
    double d;
    helm_expand_macros(b, sval, val, sizeof b->helm->ws_flag, &solo);
    if (solo && hx_number(val, strlen(val), &d))
        kelp_helm_bhv_post_double(b, var, d, key);
    else
        kelp_helm_bhv_post_string(b, var, val, key);
}

void helm_post_flags(kelp_bhv *b, kelp_bhv_flag_kind kind)
{
    /* Flags are posted on state transitions only, so each posting is made (repeatable):
     * a flag that fires again after someone else changed the variable must reach the bus. */
    const char *key = "repeatable";
    for (unsigned i = 0; i < b->nflag; i++) {
        const kelp_bhv_flag *f = &b->flag[i];
        if (f->kind != kind)
            continue;
        if (f->p.is_str)
            helm_post_flag_string(b, f->p.var, f->p.sval, key);
        else
            kelp_helm_bhv_post_double(b, f->p.var, f->p.dval, key);
    }
}

/* Duplicate filter: true when this (key, value) differs from the last one posted. */
static bool filter_pass(kelp_helm *h, uint64_t key, uint64_t val, uint32_t owner)
{
    for (unsigned i = 0; i < h->nfilter; i++)
        if (h->filter[i].key == key) {
            if (h->filter[i].val == val)
                return false;
            h->filter[i].val = val;
            return true;
        }
    if (h->nfilter < KELP_HELM_MAX_FILTER) {
        h->filter[h->nfilter].key = key;
        h->filter[h->nfilter].val = val;
        h->filter[h->nfilter].owner = owner;
        h->nfilter++;
    }
    return true;
}

static void flush_posts(kelp_helm *h)
{
    char aux[KELP_MAX_NAME + 24];
    for (unsigned i = 0; i < h->nq; i++) {
        const kelp_helm_qpost *q = &h->q[i];
        const kelp_bhv *b = q->bhv < KELP_HELM_MAX_BHVS ? &h->bhv[q->bhv] : &h->tmpl[q->bhv - KELP_HELM_MAX_BHVS];
        const char *var = h->qpool + q->var, *sv = h->qpool + q->sval, *key = h->qpool + q->key;
        if (q->is_str)
            hx_ignore(kelp_helm_ib_set_string(&h->ib, var, sv, h->ib.curr_time, false));
        else
            hx_ignore(kelp_helm_ib_set_double(&h->ib, var, q->dval, h->ib.curr_time, false));
        if (!q->repeatable) {
            uint64_t k = hx_hash(HX_HASH_INIT, b->name, strlen(b->name) + 1);
            k = hx_hash(k, &b->uid, sizeof b->uid);
            k = hx_hash(k, var, strlen(var) + 1);
            k = hx_hash(k, key, strlen(key));
            uint64_t v = hx_hash(HX_HASH_INIT, q->is_str ? "s" : "d", 1);
            v = q->is_str ? hx_hash(v, sv, strlen(sv)) : hx_hash(v, &q->dval, sizeof q->dval);
            if (!filter_pass(h, k, v, b->uid))
                continue;
        }
        bool retract = !strcmp(var, "BHV_WARNING") && !strcmp(key, "retract");
        if (!strcmp(var, "BHV_WARNING") && !retract)
            h->rep.warnings++;
        else if (!strcmp(var, "BHV_ERROR"))
            h->rep.errors++;
        char it[24];
        hx_fmt_ulong(it, sizeof it, h->dec_iter);
        hx_cat(aux, sizeof aux, it, ":", b->name, HX_END);
        sink_post(h, var, q->is_str, sv, q->dval, aux, retract);
    }
    h->nq = 0;
    h->qpool_used = 0;
}

/* ---------------------------------------------------------------- duration */

static bool duration_exceeded(kelp_bhv *b, kelp_time now)
{
    if (b->duration < 0)
        return false;
    if (!b->dur_started) {
        b->dur_started = true;
        b->dur_start = now;
        b->dur_idle_time = 0;
    }
    double el = now - b->dur_start;
    if (!b->duration_idle_decay)
        el -= b->dur_idle_time;
    return el >= b->duration;
}

static void duration_reset(kelp_bhv *b)
{
    b->dur_started = false;
    b->dur_start = -1;
    b->dur_idle_time = 0;
    b->dur_run_total = b->dur_idle_total = 0;
    if (b->duration_status[0] && b->duration >= 0)
        kelp_helm_bhv_post_double(b, b->duration_status, b->duration, NULL);
}

KELP_NOINLINE static void post_duration_status(kelp_bhv *b, kelp_time now)
{
    if (b->duration < 0 || !b->duration_status[0])
        return;
    double el = b->dur_started ? now - b->dur_start : 0;
    double rem = b->duration - el;
    if (!b->duration_idle_decay)
        rem += b->dur_idle_time;
    if (rem < 0)
        rem = 0;
    if (rem < 10)
        kelp_helm_bhv_post_double(b, b->duration_status, floor(rem * 100 + 0.5) / 100, NULL);
    else
        kelp_helm_bhv_post_int(b, b->duration_status, rem, NULL);
}

KELP_NOINLINE static void update_state_durations(kelp_bhv *b, bool idle, kelp_time now)
{
    if (b->dur_have_prev && idle && b->dur_started)
        b->dur_idle_time += now - b->dur_prev_time;
    /* 24.8's updateStateDurations: the time since the last call counts to the state now */
    if (b->dur_have_prev && now > b->dur_prev_time)
        *(idle ? &b->dur_idle_total : &b->dur_run_total) += now - b->dur_prev_time;
    b->dur_have_prev = true;
    b->dur_prev_time = now;
}

KELP_NOINLINE static void check_duration_reset(kelp_helm *h, kelp_bhv *b)
{
    if (!b->duration_reset_var[0])
        return;
    int i = kelp_helm_ib_find(&h->ib, b->duration_reset_var);
    if (i < 0 || h->ib.var[i].time < 0)
        return;
    const kelp_helm_ibvar *x = &h->ib.var[i];
    bool hit;
    if (x->is_str) {
        hit = !strcmp(x->sval, b->duration_reset_val);
    } else {
        double d;
        hit = hx_number(b->duration_reset_val, strlen(b->duration_reset_val), &d) && d == x->dval;
    }
    if (!hit)
        return;
    if (b->dur_reset_stamp < 0 || x->time > b->dur_reset_stamp) {
        b->dur_reset_stamp = x->time;
        duration_reset(b);
    }
}

/* ---------------------------------------------------------------- updates */

/* MOOS-IvP lets an update repeat itself when it carries one of these words */
static bool repeatable_update(const char *s)
{
    static const char *const words[] = {"toggle", "engage", "mod"};
    for (const char *p = s; *p; p++)
        for (int w = 0; w < 3; w++)
            if (strlen(p) >= strlen(words[w]) && kelp_util_strieq_n(p, strlen(words[w]), words[w]))
                return true;
    return false;
}

/* one '#'-separated piece "param = value", trimmed; false without '=' or when too long */
bool helm_update_piece(const char *piece, size_t pn, char *param, size_t pcap, char *val, size_t vcap)
{
    hx_trim(&piece, &pn);
    const char *eq = memchr(piece, '=', pn);
    if (!eq)
        return false;
    const char *pp = piece, *vp = eq + 1;
    size_t ppn = (size_t)(eq - piece), vpn = pn - ppn - 1;
    hx_trim(&pp, &ppn);
    hx_trim(&vp, &vpn);
    return hx_copy(param, pcap, pp, ppn) && hx_copy(val, vcap, vp, vpn);
}

/* Apply one update string; returns the result word of IVPHELM_UPDATE_RESULT. */
KELP_NOINLINE static const char *apply_update(kelp_helm *h, kelp_bhv *b, const char *s)
{
    char *param = h->ws_upd.param, *val = h->ws_upd.val, *bad = h->ws_upd.bad;
    const size_t paramcap = sizeof h->ws_upd.param, valcap = sizeof h->ws_upd.val, badcap = sizeof h->ws_upd.bad;
    bad[0] = '\0';
    /* a name=... piece must name this behaviour (neither a success nor a failure otherwise) */
    for (const char *p = s;;) {
        const char *e = strchr(p, '#');
        size_t pn = e ? (size_t)(e - p) : strlen(p);
        if (helm_update_piece(p, pn, param, paramcap, val, valcap) && !strcmp(param, "name") &&
            !helm_name_matches(b, val))
            return "name_mismatch";
        if (!e)
            break;
        p = e + 1;
    }
    bool ok = true;
    for (const char *p = s;;) {
        const char *e = strchr(p, '#');
        size_t pn = e ? (size_t)(e - p) : strlen(p);
        b->fail = NULL;
        bool parsed = helm_update_piece(p, pn, param, paramcap, val, valcap);
        if (!parsed || (strcmp(param, "name") != 0 && kelp_helm_bhv_set_param(b, param, val) < 0)) {
            ok = false;
            const char *pp = p;
            size_t ppn = pn;
            const char *eq = memchr(p, '=', pn);
            if (eq)
                ppn = (size_t)(eq - p);
            hx_trim(&pp, &ppn);
            size_t bl = strlen(bad);
            if (bl + ppn + 2 < badcap) {
                if (bl)
                    bad[bl++] = ',';
                memcpy(bad + bl, pp, ppn);
                bad[bl + ppn] = '\0';
            }
        }
        if (!e)
            break;
        p = e + 1;
    }
    if (!ok) {
        b->bad_updates++;
        char *msg = h->ws_upd.msg;
        hx_cat(msg, sizeof h->ws_upd.msg, "Faulty update for behavior: ", b->name, ". Bad parameter(s): ", bad, ".", HX_END);
        kelp_helm_bhv_post_string(b, "BHV_WARNING", msg, NULL);
        kelp_helm_bhv_post_string(b, "BHV_CONFIG_WARNING", msg, NULL);
        return "param_error";
    }
    b->good_updates++;
    return "success";
}

/* IVPHELM_UPDATE_RESULT: bhv=,var=,time= (since helm start),result=,val= */
KELP_NOINLINE static void post_update_result(kelp_helm *h, const kelp_bhv *b, const char *result, const char *s)
{
    char *msg = h->ws_upd.msg, tm[32];
    hx_fmt_fixed(tm, sizeof tm, h->ib.curr_time, 2);
    hx_cat(msg, sizeof h->ws_upd.msg, "bhv=", b->name, ",var=", b->updates, ",time=", tm, ",result=", result, ",val=", s, HX_END);
    sink(h, "IVPHELM_UPDATE_RESULT", true, msg, 0, NULL);
}

/* update_summary "good/attempted" (out of line: its texts stay off the deep path); 24.8 posts
 * no per-behaviour update variable (its results go out as IVPHELM_UPDATE_RESULT) */
KELP_NOINLINE static void update_summary(kelp_bhv *b, bool any)
{
    char g[24], t[24];
    hx_fmt_ulong(g, sizeof g, b->good_updates);
    hx_fmt_ulong(t, sizeof t, b->good_updates + b->bad_updates);
    hx_cat(b->update_summary, sizeof b->update_summary, g, "/", t, HX_END);
    (void)any;
}

KELP_NOINLINE static void check_updates(kelp_helm *h, kelp_bhv *b)
{
    if (!b->updates[0]) {
        hx_copy(b->update_summary, sizeof b->update_summary, "n/a", 3);
        return;
    }
    bool made = false, any = false;
    unsigned n = kelp_helm_ib_ndeltas(&h->ib, b->updates);
    for (unsigned k = 0; k < n; k++) {
        const char *s = NULL;
        if (!kelp_helm_ib_delta(&h->ib, b->updates, k, NULL, &s) || !s || !*s)
            continue;
        uint64_t hs = hx_hash(HX_HASH_INIT, s, strlen(s));
        const char *result = "duplicate";
        if (!b->prev_update_hash || hs != b->prev_update_hash || repeatable_update(s)) {
            any = true;
            result = apply_update(h, b, s);
            if (!strcmp(result, "success")) {
                made = true;
                b->prev_update_hash = hs;
            }
        }
        post_update_result(h, b, result, s);
    }
    if (made && b->ops->params_done)
        (void)b->ops->params_done(b);
    if (made && b->ops->post_config)
        b->ops->post_config(b);
    update_summary(b, any);
}

/* ---------------------------------------------------------------- isRunnable */

/* NOSTARVE: BHV_ERROR "<name>: VarStarve: VAR older than S s" (out of line: its text) */
KELP_NOINLINE static void post_starved(kelp_bhv *b, const char *var)
{
    char msg[KELP_MAX_NAME + 96], secs[32];
    hx_fmt_double(secs, sizeof secs, b->starve_time);
    hx_cat(msg, sizeof msg, b->name, ": VarStarve: ", var, " older than ", secs, " s", HX_END);
    kelp_helm_bhv_post_string(b, "BHV_ERROR", msg, NULL);
    b->state_ok = false;
}

KELP_NOINLINE static kelp_bhv_state runnable(kelp_helm *h, kelp_bhv *b)
{
    kelp_time now = h->ib.curr_time;
    b->failed_cond = -1;
    for (unsigned i = 0; i < b->ncond; i++)
        if (kelp_helm_cond_eval(b->cond[i], &h->ib) != 1) {
            b->failed_cond = (int)i;
            return KELP_BHV_IDLE;
        }
    if (duration_exceeded(b, now)) {
        kelp_helm_bhv_set_complete(b);
        if (!b->perpetual)
            return KELP_BHV_COMPLETED;
        duration_reset(b);
    }
    if (b->dom.dim == 0) {
        kelp_helm_bhv_post_error(b, "Null IvPDomain given to Behavior");
        return KELP_BHV_IDLE;
    }
    for (unsigned i = 0; i < b->nstarve; i++) {
        double t = kelp_helm_ib_time(&h->ib, b->starve[i]);
        if (t < 0 || now - t > b->starve_time) {
            post_starved(b, b->starve[i]);
            return KELP_BHV_IDLE;
        }
    }
    return KELP_BHV_RUNNING;
}

static bool func_finite(const kelp_ivp_func *f)
{
    for (size_t i = 0; i < f->n; i++) {
        if (!isfinite(f->pcs[i].cst))
            return false;
        for (unsigned d = 0; d < f->dom.dim; d++)
            if (!isfinite(f->pcs[i].slope[d]))
                return false;
    }
    return true;
}

/* produceOF for behaviour i; returns true when it produced a function into h->fn[i]. */
/* BHV_STATUS: posted when it changes, keyed by the behaviour (MOOS-IvP 24.8's statusInfoPost):
 * "name=<b>", an idle behaviour's failed condition as pc=<condition> (twice: 24.8 asks
 * isRunnable before the run and again after it), an active one's pwt= (5 decimals) and pcs=
 * (its pieces), then state= and updates= */
KELP_NOINLINE static void post_status(kelp_helm *h, kelp_bhv *b, kelp_bhv_state ns, unsigned i)
{
    static const char *const stname[] = {"idle", "idle", "running", "active", "completed"};
    const char *st = b->completed ? "completed" : stname[ns <= KELP_BHV_COMPLETED ? ns : 0];
    char *msg = h->ws_out.status;
    const size_t cap = sizeof h->ws_out.status;
    size_t n = hx_cat(msg, cap, "name=", b->name, HX_END);
    if (!b->completed && ns == KELP_BHV_IDLE && b->failed_cond >= 0 && (unsigned)b->failed_cond < b->ncond) {
        const char *c = b->cond[b->failed_cond];
        n += hx_cat(msg + n, cap - n, ",pc=", c, ",pc=", c, HX_END);
    }
    if (!b->completed && ns == KELP_BHV_ACTIVE) {
        char pw[32], pc[24];
        hx_fmt_fixed(pw, sizeof pw, h->fn[i].pwt, 5);
        hx_fmt_ulong(pc, sizeof pc, (unsigned long)h->fn[i].n);
        n += hx_cat(msg + n, cap - n, ",pwt=", pw, ",pcs=", pc, HX_END);
    }
    hx_cat(msg + n, cap - n, ",state=", st, ",updates=", b->update_summary, HX_END);
    kelp_helm_bhv_post_string(b, "BHV_STATUS", msg, b->name);
}

/* BHV_IPF: the function as MOOS-IvP 24.8's helm posts it each iteration a behaviour makes one
 * (BehaviorSet, the FunctionEncoder's string with context "<iteration>:<behaviour>"), through
 * the behaviour's post_mapping, cut into packets as HelmIvP does (IvPFunctionToVector, 2,000
 * characters: "P,<behaviour>^<iteration>,<packets>,<packet>,<part of the string>", a packet's
 * part 2,000 less 50 and the id long), each with the behaviour's name as source aux. Several
 * KB a function, it goes straight to the sink (not through the postings pool or the info
 * buffer); one longer than a bus value (KELP_MAX_SVAL) is not posted and counted
 * (ipf_oversize). */
KELP_NOINLINE static void post_ipf(kelp_helm *h, const kelp_bhv *b, const kelp_ivp_func *f)
{
    const char *var = helm_bhv_var(b, "BHV_IPF");
    if (hx_ieq(var, "silent"))
        return;
    char ctx[KELP_MAX_NAME + 24], it[24];
    hx_fmt_ulong(it, sizeof it, h->dec_iter);
    hx_cat(ctx, sizeof ctx, it, ":", b->name, HX_END);
    if (kelp_ivp_func_to_ipf(f, ctx, b->ipf_gel_set ? b->ipf_gel : NULL, h->ws_ipf, sizeof h->ws_ipf) < 0) {
        h->ipf_oversize++;
        return;
    }
    h->ipf_posted++;
    char id[KELP_MAX_NAME + 24], np[16], ip[16];
    size_t idn = hx_cat(id, sizeof id, b->name, "^", it, HX_END);
    size_t whole = strlen(h->ws_ipf), body = KELP_HELM_IPF_PACKET - (idn + 50);
    unsigned long n = (unsigned long)(whole / body) + 1;
    hx_fmt_ulong(np, sizeof np, n);
    for (unsigned long i = 0; i < n; i++) {
        hx_fmt_ulong(ip, sizeof ip, i + 1);
        size_t k = hx_cat(h->ws_ipf_pkt, sizeof h->ws_ipf_pkt, "P,", id, ",", np, ",", ip, ",", HX_END);
        size_t from = (size_t)i * body, len = from < whole ? whole - from : 0;
        if (len > body) len = body;
        if (len > sizeof h->ws_ipf_pkt - 1 - k) len = sizeof h->ws_ipf_pkt - 1 - k;
        memcpy(h->ws_ipf_pkt + k, h->ws_ipf + from, len);
        h->ws_ipf_pkt[k + len] = 0;
        sink(h, var, true, h->ws_ipf_pkt, 0, b->name);
    }
}

/* The running state of behaviour i (onRunState): RUNNING, or ACTIVE when it made a function
 * (*made). Out of line: its work descriptor stays off the updates path. */
KELP_NOINLINE static kelp_bhv_state run_state(kelp_helm *h, unsigned i, kelp_bhv_state old, size_t *pool_used, bool *made)
{
    kelp_bhv *b = &h->bhv[i];
    kelp_time now = h->ib.curr_time;
    kelp_bhv_state ns = KELP_BHV_RUNNING;
    if (old == KELP_BHV_IDLE || old == KELP_BHV_NONE)
        helm_post_flags(b, KELP_FLAG_RUN);
    post_duration_status(b, now);
    kelp_helm_work *w = &h->ws_work; /* in the helm, not on the stack */
    *w = (kelp_helm_work){h->mem.pool + *pool_used, h->mem.pool_cap - *pool_used, h->mem.tmp, h->mem.tmp_cap,
                          h->mem.dwork, h->mem.dwork_cap, h->mem.pq, h->mem.pq_cap};
    kelp_ivp_func *f = &h->fn[i];
    b->pwt_factor = 1.0;
    b->ipf_gel_set = false;
    int rc = b->ops->on_run ? b->ops->on_run(b, w, f) : 0;
    helm_post_flags(b, KELP_FLAG_RUNX);
    if (rc == 1 && f->n > 0 && !func_finite(f)) {
        kelp_helm_bhv_post_error(b, "NaN detected in IvP Function");
        rc = 0;
    }
    double pwt = b->pwt * (b->pwt_factor >= 0 ? b->pwt_factor : 0);
    if (rc == 1 && f->n > 0 && pwt > 0) {
        f->pwt = pwt;
        *made = true;
        post_ipf(h, b, f);
        *pool_used += f->n;
        if (old != KELP_BHV_ACTIVE)
            helm_post_flags(b, KELP_FLAG_ACTIVE);
        ns = KELP_BHV_ACTIVE;
    } else if (old == KELP_BHV_ACTIVE) {
        helm_post_flags(b, KELP_FLAG_INACTIVE);
    }
    update_state_durations(b, false, now);
    return ns;
}

KELP_NOINLINE static bool produce(kelp_helm *h, unsigned i, size_t *pool_used, bool *halted)
{
    kelp_bhv *b = &h->bhv[i];
    kelp_time now = h->ib.curr_time;
    kelp_bhv_state old = b->state;
    bool made = false;
    if (b->completed) { /* isComplete(): completed in a prior iteration */
        b->state = KELP_BHV_COMPLETED;
        return false;
    }
    b->state_ok = true;
    if (++b->bhv_iter == 1) { /* the first iteration: configflag and spawnx_flag */
        helm_post_flags(b, KELP_FLAG_CONFIG);
        helm_post_flags(b, KELP_FLAG_SPAWNX);
    }
    check_updates(h, b);
    check_duration_reset(h, b);
    kelp_bhv_state ns = runnable(h, b);
    if (ns == KELP_BHV_IDLE) {
        if (old != KELP_BHV_IDLE) {
            helm_post_flags(b, KELP_FLAG_IDLE);
            helm_post_flags(b, KELP_FLAG_INACTIVE);
        }
        if (b->ops->on_idle)
            b->ops->on_idle(b);
        update_state_durations(b, true, now);
    } else if (ns == KELP_BHV_RUNNING) {
        ns = run_state(h, i, old, pool_used, &made);
    }
    if (!b->state_ok)
        *halted = true;
    if (ns != old)
        b->state_entered = now;
    b->state = ns;
    if (made)
        h->rep.active_goal = true; /* kelp's behaviours are all goal (not constraint) behaviours */
    post_status(h, b, ns, i);
    return made;
}

/* ---------------------------------------------------------------- decision */

static void desired_name(const char *var, char *out, size_t cap)
{
    hx_cat(out, cap, "DESIRED_", hx_ieq(var, "course") ? "heading" : var, HX_END);
    for (char *c = out + 8; *c; c++)
        if (*c >= 'a' && *c <= 'z')
            *c = (char)(*c - 'a' + 'A');
}

static void list_append(char *buf, size_t cap, const char *name, char sep)
{
    size_t n = strlen(buf), m = strlen(name);
    if (n + m + 2 > cap)
        return;
    if (n)
        buf[n++] = sep;
    memcpy(buf + n, name, m + 1);
}

KELP_NOINLINE static void solve_failed(kelp_helm *h, int rc)
{
    char msg[220];
    hx_cat(msg, sizeof msg, "pHelmIvP: IvP solve failed: ", kelp_err_str(rc), " (", kelp_diag_text(&h->prob.diag), ")", HX_END);
    sink(h, "BHV_ERROR", true, msg, 0, NULL);
    h->rep.halted = true;
    hx_copy(h->rep.halt_msg, sizeof h->rep.halt_msg, msg + 10, strlen(msg + 10));
}

KELP_NOINLINE static void solve(kelp_helm *h, const bool *has_fn)
{
    kelp_helm_report *r = &h->rep;
    const kelp_ivp_domain *hd = &h->cfg.domain;
    bool cover[KELP_IVP_MAX_DIM] = {false};
    for (unsigned i = 0; i < h->nbhv; i++) {
        if (!has_fn[i])
            continue;
        for (unsigned d = 0; d < h->fn[i].dom.dim; d++) {
            int k = kelp_ivp_domain_index(hd, h->fn[i].dom.var[d].name);
            if (k < 0) {
                r->halted = true;
                hx_cat(r->halt_msg, sizeof r->halt_msg, "DomainVar ", h->fn[i].dom.var[d].name, " not recognized", HX_END);
                sink(h, "BHV_ERROR", true, "pHelmIvP: HELM HALTING: Unrecognized domain var", 0, NULL);
                return;
            }
            cover[k] = true;
        }
    }
    kelp_ivp_domain *sub = &h->ws_sub;
    kelp_ivp_domain_init(sub);
    for (unsigned d = 0; d < hd->dim; d++)
        if (cover[d])
            hx_ignore(kelp_ivp_domain_add(sub, hd->var[d].name, hd->var[d].low, hd->var[d].high, hd->var[d].points));
    kelp_ivp_problem_init(&h->prob, sub);
    for (unsigned i = 0; i < h->nbhv; i++)
        if (has_fn[i] && r->ofnum < KELP_IVP_MAX_FUNCS && kelp_ivp_problem_add(&h->prob, &h->fn[i]) == 0)
            r->ofnum++;
    if (r->ofnum == 0)
        return;
    kelp_ivp_result res;
    int rc = kelp_ivp_solve(&h->prob, h->mem.solve_work, h->mem.solve_work_size, &res);
    if (rc < 0) {
        solve_failed(h, rc);
        return;
    }
    for (unsigned j = 0; j < sub->dim; j++) {
        int k = kelp_ivp_domain_index(hd, sub->var[j].name);
        r->decided[k] = true;
        r->decision[k] = res.val[j];
    }
}

static void post_completed_pending(kelp_helm *h);

/* 24.8's CPU clock readings come in 10 ms steps: a time shown as its whole steps */
static double tick10ms(double t)
{
    return floor(t * 100.0 + 1e-9) / 100.0;
}

/* one field of the summary: ",key=" and the text, kept only when the text (hashed) changed
 * since the last summary or the summary is a full one. @return the new length */
static size_t sum_field(char *buf, size_t cap, size_t n, const char *key, const char *text, uint64_t *prev, bool full)
{
    uint64_t hv = hx_hash(HX_HASH_INIT, text, strlen(text));
    if (!full && hv == *prev)
        return n;
    *prev = hv;
    return n + hx_cat(buf + n, cap - n, ",", key, "=", text, HX_END);
}

/* a behaviour list as HelmReport writes it in full: entries joined with ':', each
 * "name$<utc of its state, 2 decimals>$<updates>" (an active one:
 * "name$<utc>$<pwt, 5 decimals>$<pieces>$<cpu, 5 decimals>$<updates>$<functions>$<mode>$<submode>") */
KELP_NOINLINE static void sum_list(const kelp_helm *h, kelp_bhv_state st, char *out, size_t cap)
{
    size_t n = 0;
    out[0] = 0;
    for (unsigned i = 0; i < h->nbhv; i++) {
        const kelp_bhv *b = &h->bhv[i];
        kelp_bhv_state bs = b->completed && b->state != KELP_BHV_NONE ? KELP_BHV_COMPLETED : b->state;
        if (bs != st)
            continue;
        char tm[32];
        hx_fmt_fixed(tm, sizeof tm, h->t0 + b->state_entered, 2);
        n += hx_cat(out + n, cap - n, n ? ":" : "", b->name, "$", tm, "$", HX_END);
        if (st == KELP_BHV_ACTIVE) {
            char pw[32], pc[24];
            hx_fmt_fixed(pw, sizeof pw, b->pwt, 5);
            hx_fmt_ulong(pc, sizeof pc, h->ws_has_fn[i] ? h->fn[i].n : 0);
            /* the behaviour's CPU: kelp reads no clock per behaviour */
            n += hx_cat(out + n, cap - n, pw, "$", pc, "$0.00000$", b->update_summary, "$1$$", HX_END);
        } else
            n += hx_cat(out + n, cap - n, b->update_summary, HX_END);
    }
}

/* IVPHELM_SUMMARY as 24.8's HelmReport::getReportAsString: iter and utc_time always, then each
 * field only when it changed since the last summary (all of them in the first one, and after
 * IVPHELM_REJOURNAL): ofnum, total_pcs_formed (this iteration's), total_pcs_cached, warnings,
 * the times (CPU seconds, 2 decimals), the decision (var=<name>:<value> per domain variable,
 * varbalk when undecided), halted, active_goal, modes, the five behaviour lists, ivpdomain,
 * halt_msg. Composed in the BHV_IPF workspace (free after the behaviours' runs). */
KELP_NOINLINE static void post_summary(kelp_helm *h)
{
    const kelp_helm_report *r = &h->rep;
    kelp_helm_sumprev *p = &h->sum;
    const kelp_ivp_domain *hd = &h->cfg.domain;
    char *buf = h->ws_ipf, *tmp = h->ws_out.tmp, num[40];
    const size_t cap = sizeof h->ws_ipf;
    const bool full = !p->valid || h->rejournal;
    p->valid = true;
    h->rejournal = false;
    hx_fmt_ulong(num, sizeof num, r->iteration);
    size_t n = hx_cat(buf, cap, "iter=", num, ",utc_time=", HX_END);
    hx_fmt_fixed(num, sizeof num, h->t0 + r->time, 2);
    n += hx_cat(buf + n, cap - n, num, HX_END);
    hx_fmt_ulong(num, sizeof num, r->ofnum);
    n = sum_field(buf, cap, n, "ofnum", num, &p->h[0], full);
    hx_fmt_ulong(num, sizeof num, r->pcs_formed);
    n = sum_field(buf, cap, n, "total_pcs_formed", num, &p->h[1], full);
    n = sum_field(buf, cap, n, "total_pcs_cached", "0", &p->h[2], full); /* kelp caches none */
    hx_fmt_ulong(num, sizeof num, r->warnings);
    n = sum_field(buf, cap, n, "warnings", num, &p->h[3], full);
    const double create = tick10ms(r->create_time), solved = tick10ms(r->solve_time);
    const double tval[6] = {solved, create, tick10ms(r->max_create_time), tick10ms(r->max_solve_time),
                            tick10ms(r->max_loop_time), create + solved};
    static const char *const tkey[6] = {"solve_time", "create_time", "max_create_time", "max_solve_time",
                                        "max_loop_time", "loop_time"};
    for (int k = 0; k < 6; k++) {
        hx_fmt_fixed(num, sizeof num, tval[k], 2);
        n = sum_field(buf, cap, n, tkey[k], num, &p->h[4 + k], full);
    }
    /* the decision: one text of all its variables */
    size_t t = 0;
    tmp[0] = 0;
    for (unsigned d = 0; d < hd->dim; d++) {
        if (r->decided[d])
            hx_fmt_x(num, sizeof num, r->decision[d], 5);
        t += hx_cat(tmp + t, sizeof h->ws_out.tmp - t, d ? ",var=" : "var=", hd->var[d].name, ":",
                    r->decided[d] ? num : "varbalk", HX_END);
    }
    uint64_t hv = hx_hash(HX_HASH_INIT, tmp, t);
    if (full || hv != p->h[10])
        n += hx_cat(buf + n, cap - n, ",", tmp, HX_END);
    p->h[10] = hv;
    n = sum_field(buf, cap, n, "halted", r->halted ? "true" : "false", &p->h[11], full);
    n = sum_field(buf, cap, n, "active_goal", r->active_goal ? "true" : "false", &p->h[12], full);
    n = sum_field(buf, cap, n, "modes", h->mode_summary[0] ? h->mode_summary : "none", &p->h[13], full);
    /* the lists ("none" when empty; an emptied completed list is written empty, as 24.8 does) */
    static const kelp_bhv_state lst[5] = {KELP_BHV_RUNNING, KELP_BHV_ACTIVE, KELP_BHV_NONE, KELP_BHV_IDLE,
                                          KELP_BHV_COMPLETED};
    static const char *const lkey[5] = {"running_bhvs", "active_bhvs", "disabled_bhvs", "idle_bhvs",
                                        "completed_bhvs"};
    char *lb = h->ws_out.buf;
    for (int k = 0; k < 5; k++) {
        if (lst[k] == KELP_BHV_NONE)
            lb[0] = 0; /* kelp has no disabled behaviours */
        else
            sum_list(h, lst[k], lb, sizeof h->ws_out.buf);
        hv = hx_hash(HX_HASH_INIT, lb, strlen(lb));
        if (full || hv != p->h[14 + k]) {
            const char *txt = lb[0] ? lb : (k == 4 && !full && p->cmpl_nonempty) ? "" : "none";
            n += hx_cat(buf + n, cap - n, ",", lkey[k], "=", txt, HX_END);
        }
        p->h[14 + k] = hv;
        if (k == 4)
            p->cmpl_nonempty = lb[0] != 0;
    }
    if (full) {
        helm_domain_string(hd, lb, sizeof h->ws_out.buf);
        n += hx_cat(buf + n, cap - n, ",ivpdomain=\"", lb, "\"", HX_END);
    }
    (void)sum_field(buf, cap, n, "halt_msg", r->halt_msg[0] ? r->halt_msg : "none", &p->h[19], full);
    sink(h, "IVPHELM_SUMMARY", true, buf, 0, NULL);
}

KELP_NOINLINE static void post_outputs(kelp_helm *h)
{
    kelp_helm_report *r = &h->rep;
    const kelp_ivp_domain *hd = &h->cfg.domain;
    char *buf = h->ws_out.buf, name[KELP_MAX_NAME + 16];
    const size_t bufcap = sizeof h->ws_out.buf;
    /* all-stop reason (MOOS-IvP's strings) */
    if (!h->engaged)
        strcpy(r->allstop, "ManualOverride");
    else if (r->halted)
        strcpy(r->allstop, "BehaviorError");
    else if (r->ofnum == 0)
        strcpy(r->allstop, "NothingToDo");
    else {
        strcpy(r->allstop, "clear");
        char missing[80] = "";
        for (unsigned d = 0; d < hd->dim; d++)
            if (!r->decided[d] && !h->cfg.optional[d])
                list_append(missing, sizeof missing, hd->var[d].name, ',');
        if (missing[0]) {
            hx_cat(r->allstop, sizeof r->allstop, "MissingDecVars:", missing, HX_END);
            sink(h, "BHV_ERROR", true, r->allstop, 0, NULL);
        }
    }
    bool clear = !strcmp(r->allstop, "clear");
    if (!clear && h->engaged && h->cfg.park_on_allstop && h->cfg.allow_park)
        h->engaged = false; /* park until an override engages the helm again */
    /* HelmIvP::postAllStop: the reason only when it differs from the one last posted (MOOS_DEBUG,
     * then IVPHELM_ALLSTOP), the zeros with it; the first reason without a decision posts no
     * zeros and is remembered as IncompleteOrEmptyDecision, so the next iteration posts it again
     * with the zeros (a mode change gets one iteration to bring the next behaviour in) */
    if (strcmp(r->allstop, h->allstop_posted) != 0) {
        memcpy(h->allstop_posted, r->allstop, sizeof h->allstop_posted);
        bool nodec = !strcmp(r->allstop, "NothingToDo") || !strncmp(r->allstop, "MissingDecVars", 14);
        h->no_decisions = nodec ? h->no_decisions + 1 : 0;
        hx_cat(buf, bufcap, "pHelmIvP AllStop: ", r->allstop, HX_END);
        sink(h, "MOOS_DEBUG", true, buf, 0, NULL);
        sink(h, "IVPHELM_ALLSTOP", true, r->allstop, 0, NULL);
        if (!clear && h->no_decisions == 1)
            strcpy(h->allstop_posted, "IncompleteOrEmptyDecision");
        else if (!clear)
            for (unsigned d = 0; d < hd->dim; d++) {
                desired_name(hd->var[d].name, name, sizeof name);
                sink(h, name, false, NULL, 0.0, NULL);
            }
    }
    for (unsigned d = 0; clear && d < hd->dim; d++)
        if (r->decided[d]) {
            desired_name(hd->var[d].name, name, sizeof name);
            sink(h, name, false, NULL, r->decision[d], NULL);
        }
    /* behaviour lists */
    char (*lists)[256] = h->ws_out.lists, *cmpl = h->ws_out.lists[3];
    lists[0][0] = lists[1][0] = lists[2][0] = cmpl[0] = 0;
    r->nactive = r->nrunning = r->nidle = r->ncompleted = 0;
    for (unsigned i = 0; i < h->nbhv; i++) {
        const kelp_bhv *b = &h->bhv[i];
        /* a behaviour that completed this iteration is listed as completed at once (24.8
         * removes it at the end of the iteration; its lists never show it running) */
        switch (b->completed && b->state != KELP_BHV_NONE ? KELP_BHV_COMPLETED : b->state) {
        case KELP_BHV_ACTIVE: list_append(lists[0], sizeof lists[0], b->name, ','); r->nactive++; break;
        case KELP_BHV_RUNNING: list_append(lists[1], sizeof lists[1], b->name, ','); r->nrunning++; break;
        case KELP_BHV_IDLE: list_append(lists[2], sizeof lists[2], b->name, ','); r->nidle++; break;
        case KELP_BHV_COMPLETED: list_append(cmpl, sizeof h->ws_out.lists[3], b->name, ','); r->ncompleted++; break;
        case KELP_BHV_NONE: break;
        }
    }
    /* behaviour counts as 24.8's helm posts them: the four list counts 0 once at start-up;
     * the behaviour count and the count ever made when they change (from 0), by the drive
     * iterations; the count leaves out the behaviours completed before this iteration (24.8
     * removes a completed behaviour at the end of the iteration it completed in). kelp has no
     * disabled behaviours: their count stays 0 */
    if (!h->last_cnt[2]) {
        static const char *const zvar[4] = {"IVPHELM_BHV_ACTIVE_CNT", "IVPHELM_BHV_IDLE_CNT", "IVPHELM_BHV_RUNNING_CNT",
                                            "IVPHELM_BHV_DISABLED_CNT"};
        for (int k = 0; k < 4; k++)
            sink(h, zvar[k], false, NULL, 0.0, NULL);
        h->last_cnt[2] = 1;
    }
    if (h->engaged) {
        unsigned bc = h->nbhv - (h->ncompleted_seen < h->nbhv ? h->ncompleted_seen : h->nbhv);
        if (bc != h->last_cnt[0]) {
            sink(h, "IVPHELM_BHV_CNT", false, NULL, (double)bc, NULL);
            h->last_cnt[0] = bc;
        }
        if (h->bhv_cnt_ever != h->last_cnt[1]) {
            sink(h, "IVPHELM_BHV_CNT_EVER", false, NULL, (double)h->bhv_cnt_ever, NULL);
            h->last_cnt[1] = (unsigned)h->bhv_cnt_ever;
        }
    }
    if (r->create_time > r->max_create_time)
        r->max_create_time = r->create_time;
    if (r->solve_time > r->max_solve_time)
        r->max_solve_time = r->solve_time;
    if (r->loop_time > r->max_loop_time)
        r->max_loop_time = r->loop_time;
    r->total_pcs_formed += r->pcs_formed;
    if (h->cfg.cpu_clock) {
        sink(h, "IVPHELM_CREATE_CPU", false, NULL, r->create_time, NULL);
        sink(h, "IVPHELM_LOOP_CPU", false, NULL, r->loop_time, NULL);
    }
    /* each list, with its count, when it changes from the last posted (empty at first) */
    static const char *const lvar[3] = {"IVPHELM_BHV_ACTIVE", "IVPHELM_BHV_RUNNING", "IVPHELM_BHV_IDLE"};
    static const char *const lcnt[3] = {"IVPHELM_BHV_ACTIVE_CNT", "IVPHELM_BHV_RUNNING_CNT", "IVPHELM_BHV_IDLE_CNT"};
    const unsigned ln[3] = {r->nactive, r->nrunning, r->nidle};
    for (int k = 0; k < 3; k++)
        if (strcmp(lists[k], h->last_lists[k]) != 0) {
            sink(h, lvar[k], true, lists[k], 0, NULL);
            sink(h, lcnt[k], false, NULL, (double)ln[k], NULL);
            memcpy(h->last_lists[k], lists[k], sizeof lists[k]);
        }
    /* IVPHELM_SUMMARY: 24.8's HelmReport, by the engaged iterations only (a parked 24.8 helm
     * returns before it) */
    if (h->engaged)
        post_summary(h);
    sink(h, "IVPHELM_IPF_CNT", false, NULL, (double)r->ofnum, NULL);
    /* every iteration, as MOOS-IvP's helm; kelp builds each function anew (nothing cached) */
    sink(h, "IVPHELM_TOTAL_PCS_FORMED", false, NULL, (double)r->pcs_formed, NULL); /* 24.8: this iteration's */
    sink(h, "IVPHELM_TOTAL_PCS_CACHED", false, NULL, 0, NULL);
    sink(h, "IVPHELM_ITER", false, NULL, (double)h->dec_iter, NULL);
    if (h->engaged)
        post_completed_pending(h);
}

/* a new report keeping the running counts (not a copy of the whole report: stack; and out of
 * line, so its saved values are not in kelp_helm_iterate's frame) */
KELP_NOINLINE static void report_reset(kelp_helm_report *r)
{
    unsigned long warnings = r->warnings, errors = r->errors, total_pcs = r->total_pcs_formed;
    double max_create = r->max_create_time, max_solve = r->max_solve_time, max_loop = r->max_loop_time;
    memset(r, 0, sizeof *r);
    r->warnings = warnings;
    r->errors = errors;
    r->max_create_time = max_create;
    r->max_solve_time = max_solve;
    r->max_loop_time = max_loop;
    r->total_pcs_formed = total_pcs;
}

/* IVPHELM_LEDGER_SUMMARY as ContactLedger::getSummary(20): "now:2, reps:31, who:ben,cal", the
 * names in order, at most 20 */
KELP_NOINLINE static void post_ledger_summary(kelp_helm *h)
{
    char *buf = h->ws_out.buf, num[24];
    const size_t cap = sizeof h->ws_out.buf;
    hx_fmt_ulong(num, sizeof num, h->ncontacts);
    size_t n = hx_cat(buf, cap, "now:", num, HX_END);
    hx_fmt_ulong(num, sizeof num, h->ledger_reports);
    n += hx_cat(buf + n, cap - n, ", reps:", num, ", who:", HX_END);
    const char *last = NULL;
    for (unsigned k = 0; k < h->ncontacts && k < 20; k++) {
        const char *next = NULL;
        for (unsigned i = 0; i < h->ncontacts; i++) {
            const char *c = h->ledger[i].name;
            if ((!last || strcmp(c, last) > 0) && (!next || strcmp(c, next) < 0))
                next = c;
        }
        if (!next)
            break;
        n += hx_cat(buf + n, cap - n, k ? "," : "", next, HX_END);
        last = next;
    }
    sink(h, "IVPHELM_LEDGER_SUMMARY", true, buf, 0, NULL);
}

/* a heading change in (-180, 180] */
static double angle180(double a)
{
    a = fmod(a, 360.0);
    if (a > 180.0)
        a -= 360.0;
    else if (a <= -180.0)
        a += 360.0;
    return a;
}

/* TURN_RATE as PlatModelGenerator::getTurnRate: the headings of the last 5 s of decisions, the
 * mean signed change between consecutive ones (degrees per iteration, starboard positive) */
KELP_NOINLINE static void post_turn_rate(kelp_helm *h, kelp_time now)
{
    double x, y, hdg, spd;
    if (!kelp_helm_ib_double(&h->ib, "NAV_X", &x) || !kelp_helm_ib_double(&h->ib, "NAV_Y", &y) ||
        !kelp_helm_ib_double(&h->ib, "NAV_HEADING", &hdg) || !kelp_helm_ib_double(&h->ib, "NAV_SPEED", &spd))
        return;
    h->hdg_head = (h->hdg_head + 1) % KELP_HELM_HDG_HIST;
    h->hdg_t[h->hdg_head] = now, h->hdg_v[h->hdg_head] = hdg;
    if (h->hdg_n < KELP_HELM_HDG_HIST)
        h->hdg_n++;
    while (h->hdg_n > 0) { /* drop the entries older than the window */
        unsigned oldest = (h->hdg_head + KELP_HELM_HDG_HIST + 1 - h->hdg_n) % KELP_HELM_HDG_HIST;
        if (now - h->hdg_t[oldest] <= KELP_HELM_TURN_WINDOW)
            break;
        h->hdg_n--;
    }
    double total = 0;
    for (unsigned k = 1; k < h->hdg_n; k++) {
        double newer = h->hdg_v[(h->hdg_head + KELP_HELM_HDG_HIST - k + 1) % KELP_HELM_HDG_HIST];
        double older = h->hdg_v[(h->hdg_head + KELP_HELM_HDG_HIST - k) % KELP_HELM_HDG_HIST];
        total += angle180(newer - older);
    }
    sink(h, "TURN_RATE", false, NULL, h->hdg_n > 1 ? total / (double)(h->hdg_n - 1) : 0.0, NULL);
}

/* before the decision (out of line: not in kelp_helm_iterate's frame) */
KELP_NOINLINE static void post_ledger_and_turn_rate(kelp_helm *h, kelp_time now)
{
    if (kelp_helm_ib_find(&h->ib, "NAV_X") >= 0 && kelp_helm_ib_find(&h->ib, "NAV_Y") >= 0)
        post_ledger_summary(h);
    if (h->engaged)
        post_turn_rate(h, now);
}

/* IVPHELM_COMPLETED_PENDING on change: true in the iteration a behaviour completed; then
 * IVPHELM_COMPLETED_COUNT on change: how many completed in this iteration (24.8: the number its
 * behaviour set removed), both with the iteration as source aux */
static void post_completed_pending(kelp_helm *h)
{
    unsigned n = 0;
    for (unsigned i = 0; i < h->nbhv; i++)
        n += h->bhv[i].completed;
    unsigned now_done = n > h->ncompleted_seen ? n - h->ncompleted_seen : 0;
    int pending = now_done > 0;
    h->ncompleted_seen = n;
    char it[24];
    hx_fmt_ulong(it, sizeof it, h->dec_iter);
    if (pending != h->completed_pending_posted) {
        sink(h, "IVPHELM_COMPLETED_PENDING", true, pending ? "true" : "false", 0, it);
        h->completed_pending_posted = pending;
    }
    if (now_done != h->completed_count_posted) {
        sink(h, "IVPHELM_COMPLETED_COUNT", false, NULL, (double)now_done, it);
        h->completed_count_posted = now_done;
    }
}

/* one of the behaviours' information variables, in 24.8's order: IVPHELM_REGISTER once each */
static void info_var(const char *var, size_t len, void *user)
{
    kelp_helm *h = user;
    if (helm_need_var(h, var, len) != 0)
        return;
    for (unsigned i = 0; i < h->nneed; i++)
        if (strlen(h->need[i]) == len && !memcmp(h->need[i], var, len)) {
            if (!h->info_posted[i]) {
                h->info_posted[i] = 1;
                sink(h, "IVPHELM_REGISTER", true, h->need[i], 0, NULL);
            }
            return;
        }
}

static void info_name(kelp_helm *h, const char *var)
{
    if (var[0])
        info_var(var, strlen(var), h);
}

/* IVPHELM_REGISTER as 24.8's registerNewVariables at each engaged iteration: the behaviours'
 * information variables not announced before (BehaviorSet::getNewInfoVars), in its order: per
 * behaviour the variables of its conditions, its duration_reset variable, then the ones it adds
 * itself (BHV_Waypoint NAV_X, NAV_Y, NAV_SPEED; BHV_Loiter NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED;
 * a contact behaviour BHV_ABLE_FILTER), its updates variable and a waypoint's lead_condition
 * variables; then the variables of the mode declarations' conditions. The walk is made again
 * only when behaviours were added (spawned). */
KELP_NOINLINE static void post_info_vars(kelp_helm *h)
{
    if (h->info_walked == h->bhv_cnt_ever + 1)
        return;
    h->info_walked = h->bhv_cnt_ever + 1;
    for (unsigned i = 0; i < h->nbhv; i++) {
        const kelp_bhv *b = &h->bhv[i];
        for (unsigned k = 0; k < b->ncond; k++)
            KELP_IGNORE(kelp_helm_cond_check(b->cond[k], info_var, h));
        info_name(h, b->duration_reset_var);
        if (b->ops == &kelp_bhv_waypoint_ops || b->ops == &kelp_bhv_loiter_ops) {
            info_name(h, "NAV_X");
            info_name(h, "NAV_Y");
            if (b->ops == &kelp_bhv_loiter_ops)
                info_name(h, "NAV_HEADING");
            info_name(h, "NAV_SPEED");
        } else if (b->ops == &kelp_bhv_avoid_collision_ops)
            info_name(h, "BHV_ABLE_FILTER");
        info_name(h, b->updates);
        if (b->ops == &kelp_bhv_waypoint_ops)
            for (unsigned k = 0; k < b->u.wpt.nlead_cond; k++)
                KELP_IGNORE(kelp_helm_cond_check(b->u.wpt.lead_cond[k], info_var, h));
    }
    for (unsigned m = 0; m < h->nmodes; m++)
        for (unsigned k = 0; k < h->modes[m].ncond; k++)
            KELP_IGNORE(kelp_helm_cond_check(h->modes[m].cond[k], info_var, h));
}

int kelp_helm_iterate(kelp_helm *h, kelp_time now)
{
    if (!h || !kelp_util_time_ok(now))
        return KELP_ERR_ARG;
    if (!h->started)
        kelp_helm_start(h, now);
    /* the time step rule: a step back, or forward beyond KELP_TIME_STEP_MAX, is not helm time.
     * Helm time (durations, perpetual and idle decay, updates, starve times, the IB's stamps)
     * carries on from the last iteration; t0 + helm time stays the caller's clock */
    double step = kelp_util_clock_step(&h->clock, now, KELP_TIME_STEP_MAX);
    if (step != 0.0) {
        h->t0 += step;
        h->clock_steps++;
    }
    h->iteration++;
    h->ib.curr_time = now - h->t0;
    if (h->iteration == 1)
        h->first_iter_time = h->ib.curr_time;
    for (unsigned i = 0; i < h->ib.nvar; i++)
        if (h->ib.var[i].pending) {
            h->ib.var[i].time = h->ib.curr_time;
            h->ib.var[i].pending = false;
        }
    if (h->iteration == 1)
        for (unsigned i = 0; i < h->ninit; i++)
            if (h->init_defer[i] && kelp_helm_ib_find(&h->ib, h->init[i].var) < 0)
                post_init(h, &h->init[i]);
    helm_ledger_update(h);
    helm_mode_eval(h, post_mode);
    helm_spawn(h);
    kelp_helm_report *r = &h->rep;
    report_reset(r);
    if (h->engaged) /* 24.8's helm iteration counts its decisions (HelmEngine), not parked loops */
        h->dec_iter++;
    r->iteration = h->dec_iter;
    r->time = h->ib.curr_time;
    sink(h, "IVPHELM_STATE", true, h->engaged ? "DRIVE" : "PARK", 0, NULL);
    post_ledger_and_turn_rate(h, now);
    double (*clk)(void *) = h->cfg.cpu_clock;
    /* the CPU clock's readings wait in the report (loop_time: the start; solve_time: the end of
     * building) until the end is read: no doubles kept on this frame across the behaviours */
    r->loop_time = clk ? clk(h->cfg.user) : 0;
    if (h->engaged) {
        post_info_vars(h);
        bool *has_fn = h->ws_has_fn;
        memset(has_fn, 0, sizeof h->ws_has_fn);
        size_t pool_used = 0;
        for (unsigned i = 0; i < h->nbhv; i++) {
            if (h->config_pending && h->bhv[i].ops->post_config)
                h->bhv[i].ops->post_config(&h->bhv[i]);
            has_fn[i] = produce(h, i, &pool_used, &r->halted);
            if (has_fn[i])
                r->pcs_formed += h->fn[i].n;
        }
        h->config_pending = false;
        flush_posts(h);
        if (h->startup_events_pending) { /* after the behaviours' postings, as 24.8 */
            h->startup_events_pending = false;
            for (unsigned i = 0; i < h->nbhv; i++)
                helm_life_event(h, h->bhv[i].name, h->bhv[i].type, "spawn", "helm_startup");
        }
        r->solve_time = clk ? clk(h->cfg.user) : 0;
        if (r->halted) { /* MOOS-IvP's halt message names the behaviour error */
            /* "BHV_ERROR: " (11 bytes) then the value, cut as in a buffer of sizeof halt_msg - 12 */
            char *err = r->halt_msg + hx_cat(r->halt_msg, sizeof r->halt_msg, "BHV_ERROR: ", HX_END);
            if (!kelp_helm_ib_string(&h->ib, "BHV_ERROR", err, sizeof r->halt_msg - 12))
                hx_copy(err, sizeof r->halt_msg - 12, " - unknown - ", 13);
        } else
            solve(h, has_fn);
        post_listen_vars(h);
        if (clk) {
            double t_end = clk(h->cfg.user), t_start = r->loop_time, t_built = r->solve_time;
            r->create_time = t_built - t_start;
            r->solve_time = t_end - t_built;
            r->loop_time = t_end - t_start;
        }
    } else {
        h->nq = 0;
        h->qpool_used = 0;
        r->loop_time = 0; /* (held the clock's start reading) */
    }
    post_outputs(h);
    helm_reap(h);
    kelp_helm_ib_clear_deltas(&h->ib);
    return 0;
}
