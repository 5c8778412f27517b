/* uTimerScript's logic (include/kelp/timerscript.h): configuration parsing, scheduling,
 * macro expansion and the iteration. Times follow MOOS-IvP's uTimerScript: a forward of N
 * seconds and the time spent paused are real (MOOS) seconds, scaled by time_warp with the rest. */
#include <math.h>
#include <string.h>
#include <kelp/kv.h>
#include <kelp/timerscript.h>
#include <kelp/util.h>
#include "field_int.h"

#define TS_RAND_DIGITS_MAX 20 /* $(1) .. $(20) */

static bool key_is(const char *k, size_t kl, const char *z) { return kelp_util_strieq_n(k, kl, z); }

static int copy_name(char *dst, const char *v, size_t vl, kelp_diag *d)
{
    for (size_t i = 0; i < vl; i++)
        if (v[i] == ' ' || v[i] == '\t' || v[i] == ',' || v[i] == '=') {
            return kelp_fail(d, KELP_ERR_PARSE, "a variable name has no white space, ',' or '='");
        }
    if (vl == 0 || field_copy_text(dst, KELP_MAX_NAME, v, vl) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, vl ? "name too long" : "empty name");
    }
    return KELP_OK;
}

/* "A" or "A:B" with lo <= A <= B */
static int parse_span(const char *v, size_t vl, double lo, kelp_timerscript_span *out, kelp_diag *d)
{
    const char *colon = memchr(v, ':', vl);
    size_t al = colon ? (size_t)(colon - v) : vl;
    double a, b;
    if (kelp_util_parse_finite(v, al, &a) < 0 ||
        (colon ? kelp_util_parse_finite(colon + 1, vl - al - 1, &b) < 0 : (b = a, false))) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected a number or a range A:B");
    }
    if (a < lo || b < a) {
        return kelp_fail(d, KELP_ERR_PARSE, lo > 0 ? "expected 0 < A <= B" : "expected 0 <= A <= B");
    }
    if (lo > 0 && a <= 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected 0 < A <= B");
    }
    out->min = a, out->max = b;
    return KELP_OK;
}

static void copy_cut(char dst[KELP_MAX_NAME], const char *s)
{
    size_t n = strlen(s);
    if (n >= KELP_MAX_NAME) n = KELP_MAX_NAME - 1;
    memcpy(dst, s, n);
    dst[n] = 0;
}

void kelp_timerscript_cfg_default(kelp_timerscript_cfg *c, const char *app_name, const char *community)
{
    memset(c, 0, sizeof *c);
    copy_cut(c->app_name, app_name ? app_name : "uTimerScript");
    copy_cut(c->community, community ? community : "");
    memcpy(c->script_name, "unnamed", 8);
    memcpy(c->var_forward, "UTS_FORWARD", 12);
    memcpy(c->var_pause, "UTS_PAUSE", 10);
    memcpy(c->var_reset, "UTS_RESET", 10);
    memcpy(c->var_status, "UTS_STATUS", 11);
    memcpy(c->var_next, "UTS_NEXT", 9);
    c->shuffle = true;
    c->verbose = true;
    c->upon_awake = KELP_TS_AWAKE_NA;
    c->reset_max = -1;
    c->reset_time = -1;
    c->warp = (kelp_timerscript_span){ 1, 1 };
}

/* ---- event = var=..., val=..., time=..., amt=..., quit ---- */

/* "$[IDX]" / "$(IDX)" / "$$IDX" -> the event's index, 3 digits */
static int put_idx(char *dst, const char *src, unsigned idx, kelp_diag *d)
{
    static const char *const forms[] = { "$[IDX]", "$(IDX)", "$$IDX" };
    size_t n = 0;
    while (*src) {
        size_t fl = 0;
        for (unsigned k = 0; k < 3 && !fl; k++)
            if (strncmp(src, forms[k], strlen(forms[k])) == 0) fl = strlen(forms[k]);
        size_t need = fl ? 3 : 1;
        if (n + need + 1 > KELP_TS_MAX_VAL) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "event value too long");
        }
        if (fl) {
            dst[n++] = (char)('0' + (idx / 100) % 10);
            dst[n++] = (char)('0' + (idx / 10) % 10);
            dst[n++] = (char)('0' + idx % 10);
            src += fl;
        } else {
            dst[n++] = *src++;
        }
    }
    dst[n] = 0;
    return KELP_OK;
}

