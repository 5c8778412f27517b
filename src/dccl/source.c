/* kelp DCCL: building a message from bus variables as pAcommsHandler 1.1 does
 * (DCCLMessageVar::read_pubsub_vars, tes_util::val_from_string), triggers. */
#include <string.h>

#include "dccl_int.h"

bool kelp_dccl_val_from_string(const char *str, const char *key, const char **val, size_t *len)
{
    size_t kn = strlen(key), sn = strlen(str), start = 0;
    const char *hit = NULL;
    /* find "key=" at the start or right after a ',' */
    while (start + kn + 1 <= sn) {
        const char *p = str + start;
        const char *q = NULL;
        size_t i;
        for (i = 0; start + i + kn + 1 <= sn; i++) {
            if (memcmp(p + i, key, kn) == 0 && p[i + kn] == '=') {
                q = p + i;
                break;
            }
        }
        if (!q) return false;
        if (q == str || q[-1] == ',') {
            hit = q;
            break;
        }
        start = (size_t)(q - str) + 1;
    }
    if (!hit) return false;
    {
        const char *eq = strchr(hit, '=');
        const char *v = eq + 1;
        const char *end;
        if (*v == '{') {
            v++;
            end = strchr(v, '}');
        } else {
            end = strchr(v, ',');
        }
        if (!end) end = str + sn;
        *val = v;
        *len = (size_t)(end - v);
    }
    return true;
}

bool kelp_dccl_is_trigger(const kelp_dccl_msgdef *def, const kelp_dccl_var *v)
{
    if (def->trigger != KELP_DCCL_TRIG_PUBLISH || !def->trigger_var || !v || !v->name) return false;
    if (strcmp(def->trigger_var, v->name) != 0) return false;
    if (!def->trigger_mandatory || !def->trigger_mandatory[0]) return true;
    if (v->is_double || !v->s) return false;
    return strstr(v->s, def->trigger_mandatory) != NULL;
}

static const kelp_dccl_var *find_var(const kelp_dccl_var *vars, size_t n, const char *name)
{
    size_t i = n;
    if (!name) return NULL;
    while (i-- > 0) /* the newest (last) value wins */
        if (vars[i].name && strcmp(vars[i].name, name) == 0) return &vars[i];
    return NULL;
}

int kelp_dccl_source(const kelp_dccl_msgdef *def, const kelp_dccl_var *vars, size_t n_vars, unsigned element,
                     kelp_dccl_val *out, size_t n_out)
{
    unsigned fi;
    if (!def || !out || n_out < def->n_slots) return KELP_ERR_ARG;
    if (element >= def->repeat && element != 0) return KELP_ERR_RANGE;
    for (fi = 0; fi < def->n_fields; fi++) {
        const kelp_dccl_field *f = &def->fields[fi];
        /* a header field keeping its default name reads no variable (Goby clears its source
         * in DCCLMessageVarHead::initialize_specific); only a renamed one is sourced */
        if (fi < KELP_DCCL_N_HEAD) {
            const char *dn = kelp_dccl_head_default_name(fi);
            if (!f->name || (dn && strcmp(f->name, dn) == 0)) continue;
        }
        const char *src = f->src_var ? f->src_var : def->trigger_var;
        const kelp_dccl_var *v = find_var(vars, n_vars, src);
        const char *s;
        size_t sl;
        bool array = def->repeat <= 1 && f->array_length > 1;
        unsigned el = (def->repeat > 1 && f->array_length > 1) ? element : 0;
        if (!v) continue;
        if (v->is_double) {
            if (!array) {
                kelp_dccl_val_set_double(&out[f->slot + el], v->d, KELP_DCCL_MAX_DBL_PRECISION);
                continue;
            }
            /* explode() works on the string form */
            dccl_val_set_double_str(&out[f->slot], v->d, KELP_DCCL_MAX_DBL_PRECISION);
            continue;
        }
        s = v->s ? v->s : "";
        if (!kelp_dccl_val_from_string(s, f->src_key ? f->src_key : f->name, &s, &sl)) sl = strlen(s);
        if (!array) {
            kelp_dccl_val_set_strn(&out[f->slot + el], s, sl);
        } else {
            /* split on ',' into elements 0..; extra pieces are dropped */
            unsigned k = 0;
            size_t a = 0, b;
            for (b = 0; b <= sl && k < f->array_length; b++) {
                if (b == sl || s[b] == ',') {
                    kelp_dccl_val_set_strn(&out[f->slot + k], s + a, b - a);
                    k++;
                    a = b + 1;
                }
            }
        }
    }
    return KELP_OK;
}

void kelp_dccl_timer_init(kelp_dccl_timer *t, double start)
{
    t->start = start;
    t->k = 1;
}

bool kelp_dccl_timer_due(kelp_dccl_timer *t, const kelp_dccl_msgdef *def, kelp_time now)
{
    if (def->trigger != KELP_DCCL_TRIG_TIME || !(def->trigger_time > 0)) return false;
    if (now > t->start + (double)t->k * def->trigger_time) {
        t->k++;
        return true;
    }
    return false;
}
