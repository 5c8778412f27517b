/* kelp helm: hierarchical modes ("set MODE = VAL { conditions } ELSEVAL" in a .bhv file), as
 * MOOS-IvP's helm evaluates them: entries in file order, each seeing the results of the ones
 * before it; a condition on the mode variable itself ("MODE = ACTIVE") makes "ACTIVE" the
 * prefix of the entry's value ("ACTIVE:SURVEYING"). */
#include <string.h>
#include "helm_int.h"

static void mode_need(const char *var, size_t len, void *user)
{
    (void)helm_need_var(user, var, len);
}

/* "set MODE" -> "MODE" */
static bool mode_var_of(const kelp_mission_node *nd, char *out, size_t cap)
{
    const char *k = nd->key + 3;
    size_t n = nd->klen - 3;
    hx_trim(&k, &n);
    if (!hx_varname(k, n))
        return false;
    return hx_copy(out, cap, k, n);
}

int helm_mode_load(kelp_helm *h, const kelp_mission *m, size_t bi)
{
    const kelp_mission_node *nd = &m->nodes[bi];
    if (h->nmodes >= KELP_HELM_MAX_MODES)
        return helm_fail(h, nd->line, KELP_ERR_NOSPACE, "mode declaration: too many mode declarations (KELP_HELM_MAX_MODES)", HX_END);
    kelp_helm_mode *e = &h->modes[h->nmodes];
    memset(e, 0, sizeof *e);
    if (!mode_var_of(nd, e->var, sizeof e->var))
        return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: bad mode variable name", HX_END);
    const char *v = nd->val;
    size_t vl = nd->vlen;
    hx_trim(&v, &vl);
    if (!vl || !hx_copy(e->val, sizeof e->val, v, vl) || strpbrk(e->val, " \t,="))
        return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: mode value must be one word", HX_END);
    for (size_t j = bi + 1; j < m->nnodes; j++) {
        const kelp_mission_node *c = &m->nodes[j];
        if (c->parent != (int)bi)
            continue;
        if (c->kind != KELP_MN_PARAM)
            return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: expected a condition in a mode declaration", HX_END);
        if (c->klen == 5 && !memcmp(c->key, "}else", 5)) {
            if (!hx_copy(e->elseval, sizeof e->elseval, c->val, c->vlen))
                return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: else value too long", HX_END);
            continue;
        }
        if (e->ncond >= KELP_HELM_MAX_CONDS)
            return helm_fail(h, nd->line, KELP_ERR_NOSPACE, "mode declaration: too many conditions in a mode declaration", HX_END);
        /* the parser split "A != b" at its '=': put it back together */
        const char *k = c->key, *cv = c->val;
        size_t kl = c->klen, cvl = c->vlen;
        hx_trim(&k, &kl);
        hx_trim(&cv, &cvl);
        char *dst = e->cond[e->ncond];
        if (kl + cvl + 2 > KELP_HELM_MAX_COND_LEN)
            return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: condition too long", HX_END);
        memcpy(dst, k, kl);
        dst[kl] = '=';
        memcpy(dst + kl + 1, cv, cvl);
        dst[kl + 1 + cvl] = '\0';
        if (kelp_helm_cond_check(dst, mode_need, h) != 0)
            return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: bad condition '", dst, "'", HX_END);
        /* "MODE = ACTIVE" (single '='): the prefix condition */
        if (!e->prefix[0] && kl == strlen(e->var) && !memcmp(k, e->var, kl) && cvl && cv[0] != '=') {
            if (!hx_copy(e->prefix, sizeof e->prefix, cv, cvl))
                return helm_fail(h, nd->line, KELP_ERR_PARSE, "mode declaration: mode prefix too long", HX_END);
            e->modevar_conds |= 1u << e->ncond;
        }
        e->ncond++;
    }
    h->nmodes++;
    return 0;
}

/* Evaluate every entry; results go to the information buffer (seen by later entries and by
 * the behaviours' conditions this iteration) and, when changed, to the sink. */
void helm_mode_eval(kelp_helm *h, void (*post)(kelp_helm *h, const char *var, const char *val))
{
    bool produced[KELP_HELM_MAX_MODES] = { false };
    char (*value)[128] = h->ws_out.mode_value;
    for (unsigned i = 0; i < h->nmodes; i++) {
        const kelp_helm_mode *e = &h->modes[i];
        bool all = true, modevar = true;
        for (unsigned c = 0; c < e->ncond; c++) {
            bool ok = kelp_helm_cond_eval(e->cond[c], &h->ib) == 1;
            all = all && ok;
            if (e->modevar_conds & (1u << c))
                modevar = modevar && ok;
        }
        const char *v = all ? e->val : (modevar && e->elseval[0]) ? e->elseval : NULL;
        if (!v)
            continue;
        char full[128];
        if (e->prefix[0])
            hx_cat(full, sizeof full, e->prefix, ":", v, HX_END);
        else
            hx_cat(full, sizeof full, v, HX_END);
        hx_ignore(kelp_helm_ib_set_string(&h->ib, e->var, full, h->ib.curr_time, false));
        /* the result belongs to the first entry of this variable */
        unsigned first = i;
        for (unsigned j = 0; j < i; j++)
            if (!strcmp(h->modes[j].var, e->var)) {
                first = j;
                break;
            }
        produced[first] = true;
        memcpy(value[first], full, sizeof full);
    }
    size_t n = 0;
    h->mode_summary[0] = '\0';
    for (unsigned i = 0; i < h->nmodes; i++) {
        if (!produced[i])
            continue;
        n += hx_cat(h->mode_summary + n, sizeof h->mode_summary - n, n ? "#" : "", h->modes[i].var, "@", value[i],
                    HX_END);
        if (strcmp(h->mode_posted[i], value[i]) != 0) {
            memcpy(h->mode_posted[i], value[i], sizeof h->mode_posted[i]);
            post(h, h->modes[i].var, value[i]);
        }
    }
}

/* IVPHELM_MODESET: "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,SURVEYING#ACTIVE,RETURNING" (each
 * entry "parent,child", its else value "parent,else"; the variable's name where it changes) */
void helm_mode_describe(const kelp_helm *h, char *buf, size_t cap)
{
    size_t n = 0;
    const char *cur = "";
    buf[0] = '\0';
    for (unsigned i = 0; i < h->nmodes; i++) {
        const kelp_helm_mode *e = &h->modes[i];
        if (i)
            n += hx_cat(buf + n, cap - n, "#", HX_END);
        if (strcmp(e->var, cur) != 0) {
            n += hx_cat(buf + n, cap - n, e->var, "#", HX_END);
            cur = e->var;
        }
        const char *parent = strrchr(e->prefix, ':');
        parent = parent ? parent + 1 : e->prefix[0] ? e->prefix : "---";
        n += hx_cat(buf + n, cap - n, parent, ",", e->val, HX_END);
        if (e->elseval[0])
            n += hx_cat(buf + n, cap - n, "#", parent, ",", e->elseval, HX_END);
    }
}