int kelp_timerscript_cfg_add_event(kelp_timerscript_cfg *c, const char *spec, kelp_diag *d)
{
    kelp_timerscript_event e;
    memset(&e, 0, sizeof e);
    const char *val = NULL;
    size_t vall = 0;
    long amt = 1;
    size_t pos = 0, len = strlen(spec), il;
    const char *it;
    int rc;
    while ((rc = field_next_item(spec, len, &pos, ',', &it, &il)) == 1) {
        if (key_is(it, il, "quit")) {
            e.quit = true;
            continue;
        }
        const char *eq = memchr(it, '=', il);
        if (!eq) {
            return kelp_fail(d, KELP_ERR_PARSE, "event item without '='");
        }
        const char *k = it, *v = eq + 1;
        size_t kl = (size_t)(eq - it), vl = il - kl - 1;
        while (kl && (k[kl - 1] == ' ' || k[kl - 1] == '\t')) kl--;
        while (vl && (*v == ' ' || *v == '\t')) v++, vl--;
        if (key_is(k, kl, "var")) {
            if (copy_name(e.var, v, vl, d) < 0) return KELP_ERR_PARSE;
        } else if (key_is(k, kl, "val")) {
            val = v, vall = vl;
        } else if (key_is(k, kl, "amt")) {
            if (kelp_util_parse_long(v, vl, &amt) < 0 || amt < 1 || amt > KELP_TS_MAX_EVENTS) {
                return kelp_fail(d, KELP_ERR_PARSE, "amt must be a whole number from 1");
            }
        } else if (key_is(k, kl, "time")) {
            kelp_timerscript_span s = { 0, 0 };
            if (parse_span(v, vl, 0, &s, d) < 0) return KELP_ERR_PARSE;
            e.tmin = s.min, e.tmax = s.max;
        } else {
            return kelp_fail(d, KELP_ERR_PARSE, "unknown event key (var, val, time, amt, quit)");
        }
    }
    if (rc < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "unbalanced quote or brace in the event");
    }
    if (e.quit) {
        memcpy(e.var, "EXITED_NORMALLY", 16);
        (void)field_copy_text(e.val, sizeof e.val, c->app_name, strlen(c->app_name));
        e.quoted = true;
    } else {
        if (!e.var[0]) {
            return kelp_fail(d, KELP_ERR_PARSE, "event without var=");
        }
        if (!val || vall == 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "event without val=");
        }
        if (vall >= 2 && val[0] == '"' && val[vall - 1] == '"') val++, vall -= 2, e.quoted = true;
        if (field_copy_text(e.val, sizeof e.val, val, vall) < 0) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "event value too long");
        }
    }
    if (c->nev + (unsigned long)amt > KELP_TS_MAX_EVENTS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many events");
    }
    for (long i = 0; i < amt; i++) {
        kelp_timerscript_event *ev = &c->ev[c->nev];
        *ev = e;
        if (put_idx(ev->val, e.val, c->nev, d) < 0) return KELP_ERR_NOSPACE;
        c->nev++;
    }
    return KELP_OK;
}

/* ---- rand_var = varname=X, min=.., max=.., key=at_post|at_start|at_reset ---- */

int kelp_timerscript_cfg_add_randvar(kelp_timerscript_cfg *c, const char *spec, kelp_diag *d)
{
    kelp_timerscript_randvar v;
    memset(&v, 0, sizeof v);
    v.key = -1;
    v.snap = 0.001;
    v.sigma = 1;
    bool have_min = false, have_max = false, have_mu = false, have_sigma = false;
    size_t pos = 0, kl, vl;
    const char *k, *val;
    int rc;
    while ((rc = kelp_kv_next(spec, ',', &pos, &k, &kl, &val, &vl)) == 1) {
        double dv = 0;
        bool num = kelp_util_parse_finite(val, vl, &dv) == 0;
        if (key_is(k, kl, "varname")) {
            if (copy_name(v.name, val, vl, d) < 0) return KELP_ERR_PARSE;
        } else if (key_is(k, kl, "key")) {
            if (key_is(val, vl, "at_start")) v.key = KELP_TS_RV_AT_START;
            else if (key_is(val, vl, "at_reset")) v.key = KELP_TS_RV_AT_RESET;
            else if (key_is(val, vl, "at_post")) v.key = KELP_TS_RV_AT_POST;
            else {
                return kelp_fail(d, KELP_ERR_PARSE, "key must be at_start, at_reset or at_post");
            }
        } else if (key_is(k, kl, "type")) {
            if (key_is(val, vl, "uniform")) v.type = KELP_TS_RV_UNIFORM;
            else if (key_is(val, vl, "gaussian") || key_is(val, vl, "normal")) v.type = KELP_TS_RV_GAUSSIAN;
            else {
                return kelp_fail(d, KELP_ERR_PARSE, "type must be uniform or gaussian");
            }
        } else if (num && key_is(k, kl, "min")) {
            v.min = dv, have_min = true;
        } else if (num && key_is(k, kl, "max")) {
            v.max = dv, have_max = true;
        } else if (num && key_is(k, kl, "mu")) {
            v.mu = dv, have_mu = true;
        } else if (num && key_is(k, kl, "sigma")) {
            v.sigma = dv, have_sigma = true;
        } else if (num && key_is(k, kl, "snap")) {
            if (dv > 0) v.snap = dv;
        } else {
            return kelp_fail(d, KELP_ERR_PARSE, "unknown key or not a number (varname, key, type, min, max, mu, sigma, snap)");
        }
    }
    if (rc < 0) return kelp_fail(d, KELP_ERR_PARSE, "item without '='");
    if (v.key < 0) return kelp_fail(d, KELP_ERR_PARSE, "key (at_start, at_reset or at_post) is required");
    if (!v.name[0]) return kelp_fail(d, KELP_ERR_PARSE, "varname is required");
    if (!have_min || !have_max) return kelp_fail(d, KELP_ERR_PARSE, "min and max are required");
    if (v.min > v.max) return kelp_fail(d, KELP_ERR_PARSE, "min is greater than max");
    if (v.type == KELP_TS_RV_GAUSSIAN && (!have_mu || !have_sigma)) return kelp_fail(d, KELP_ERR_PARSE, "a gaussian needs mu and sigma");
    if (v.type == KELP_TS_RV_GAUSSIAN && v.sigma < 0) return kelp_fail(d, KELP_ERR_PARSE, "sigma is negative");
    for (unsigned i = 0; i < c->nrv; i++)
        if (kelp_util_strieq(c->rv[i].name, v.name)) {
            return kelp_fail(d, KELP_ERR_PARSE, "duplicate random variable");
        }
    if (c->nrv >= KELP_TS_MAX_RANDVARS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "too many random variables");
    }
    c->rv[c->nrv++] = v;
    return KELP_OK;
}

