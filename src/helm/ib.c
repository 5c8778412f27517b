/* kelp helm: the information buffer (InfoBuffer, seed 4.5.2-4.5.4). */
#include <string.h>
#include "helm_int.h"

void kelp_helm_ib_init(kelp_helm_ib *ib)
{
    memset(ib, 0, sizeof *ib);
}

int kelp_helm_ib_find(const kelp_helm_ib *ib, const char *name)
{
    for (unsigned i = 0; i < ib->nvar; i++)
        if (strcmp(ib->var[i].name, name) == 0)
            return (int)i;
    return -1;
}

static int slot(kelp_helm_ib *ib, const char *name)
{
    int i = kelp_helm_ib_find(ib, name);
    if (i >= 0)
        return i;
    size_t n = strlen(name);
    if (ib->nvar >= KELP_HELM_MAX_VARS || n == 0 || n >= KELP_MAX_NAME)
        return KELP_ERR_NOSPACE;
    kelp_helm_ibvar *v = &ib->var[ib->nvar];
    memset(v, 0, sizeof *v);
    memcpy(v->name, name, n + 1);
    v->time = -1;
    return (int)ib->nvar++;
}

static void add_delta(kelp_helm_ib *ib, int i, bool is_str, double d, const char *s)
{
    if (ib->ndelta >= KELP_HELM_MAX_DELTAS) {
        ib->dropped++;
        return;
    }
    kelp_helm_ibdelta *x = &ib->delta[ib->ndelta];
    x->var = (uint16_t)i;
    x->is_str = is_str;
    x->dval = d;
    x->soff = 0;
    if (is_str) {
        size_t n = strlen(s) + 1;
        if (ib->npool + n > sizeof ib->pool) {
            ib->dropped++;
            return;
        }
        memcpy(ib->pool + ib->npool, s, n);
        x->soff = (uint32_t)ib->npool;
        ib->npool += n;
    }
    ib->ndelta++;
}

int kelp_helm_ib_set_double(kelp_helm_ib *ib, const char *name, double v, double t, bool delta)
{
    int i = slot(ib, name);
    if (i < 0) {
        ib->dropped++;
        return i;
    }
    kelp_helm_ibvar *x = &ib->var[i];
    x->is_str = false;
    x->dval = v;
    x->sval[0] = '\0';
    x->time = t;
    if (delta)
        add_delta(ib, i, false, v, NULL);
    return 0;
}

int kelp_helm_ib_set_string(kelp_helm_ib *ib, const char *name, const char *v, double t, bool delta)
{
    size_t n = strlen(v);
    if (n >= KELP_HELM_MAX_SVAL) {
        ib->dropped++;
        return KELP_ERR_RANGE;
    }
    int i = slot(ib, name);
    if (i < 0) {
        ib->dropped++;
        return i;
    }
    kelp_helm_ibvar *x = &ib->var[i];
    x->is_str = true;
    x->dval = 0;
    memcpy(x->sval, v, n + 1);
    x->time = t;
    if (delta)
        add_delta(ib, i, true, 0, v);
    return 0;
}

bool kelp_helm_ib_double(const kelp_helm_ib *ib, const char *name, double *out)
{
    int i = kelp_helm_ib_find(ib, name);
    if (i < 0)
        return false;
    const kelp_helm_ibvar *x = &ib->var[i];
    if (!x->is_str) {
        *out = x->dval;
        return true;
    }
    return hx_number(x->sval, strlen(x->sval), out);
}

bool kelp_helm_ib_string(const kelp_helm_ib *ib, const char *name, char *buf, size_t cap)
{
    int i = kelp_helm_ib_find(ib, name);
    if (i < 0 || cap == 0)
        return false;
    const kelp_helm_ibvar *x = &ib->var[i];
    if (!x->is_str) {
        hx_fmt_double(buf, cap, x->dval);
        return true;
    }
    return hx_copy(buf, cap, x->sval, strlen(x->sval));
}

double kelp_helm_ib_time(const kelp_helm_ib *ib, const char *name)
{
    int i = kelp_helm_ib_find(ib, name);
    return i < 0 ? -1.0 : ib->var[i].time;
}

bool kelp_helm_ib_delta(const kelp_helm_ib *ib, const char *name, unsigned k, double *dval, const char **sval)
{
    int i = kelp_helm_ib_find(ib, name);
    if (i < 0)
        return false;
    for (unsigned j = 0; j < ib->ndelta; j++) {
        const kelp_helm_ibdelta *x = &ib->delta[j];
        if (x->var != (uint16_t)i)
            continue;
        if (k-- == 0) {
            if (dval)
                *dval = x->dval;
            if (sval)
                *sval = x->is_str ? ib->pool + x->soff : NULL;
            return true;
        }
    }
    return false;
}

unsigned kelp_helm_ib_ndeltas(const kelp_helm_ib *ib, const char *name)
{
    int i = kelp_helm_ib_find(ib, name);
    unsigned n = 0;
    if (i < 0)
        return 0;
    for (unsigned j = 0; j < ib->ndelta; j++)
        if (ib->delta[j].var == (uint16_t)i)
            n++;
    return n;
}

void kelp_helm_ib_clear_deltas(kelp_helm_ib *ib)
{
    ib->ndelta = 0;
    ib->npool = 0;
}