/* ---- the other parameters ---- */

static int set_var(char *dst, const char *v, kelp_diag *d) { return copy_name(dst, v, strlen(v), d); }

static int set_bool(bool *dst, const char *v, kelp_diag *d)
{
    if (kelp_util_parse_bool(v, strlen(v), dst) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected true or false");
    }
    return 1;
}

static int add_block(kelp_timerscript_cfg *c, const char *v, kelp_diag *d)
{
    size_t pos = 0, len = strlen(v), il;
    const char *it;
    int rc;
    while ((rc = field_next_item(v, len, &pos, ',', &it, &il)) == 1) {
        for (unsigned i = 0; i < c->nblock; i++)
            if (kelp_util_strieq_n(it, il, c->block[i])) {
                return kelp_fail(d, KELP_ERR_PARSE, "duplicate block_on app");
            }
        if (c->nblock >= KELP_TS_MAX_BLOCK) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "too many block_on apps");
        }
        if (copy_name(c->block[c->nblock], it, il, d) < 0) return KELP_ERR_PARSE;
        c->nblock++;
    }
    return rc < 0 ? kelp_fail(d, KELP_ERR_PARSE, "unbalanced quote") : 1;
}

int kelp_timerscript_cfg_set(kelp_timerscript_cfg *c, const char *key, const char *v, kelp_diag *d)
{
    size_t vl = strlen(v);
    kelp_timerscript_span s;
    if (kelp_util_strieq(key, "event")) return kelp_timerscript_cfg_add_event(c, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "rand_var") || kelp_util_strieq(key, "randvar"))
        return kelp_timerscript_cfg_add_randvar(c, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "paused")) return set_bool(&c->paused, v, d);
    if (kelp_util_strieq(key, "script_atomic")) return set_bool(&c->atomic, v, d);
    if (kelp_util_strieq(key, "shuffle")) return set_bool(&c->shuffle, v, d);
    if (kelp_util_strieq(key, "verbose")) return set_bool(&c->verbose, v, d);
    if (kelp_util_strieq(key, "upon_awake")) {
        if (kelp_util_strieq(v, "reset")) c->upon_awake = KELP_TS_AWAKE_RESET;
        else if (kelp_util_strieq(v, "restart")) c->upon_awake = KELP_TS_AWAKE_RESTART;
        else if (kelp_util_strieq(v, "n/a")) c->upon_awake = KELP_TS_AWAKE_NA;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected reset, restart or n/a");
        }
        return 1;
    }
    if (kelp_util_strieq(key, "time_zero")) {
        if (kelp_util_strieq(v, "db_start")) c->time_zero_db = true;
        else if (kelp_util_strieq(v, "script_start")) c->time_zero_db = false;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected db_start or script_start");
        }
        return 1;
    }
    if (kelp_util_strieq(key, "reset_max")) {
        long n;
        if (kelp_util_strieq(v, "nolimit") || kelp_util_strieq(v, "any") || kelp_util_strieq(v, "unlimited")) c->reset_max = -1;
        else if (kelp_util_parse_long(v, vl, &n) == 0 && n >= 0) c->reset_max = n;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected a whole number >= 0 or nolimit");
        }
        return 1;
    }
    if (kelp_util_strieq(key, "reset_time")) {
        double dv;
        if (kelp_util_strieq(v, "all-posted") || kelp_util_strieq(v, "end")) c->reset_time = 0;
        else if (kelp_util_strieq(v, "none")) c->reset_time = -1;
        else if (kelp_util_parse_finite(v, vl, &dv) == 0 && dv > 0) c->reset_time = dv;
        else {
            return kelp_fail(d, KELP_ERR_PARSE, "expected none, all-posted or seconds > 0");
        }
        return 1;
    }
    if (kelp_util_strieq(key, "script_name")) {
        if (vl == 0 || field_copy_text(c->script_name, sizeof c->script_name, v, vl) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "empty or too long");
        }
        return 1;
    }
    if (kelp_util_strieq(key, "forward_var") || kelp_util_strieq(key, "forward_variable"))
        return set_var(c->var_forward, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "reset_var") || kelp_util_strieq(key, "reset_variable"))
        return set_var(c->var_reset, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "pause_var") || kelp_util_strieq(key, "pause_variable"))
        return set_var(c->var_pause, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "status_var")) return set_var(c->var_status, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "next_var")) return set_var(c->var_next, v, d) < 0 ? KELP_ERR_PARSE : 1;
    if (kelp_util_strieq(key, "block_on")) return add_block(c, v, d);
    if (kelp_util_strieq(key, "time_warp") || kelp_util_strieq(key, "delay_start") || kelp_util_strieq(key, "delay_reset")) {
        bool warp = kelp_util_strieq(key, "time_warp");
        if (parse_span(v, vl, warp ? 1e-9 : 0, &s, d) < 0) return KELP_ERR_PARSE;
        *(warp ? &c->warp : kelp_util_strieq(key, "delay_start") ? &c->delay_start : &c->delay_reset) = s;
        return 1;
    }
    if (kelp_util_strieq(key, "condition")) {
        if (c->ncond >= KELP_TS_MAX_CONDS) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "too many conditions");
        }
        if (kelp_helm_cond_check(v, NULL, NULL) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "not a logic condition (e.g. NAV_SPEED > 0, (A = true) and (B != x))");
        }
        if (field_copy_text(c->cond[c->ncond], sizeof c->cond[0], v, vl) < 0) {
            return kelp_fail(d, KELP_ERR_NOSPACE, "condition too long");
        }
        c->ncond++;
        return 1;
    }
    return 0;
}

/* ---- state ---- */

static void add_sub(kelp_timerscript *r, const char *name, size_t len)
{
    if (len == 0 || len >= KELP_MAX_NAME) return;
    for (unsigned i = 0; i < r->nsub; i++)
        if (strlen(r->sub[i]) == len && memcmp(r->sub[i], name, len) == 0) return;
    if (r->nsub >= KELP_TS_MAX_SUBS) return;
    memcpy(r->sub[r->nsub], name, len);
    r->sub[r->nsub][len] = 0;
    r->nsub++;
}

static void on_cond_var(const char *var, size_t len, void *user) { add_sub(user, var, len); }

static double draw(kelp_timerscript *r, kelp_timerscript_span s) { return s.max > s.min ? s.min + kelp_rng_uniform(&r->rng) * (s.max - s.min) : s.min; }

static void draw_randvars(kelp_timerscript *r, int key)
{
    for (unsigned i = 0; i < r->cfg.nrv; i++) {
        const kelp_timerscript_randvar *v = &r->cfg.rv[i];
        if (v->key != key) continue;
        double x = v->type == KELP_TS_RV_GAUSSIAN ? kelp_rng_gauss(&r->rng, v->mu, v->sigma)
                                                  : draw(r, (kelp_timerscript_span){ v->min, v->max });
        x = floor(x / v->snap + 0.5) * v->snap;
        if (x < v->min) x = v->min;
        if (x > v->max) x = v->max;
        r->rv_val[i] = x;
        if (kelp_util_fmt_fixed(r->rv_text[i], sizeof r->rv_text[i], x, v->type == KELP_TS_RV_GAUSSIAN ? 5 : 3, true) < 0)
            memcpy(r->rv_text[i], "nan", 4);
    }
}

/* does an event value hold $[name] or $(name)? */
static bool uses(const kelp_timerscript_cfg *c, const char *name)
{
    size_t n = strlen(name);
    for (unsigned i = 0; i < c->nev; i++)
        for (const char *p = strchr(c->ev[i].val, '$'); p; p = strchr(p + 1, '$'))
            if ((p[1] == '[' || p[1] == '(') && strncmp(p + 2, name, n) == 0 && p[2 + n] == (p[1] == '[' ? ']' : ')'))
                return true;
    return false;
}

int kelp_timerscript_init(kelp_timerscript *r, const kelp_timerscript_cfg *c, uint64_t seed)
{
    memset(r, 0, sizeof *r);
    r->cfg = *c;
    kelp_rng_seed(&r->rng, seed);
    kelp_helm_ib_init(&r->ib);
    r->paused = c->paused;
    r->conds_ok = c->ncond == 0;
    r->prev = -1;
    r->warp = c->warp.min;
    const char *cmd[] = { c->var_forward, c->var_pause, c->var_reset, c->var_next, "DB_UPTIME" };
    for (unsigned i = 0; i < 5; i++) add_sub(r, cmd[i], strlen(cmd[i]));
    if (c->nblock) add_sub(r, "DB_CLIENTS", 10);
    for (unsigned i = 0; i < c->nblock; i++) {
        char st[KELP_MAX_NAME + 8];
        size_t n = strlen(c->block[i]);
        for (size_t k = 0; k < n; k++) st[k] = (c->block[i][k] >= 'a' && c->block[i][k] <= 'z') ? (char)(c->block[i][k] - 32) : c->block[i][k];
        memcpy(st + n, "_STATUS", 8);
        add_sub(r, st, n + 7);
    }
    if (uses(c, "NAV_X")) add_sub(r, "NAV_X", 5);
    if (uses(c, "NAV_Y")) add_sub(r, "NAV_Y", 5);
    for (unsigned i = 0; i < c->ncond; i++)
        if (kelp_helm_cond_check(c->cond[i], on_cond_var, r) < 0) return KELP_ERR_PARSE;
    r->blocked_any = c->nblock > 0;
    draw_randvars(r, KELP_TS_RV_AT_START);
    draw_randvars(r, KELP_TS_RV_AT_RESET);
    draw_randvars(r, KELP_TS_RV_AT_POST);
    return KELP_OK;
}

const char *kelp_timerscript_subscription(const kelp_timerscript *r, unsigned i) { return i < r->nsub ? r->sub[i] : NULL; }

void kelp_timerscript_set_db_start(kelp_timerscript *r, double t)
{
    r->db_start = t;
    r->db_set = true;
}

static void warn(const kelp_field_sink *out, const char *msg)
{
    if (out && out->warn) out->warn(out->ctx, msg);
}

/* script time of the next unposted event (its delay included), or -1 */
static double next_time(const kelp_timerscript *r)
{
    double delay = r->resets ? r->delay_reset : r->delay_start, best = -1;
    for (unsigned i = 0; i < r->cfg.nev; i++)
        if (!r->posted[i] && (best < 0 || r->t[i] + delay < best)) best = r->t[i] + delay;
    return best;
}

static void reset(kelp_timerscript *r)
{
    if (r->cfg.reset_max >= 0 && r->resets >= (unsigned long)r->cfg.reset_max) return;
    r->resets++;
    r->status_due = true;
    r->started = false;
}

static void block_clear(kelp_timerscript *r, const char *app, size_t len)
{
    bool any = false;
    for (unsigned i = 0; i < r->cfg.nblock; i++) {
        if (kelp_util_strieq_n(app, len, r->cfg.block[i])) r->block_seen[i] = true;
        any = any || !r->block_seen[i];
    }
    r->blocked_any = any;
}

int kelp_timerscript_mail(kelp_timerscript *r, const char *var, bool is_string, const char *sval, double dval, kelp_time now,
                 const kelp_field_sink *out)
{
    const kelp_timerscript_cfg *c = &r->cfg;
    double d = dval;
    bool num = !is_string || kelp_util_parse_finite(sval, strlen(sval), &d) == 0;
    if (strcmp(var, c->var_forward) == 0) {
        if (!num || !isfinite(d)) {
            r->bad_mail++;
            warn(out, "forward: not a number of seconds");
            return KELP_ERR_PARSE;
        }
        if (d <= 0) {
            double nt = next_time(r);
            if (nt > r->elapsed && r->warp > 0) r->skip += (nt - r->elapsed) / r->warp;
        } else {
            r->skip += d;
        }
        return 1;
    }
    if (strcmp(var, c->var_next) == 0) {
        double nt = next_time(r);
        if (nt > r->elapsed && r->warp > 0) r->skip += (nt - r->elapsed) / r->warp;
        return 1;
    }
    if (strcmp(var, c->var_reset) == 0) {
        if (is_string && (kelp_util_strieq(sval, "reset") || kelp_util_strieq(sval, "true"))) reset(r);
        return 1;
    }
    if (strcmp(var, c->var_pause) == 0) {
        if (!is_string || !(kelp_util_strieq(sval, "true") || kelp_util_strieq(sval, "false") || kelp_util_strieq(sval, "toggle"))) {
            r->bad_mail++;
            warn(out, "pause: expected true, false or toggle");
            return KELP_ERR_PARSE;
        }
        r->paused = kelp_util_strieq(sval, "toggle") ? !r->paused : kelp_util_strieq(sval, "true");
        if (kelp_helm_ib_set_string(&r->ib, var, sval, now, false) < 0) r->bad_mail++;
        return 1;
    }
    int used = 0;
    if (strcmp(var, "DB_UPTIME") == 0 && num) {
        if (!r->db_from_mail) r->db_start = now - d, r->db_set = r->db_from_mail = true;
        used = 1;
    } else if (strcmp(var, "DB_CLIENTS") == 0 && is_string) {
        size_t pos = 0, len = strlen(sval), il;
        const char *it;
        while (field_next_item(sval, len, &pos, ',', &it, &il) == 1) block_clear(r, it, il);
        used = 1;
    } else if (strcmp(var, "NAV_X") == 0 && num) {
        r->nav_x = d, used = 1;
    } else if (strcmp(var, "NAV_Y") == 0 && num) {
        r->nav_y = d, used = 1;
    } else {
        size_t vl = strlen(var);
        if (vl > 7 && strcmp(var + vl - 7, "_STATUS") == 0) {
            for (unsigned i = 0; i < c->nblock; i++)
                if (kelp_util_strieq_n(var, vl - 7, c->block[i])) block_clear(r, var, vl - 7), used = 1;
        }
    }
    /* every value is kept for the conditions */
    int rc = is_string ? kelp_helm_ib_set_string(&r->ib, var, sval, now, false)
                       : kelp_helm_ib_set_double(&r->ib, var, dval, now, false);
    if (rc == 0) used = 1;
    return used;
}

/* ---- expansion ---- */

typedef struct obuf {
    char *b;
    size_t cap, n;
    bool full;
} obuf;

static void put(obuf *o, const char *s, size_t len)
{
    if (o->n + len + 1 > o->cap) {
        o->full = true;
        return;
    }
    memcpy(o->b + o->n, s, len);
    o->n += len;
    o->b[o->n] = 0;
}

static void put_num(obuf *o, double v, unsigned dec)
{
    char t[48];
    int k = kelp_util_fmt_fixed(t, sizeof t, v, dec, dec != 2);
    if (k < 0 || (size_t)k >= sizeof t) o->full = true;
    else put(o, t, (size_t)k);
}

/* the value of macro name[0..nl), written to o; false when it is no macro */
static bool macro(kelp_timerscript *r, const char *name, size_t nl, kelp_time now, obuf *o)
{
    if (kelp_util_strieq_n(name, nl, "DBTIME")) put_num(o, now - r->db_start, 2);
    else if (kelp_util_strieq_n(name, nl, "UTCTIME") || kelp_util_strieq_n(name, nl, "UTC")) put_num(o, now, 2);
    else if (kelp_util_strieq_n(name, nl, "TCOUNT")) put_num(o, (double)r->posted_total, 0);
    else if (kelp_util_strieq_n(name, nl, "COUNT")) put_num(o, (double)r->posted_local, 0);
    else if (kelp_util_strieq_n(name, nl, "NAV_X")) put_num(o, r->nav_x, 2);
    else if (kelp_util_strieq_n(name, nl, "NAV_Y")) put_num(o, r->nav_y, 2);
    else if (kelp_util_strieq_n(name, nl, "VNAME")) put(o, r->cfg.community, strlen(r->cfg.community));
    else {
        long digits;
        if (kelp_util_parse_long(name, nl, &digits) == 0 && digits >= 1 && digits <= TS_RAND_DIGITS_MAX && name[0] != ' ') {
            char t[TS_RAND_DIGITS_MAX];
            size_t k = 0;
            for (long i = 0; i < digits; i++) {
                unsigned dgt = (unsigned)(kelp_rng_next(&r->rng) % 10);
                if (dgt || k) t[k++] = (char)('0' + dgt);
            }
            put(o, t, k);
            return true;
        }
        for (unsigned i = 0; i < r->cfg.nrv; i++)
            if (strlen(r->cfg.rv[i].name) == nl && memcmp(r->cfg.rv[i].name, name, nl) == 0) {
                put(o, r->rv_text[i], strlen(r->rv_text[i]));
                return true;
            }
        return false;
    }
    return true;
}

/* one innermost "{a op b}" replaced by its value; false when there is none that evaluates */
static bool math_pass(char *s, size_t cap)
{
    char *open = NULL, *close = NULL;
    for (char *p = s; *p; p++) {
        if (*p == '{') open = p;
        else if (*p == '}' && open) {
            close = p;
            break;
        }
    }
    if (!open || !close) return false;
    const char *e = open + 1;
    size_t el = (size_t)(close - e);
    while (el && (*e == ' ' || *e == '\t')) e++, el--;
    while (el && (e[el - 1] == ' ' || e[el - 1] == '\t')) el--;
    bool neg = false;
    if (el && (*e == '+' || *e == '-')) neg = *e == '-', e++, el--;
    const char *op = NULL;
    for (const char *ops = "*/+-"; *ops && !op; ops++) op = memchr(e, *ops, el);
    if (!op) return false;
    double a, b, v;
    if (kelp_util_parse_finite(e, (size_t)(op - e), &a) < 0 || kelp_util_parse_finite(op + 1, el - (size_t)(op - e) - 1, &b) < 0)
        return false;
    if (neg) a = -a;
    switch (*op) {
    case '*': v = a * b; break;
    case '/': v = a / b; break;
    case '+': v = a + b; break;
    default: v = a - b; break;
    }
    char t[48];
    int k = isfinite(v) ? kelp_util_fmt_fixed(t, sizeof t, v, 6, true) : -1;
    if (k < 0 || (size_t)k >= sizeof t) return false;
    size_t tail = strlen(close + 1), head = (size_t)(open - s);
    if (head + (size_t)k + tail + 1 > cap) return false;
    memmove(s + head + k, close + 1, tail + 1);
    memcpy(s + head, t, (size_t)k);
    return true;
}

int kelp_timerscript_expand(kelp_timerscript *r, const char *val, kelp_time now, char *out, size_t cap, double *dval)
{
    if (!cap) return KELP_ERR_NOSPACE;
    obuf o = { out, cap, 0, false };
    out[0] = 0;
    draw_randvars(r, KELP_TS_RV_AT_POST); /* a posting draws them, whatever its value */
    /* a lone time or count macro is a number */
    size_t vl = strlen(val);
    if (vl > 3 && val[0] == '$' && ((val[1] == '[' && val[vl - 1] == ']') || (val[1] == '(' && val[vl - 1] == ')'))) {
        const char *nm = val + 2;
        size_t nl = vl - 3;
        if (kelp_util_strieq_n(nm, nl, "DBTIME") || kelp_util_strieq_n(nm, nl, "UTCTIME") || kelp_util_strieq_n(nm, nl, "UTC") ||
            kelp_util_strieq_n(nm, nl, "COUNT") || kelp_util_strieq_n(nm, nl, "TCOUNT")) {
            (void)macro(r, nm, nl, now, &o);
            if (o.full) return KELP_ERR_NOSPACE;
            /* the number posted is the time or count itself; the text (2 decimals) is for the log */
            if (kelp_util_strieq_n(nm, nl, "DBTIME")) *dval = now - r->db_start;
            else if (kelp_util_strieq_n(nm, nl, "UTCTIME") || kelp_util_strieq_n(nm, nl, "UTC")) *dval = now;
            else if (kelp_util_parse_finite(out, o.n, dval) < 0) return 0;
            return 1;
        }
    }
    for (size_t i = 0; i < vl && !o.full;) {
        if (val[i] == '$' && i + 1 < vl && (val[i + 1] == '[' || val[i + 1] == '(')) {
            char cl = val[i + 1] == '[' ? ']' : ')';
            const char *end = memchr(val + i + 2, cl, vl - i - 2);
            if (end && macro(r, val + i + 2, (size_t)(end - val - i - 2), now, &o)) {
                i = (size_t)(end - val) + 1;
                continue;
            }
        }
        put(&o, val + i, 1);
        i++;
    }
    if (o.full) return KELP_ERR_NOSPACE;
    for (int k = 0; k < KELP_TS_MATH_PASSES && math_pass(out, cap); k++) {
    }
    return kelp_util_parse_finite(out, strlen(out), dval) == 0 ? 1 : 0;
}

/* ---- iteration ---- */

static void schedule(kelp_timerscript *r, kelp_time now)
{
    const kelp_timerscript_cfg *c = &r->cfg;
    bool first = !r->drawn;
    if (c->shuffle || first)
        for (unsigned i = 0; i < c->nev; i++) r->t[i] = draw(r, (kelp_timerscript_span){ c->ev[i].tmin, c->ev[i].tmax });
    r->drawn = true;
    r->warp = draw(r, c->warp);
    r->delay_start = draw(r, c->delay_start);
    r->delay_reset = draw(r, c->delay_reset);
    draw_randvars(r, KELP_TS_RV_AT_RESET);
    draw_randvars(r, KELP_TS_RV_AT_POST);
    r->start = (c->time_zero_db && first) ? r->db_start : now;
    r->elapsed = 0;
    r->prev = -1;
    r->skip = 0;
    r->pause_time = 0;
    r->posted_local = 0;
    memset(r->posted, 0, sizeof r->posted);
    r->started = true;
}

static bool conditions(kelp_timerscript *r)
{
    for (unsigned i = 0; i < r->cfg.ncond; i++)
        if (kelp_helm_cond_eval(r->cfg.cond[i], &r->ib) != 1) return false;
    return true;
}

static void post_event(kelp_timerscript *r, unsigned i, kelp_time now, const kelp_field_sink *out)
{
    const kelp_timerscript_event *e = &r->cfg.ev[i];
    char text[KELP_TS_MAX_VAL];
    double d = 0;
    int rc = kelp_timerscript_expand(r, e->val, now, text, sizeof text, &d);
    if (rc < 0) {
        warn(out, "an event's value does not fit once expanded: posted unexpanded");
        (void)field_copy_text(text, sizeof text, e->val, strlen(e->val));
        rc = 0;
    }
    if (e->quit) r->quit = true;
    bool as_num = rc == 1 && !e->quoted;
    out->publish(out->ctx, e->var, !as_num, text, d);
    kelp_timerscript_logline *l = &r->log[r->nlog++ % KELP_TS_LOG];
    l->total = r->posted_total + 1;
    l->local = r->posted_local + 1;
    l->db_time = now - r->db_start;
    l->script_time = r->elapsed;
    size_t n = 0;
    l->text[0] = 0;
    field_putf(l->text, sizeof l->text, &n, "%s = %s", e->var, text);
}

#define TS_STATUS_MAX 400 /* the fixed text, a script name and four numbers */

static void post_status(kelp_timerscript *r, kelp_time now, const kelp_field_sink *out)
{
    char st[TS_STATUS_MAX];
    if (kelp_timerscript_status(r, st, sizeof st) > 0) out->publish(out->ctx, r->cfg.var_status, true, st, 0);
    r->status_ever = true;
    r->status_time = now;
}

int kelp_timerscript_iterate(kelp_timerscript *r, kelp_time now, const kelp_field_sink *out)
{
    const kelp_timerscript_cfg *c = &r->cfg;
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG;
    /* the time step rule: a clock step (back, or forward beyond KELP_TIME_STEP_MAX) is not script
     * time: every reference moves with it, so no event fires early or late by the step, none is
     * posted in a burst, and DBTIME / the status period never run backwards */
    double step = kelp_util_clock_step(&r->clock, now, KELP_TIME_STEP_MAX);
    if (step != 0.0) {
        r->start += step;
        if (r->prev >= 0) r->prev += step;
        r->status_time += step;
        r->db_start += step;
    }
    if (!r->db_set) kelp_timerscript_set_db_start(r, now);
    /* as MOOS-IvP's uTimerScript: the status is owed to what this iteration does (a posting, a
     * change of conditions, a reset it makes, 5 s of silence), not to the mail before it */
    r->status_due = false;
    bool ok = r->conds_ok;
    if (!c->atomic || r->posted_local == 0 || r->posted_local == c->nev) ok = conditions(r);
    if (ok && !r->conds_ok) { /* awakening */
        if (c->upon_awake == KELP_TS_AWAKE_RESET && r->elapsed > 0) reset(r);
        else if (c->upon_awake == KELP_TS_AWAKE_RESTART) {
            r->resets = 0;
            r->started = false;
        }
    }
    if (ok != r->conds_ok) r->status_due = true;
    r->conds_ok = ok;
    if (!r->started) schedule(r, now);
    bool running = !r->paused && r->conds_ok && !r->blocked_any;
    if (!running && r->prev >= 0) r->pause_time += now - r->prev;
    r->prev = now;
    r->elapsed = ((now - r->start) + r->skip - r->pause_time) * r->warp;
    if (!r->status_ever || now - r->status_time > KELP_TS_STATUS_PERIOD) r->status_due = true;
    int posted = 0;
    if (running) {
        double delay = r->resets ? r->delay_reset : r->delay_start;
        bool all = true;
        for (unsigned i = 0; i < c->nev; i++) {
            if (!r->posted[i] && r->elapsed - delay >= r->t[i] && (c->reset_time <= 0 || r->t[i] <= c->reset_time)) {
                post_event(r, i, now, out);
                r->posted[i] = true;
                r->posted_local++;
                r->posted_total++;
                r->status_due = true;
                posted++;
            }
            all = all && r->posted[i];
        }
        if (all && c->reset_time == 0) reset(r);
    }
    if (c->reset_time > 0 && r->elapsed >= c->reset_time) reset(r);
    if (r->status_due && c->var_status[0] && !kelp_util_strieq(c->var_status, "silent")) post_status(r, now, out);
    r->status_due = false;
    return posted;
}

int kelp_timerscript_status(const kelp_timerscript *r, char *buf, size_t cap)
{
    const kelp_timerscript_cfg *c = &r->cfg;
    size_t n = 0;
    static const char *const awake[] = { "n/a", "reset", "restart" };
    field_putf(buf, cap, &n, "name=%s, elapsed_time=", c->script_name);
    int rc = field_put_fixed(buf, cap, &n, r->elapsed, 2, false);
    field_putf(buf, cap, &n, ", posted=%u, pending=%u, paused=%s, conditions_ok=%s, time_warp=", r->posted_local,
               c->nev - r->posted_local, r->paused ? "true" : "false", r->conds_ok ? "true" : "false");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, r->warp, 5, true);
    field_putf(buf, cap, &n, ", delay_start=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, r->delay_start, 5, true);
    field_putf(buf, cap, &n, ", delay_reset=");
    if (rc == 0) rc = field_put_fixed(buf, cap, &n, r->delay_reset, 5, true);
    field_putf(buf, cap, &n, ", shuffle=%s, upon_awake=%s, resets=%lu/", c->shuffle ? "true" : "false",
               awake[c->upon_awake >= 0 && c->upon_awake <= 2 ? c->upon_awake : 0], r->resets);
    if (c->reset_max < 0) field_putf(buf, cap, &n, "any");
    else field_putf(buf, cap, &n, "%ld", c->reset_max);
    if (rc < 0 || n + 1 >= cap) return KELP_ERR_NOSPACE;
    return (int)n;
}
