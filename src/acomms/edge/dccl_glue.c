/* kelp acomms: the DCCL side of pAcommsHandler (edge; allocates at start-up).
 *
 * pAcommsHandler 1.1 keeps the newest value of every <src_var>/<trigger_var> it subscribes to,
 * builds a message when its trigger var is written (with the mandatory content) or its
 * trigger_time comes, encodes it (always encrypted, key SHA-256(passphrase or "")), and on
 * receipt decodes and runs the <publish> blocks.  This file keeps that state behind an opaque
 * handle so the queue/MAC/driver side never includes <kelp/dccl.h>. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KELP_ACOMMS_DCCL_ONLY 1
#include <kelp/acomms.h>
#include <kelp/dccl.h>
#include <kelp/edge/dccl.h>

#define GLUE_MAX_ALGS 64
#define GLUE_MAX_MODEMS 256

typedef struct gvar {
    char *name;
    bool set;
    bool is_double;
    double d;
    char *s;
} gvar;

typedef struct gmsg {
    unsigned manip;
    kelp_dccl_timer timer;
    kelp_dccl_val *rep;     /* <repeat> messages: values collected so far */
    unsigned rep_count;
} gmsg;

struct kelp_acomms_dccl {
    kelp_dccl_loaded ld;
    gmsg *msg;
    kelp_dccl_alg_entry alg_store[GLUE_MAX_ALGS];
    kelp_dccl_algs algs;
    kelp_dccl_modem_entry modems[GLUE_MAX_MODEMS];
    kelp_dccl_builtin bi;
    kelp_dccl_mbedtls mb;
    bool mb_ok;
    kelp_dccl_codec cx;
    gvar *vars;
    size_t nvars;
    kelp_dccl_var *src;     /* scratch for kelp_dccl_source */
    kelp_dccl_val *vals;    /* scratch, max n_slots */
    size_t max_slots;
    size_t max_pubs;        /* publications of the message with the most (<repeat/> x <publish>) */
    kelp_dccl_pub *pubs;
};

long kelp_acomms_manip_from_name(const char *name, size_t len)
{
    static const struct {
        const char *n;
        unsigned bit;
    } T[] = { { "NO_MANIP", 0 },
              { "NO_ENCODE", KELP_ACOMMS_MANIP_NO_ENCODE },
              { "NO_DECODE", KELP_ACOMMS_MANIP_NO_DECODE },
              { "NO_QUEUE", KELP_ACOMMS_MANIP_NO_QUEUE },
              { "LOOPBACK", KELP_ACOMMS_MANIP_LOOPBACK },
              { "ON_DEMAND", KELP_ACOMMS_MANIP_ON_DEMAND },
              { "TCP_SHARE_IN", KELP_ACOMMS_MANIP_TCP_SHARE_IN } };
    for (size_t i = 0; i < sizeof T / sizeof T[0]; i++)
        if (strlen(T[i].n) == len && memcmp(T[i].n, name, len) == 0) return (long)T[i].bit;
    return -1;
}

static long var_index(const kelp_acomms_dccl *d, const char *name)
{
    for (size_t i = 0; i < d->nvars; i++)
        if (strcmp(d->vars[i].name, name) == 0) return (long)i;
    return -1;
}

static int add_var(kelp_acomms_dccl *d, const char *name, size_t *cap)
{
    if (!name || !name[0] || var_index(d, name) >= 0) return KELP_OK;
    if (d->nvars == *cap) {
        size_t nc = *cap ? *cap * 2 : 16;
        gvar *nv = realloc(d->vars, nc * sizeof *nv);
        if (!nv) return KELP_ERR_NOSPACE;
        d->vars = nv;
        *cap = nc;
    }
    gvar *v = &d->vars[d->nvars];
    memset(v, 0, sizeof *v);
    v->name = strdup(name);
    v->s = calloc(1, KELP_MAX_SVAL + 1);
    if (!v->name || !v->s) {
        free(v->name);
        free(v->s);
        return KELP_ERR_NOSPACE;
    }
    d->nvars++;
    return KELP_OK;
}

void kelp_acomms_dccl_close(kelp_acomms_dccl *d)
{
    if (!d) return;
    for (size_t i = 0; i < d->nvars; i++) {
        free(d->vars[i].name);
        free(d->vars[i].s);
    }
    if (d->msg)
        for (size_t i = 0; i < d->ld.set.n; i++) free(d->msg[i].rep);
    free(d->vars);
    free(d->msg);
    free(d->src);
    free(d->vals);
    free(d->pubs);
    if (d->mb_ok) kelp_dccl_mbedtls_free(&d->mb);
    kelp_dccl_loaded_free(&d->ld);
    free(d);
}

kelp_acomms_dccl *kelp_acomms_dccl_open(const kelp_acomms_dccl_cfg *cfg, kelp_diag *diag)
{
    kelp_diag e; /* the lookup file's reason, put after "modem_id_lookup_path: " */
    kelp_diag_clear(&e);
    if (!cfg) {
        (void)kelp_fail(diag, KELP_ERR_ARG, "no configuration");
        return NULL;
    }
    kelp_acomms_dccl *d = calloc(1, sizeof *d);
    if (!d) {
        (void)kelp_fail(diag, KELP_ERR_NOSPACE, "out of memory");
        return NULL;
    }
    kelp_dccl_loaded_init(&d->ld);
    kelp_dccl_algs_init(&d->algs, d->alg_store, GLUE_MAX_ALGS);
    kelp_dccl_builtin_init(&d->bi, d->modems, GLUE_MAX_MODEMS);
    if (kelp_dccl_algs_add_builtin(&d->algs, &d->bi) != KELP_OK) {
        (void)kelp_fail(diag, KELP_ERR_NOSPACE, "cannot register the DCCL algorithms");
        goto fail;
    }
    if (cfg->have_origin) kelp_dccl_builtin_set_origin(&d->bi, cfg->lat_origin, cfg->lon_origin);
    if (cfg->lookup_path && cfg->lookup_path[0] &&
        kelp_dccl_builtin_load_modems(&d->bi, cfg->lookup_path, &e) != KELP_OK) {
        (void)kelp_failf(diag, e.code, "modem_id_lookup_path: %s", kelp_diag_text(&e));
        goto fail;
    }
    /* every file once; manipulators of the same path merged (queue_cfg + dccl_cfg) */
    size_t nf = cfg->nfiles;
    size_t *first = calloc(nf + 1, sizeof *first), *m0 = calloc(nf + 1, sizeof *m0), *m1 = calloc(nf + 1, sizeof *m1);
    unsigned *fm = calloc(nf + 1, sizeof *fm);
    if (!first || !m0 || !m1 || !fm) goto oom_files;
    for (size_t i = 0; i < nf; i++) {
        first[i] = i;
        for (size_t k = 0; k < i; k++)
            if (strcmp(cfg->files[k], cfg->files[i]) == 0) {
                first[i] = first[k];
                break;
            }
        fm[first[i]] |= cfg->manips ? cfg->manips[i] : 0;
        if (first[i] != i) continue;
        m0[i] = d->ld.set.n;
        if (kelp_dccl_load_file(&d->ld, cfg->files[i], &d->algs, diag) != KELP_OK) {
            free(first), free(m0), free(m1), free(fm);
            goto fail;
        }
        m1[i] = d->ld.set.n;
    }
    size_t nm = d->ld.set.n;
    d->msg = calloc(nm + 1, sizeof *d->msg);
    if (!d->msg) goto oom_files;
    for (size_t i = 0; i < nf; i++)
        if (first[i] == i)
            for (size_t m = m0[i]; m < m1[i]; m++) d->msg[m].manip = fm[i];
    free(first), free(m0), free(m1), free(fm);
    size_t vcap = 0;
    for (size_t m = 0; m < nm; m++) {
        const kelp_dccl_msgdef *def = d->ld.set.msgs[m];
        if (def->n_slots > d->max_slots) d->max_slots = def->n_slots;
        if (kelp_dccl_n_publications(def) > d->max_pubs) d->max_pubs = kelp_dccl_n_publications(def);
        if (add_var(d, def->trigger_var, &vcap) != KELP_OK) goto oom;
        for (unsigned f = 0; f < def->n_fields; f++)
            if (add_var(d, def->fields[f].src_var, &vcap) != KELP_OK) goto oom;
        if (def->repeat > 1) {
            d->msg[m].rep = calloc(def->n_slots, sizeof *d->msg[m].rep);
            if (!d->msg[m].rep) goto oom;
        }
    }
    d->src = calloc(d->nvars + 1, sizeof *d->src);
    d->vals = calloc(d->max_slots + 1, sizeof *d->vals);
    d->pubs = calloc(d->max_pubs + 1, sizeof *d->pubs);
    if (!d->src || !d->vals || !d->pubs) goto oom;
    if (!cfg->plaintext) {
        if (kelp_dccl_mbedtls_init(&d->mb, cfg->passphrase) != KELP_OK) {
            (void)kelp_fail(diag, KELP_ERR_CRYPTO, "crypto initialisation failed");
            goto fail;
        }
        d->mb_ok = true;
    }
    kelp_dccl_codec_init(&d->cx, cfg->modem_id, d->mb_ok ? &d->mb.ops : NULL, &d->algs);
    return d;
oom_files:
    free(first), free(m0), free(m1), free(fm);
oom:
    (void)kelp_fail(diag, KELP_ERR_NOSPACE, "out of memory");
fail:
    kelp_acomms_dccl_close(d);
    return NULL;
}

size_t kelp_acomms_dccl_count(const kelp_acomms_dccl *d)
{
    return d ? d->ld.set.n : 0;
}

int kelp_acomms_dccl_info_get(const kelp_acomms_dccl *d, size_t i, kelp_acomms_dccl_info *out)
{
    if (!d || !out || i >= d->ld.set.n) return KELP_ERR_ARG;
    const kelp_dccl_msgdef *def = d->ld.set.msgs[i];
    memset(out, 0, sizeof *out);
    out->name = def->name;
    out->id = def->id;
    out->size = def->size;
    out->trigger = def->trigger == KELP_DCCL_TRIG_PUBLISH ? 1 : def->trigger == KELP_DCCL_TRIG_TIME ? 2 : 0;
    out->trigger_var = def->trigger_var;
    out->mandatory = def->trigger_mandatory;
    out->trigger_time = def->trigger_time;
    out->in_var = def->in_var;
    out->out_var = def->out_var;
    out->manip = d->msg[i].manip;
    out->ack = def->queuing.ack;
    out->blackout_time = def->queuing.blackout_time;
    out->max_queue = def->queuing.max_queue;
    out->newest_first = def->queuing.newest_first;
    out->value_base = def->queuing.value_base;
    out->ttl = def->queuing.ttl;
    return KELP_OK;
}

long kelp_acomms_dccl_find_id(const kelp_acomms_dccl *d, unsigned id)
{
    for (size_t i = 0; d && i < d->ld.set.n; i++)
        if (d->ld.set.msgs[i]->id == id) return (long)i;
    return -1;
}

long kelp_acomms_dccl_find_name(const kelp_acomms_dccl *d, const char *name)
{
    for (size_t i = 0; d && name && i < d->ld.set.n; i++)
        if (strcmp(d->ld.set.msgs[i]->name, name) == 0) return (long)i;
    return -1;
}

size_t kelp_acomms_dccl_nvars(const kelp_acomms_dccl *d)
{
    return d ? d->nvars : 0;
}

const char *kelp_acomms_dccl_var_name(const kelp_acomms_dccl *d, size_t i)
{
    return d && i < d->nvars ? d->vars[i].name : NULL;
}

void kelp_acomms_dccl_set_var(kelp_acomms_dccl *d, const char *name, bool is_double, double dval, const char *sval)
{
    if (!d || !name) return;
    long i = var_index(d, name);
    if (i < 0) return;
    gvar *v = &d->vars[i];
    v->set = true;
    v->is_double = is_double;
    v->d = dval;
    if (!is_double) snprintf(v->s, KELP_MAX_SVAL + 1, "%s", sval ? sval : "");
}

size_t kelp_acomms_dccl_triggered(const kelp_acomms_dccl *d, const char *name, size_t *idx, size_t cap)
{
    size_t n = 0;
    if (!d || !name) return 0;
    long vi = var_index(d, name);
    if (vi < 0 || !d->vars[vi].set) return 0;
    const gvar *v = &d->vars[vi];
    kelp_dccl_var dv = { v->name, v->is_double, v->d, v->s };
    for (size_t i = 0; i < d->ld.set.n && n < cap; i++) {
        if (d->msg[i].manip & KELP_ACOMMS_MANIP_NO_ENCODE) continue;
        if (kelp_dccl_is_trigger(d->ld.set.msgs[i], &dv)) idx[n++] = i;
    }
    return n;
}

void kelp_acomms_dccl_start(kelp_acomms_dccl *d, double now)
{
    for (size_t i = 0; d && i < d->ld.set.n; i++) kelp_dccl_timer_init(&d->msg[i].timer, now);
}

size_t kelp_acomms_dccl_due(kelp_acomms_dccl *d, double now, size_t *idx, size_t cap)
{
    size_t n = 0;
    for (size_t i = 0; d && i < d->ld.set.n; i++) {
        if (!kelp_dccl_timer_due(&d->msg[i].timer, d->ld.set.msgs[i], now)) continue;
        if (d->msg[i].manip & KELP_ACOMMS_MANIP_NO_ENCODE) continue;
        if (n < cap) idx[n++] = i;
    }
    return n;
}

/* rc of the DCCL codec into diag: the codec's reason (or dflt when it gave none) */
static int codec_fail(kelp_acomms_dccl *d, kelp_diag *diag, int rc, const char *dflt)
{
#ifdef KELP_NO_ERRMSG
    (void)d, (void)dflt;
#endif
    return kelp_fail(diag, rc, d->cx.diag.code ? kelp_diag_text(&d->cx.diag) : dflt); /* NULL: kelp_err_str */
}

static int encode_vals(kelp_acomms_dccl *d, const kelp_dccl_msgdef *def, const kelp_dccl_val *vals, double now,
                       uint8_t *out, size_t cap, size_t *len, kelp_diag *diag)
{
    int rc = kelp_dccl_encode(&d->cx, def, vals, def->n_slots, now, out, cap, len);
    return rc ? codec_fail(d, diag, rc, NULL) : KELP_OK;
}

int kelp_acomms_dccl_encode_vars(kelp_acomms_dccl *d, size_t i, double now, uint8_t *out, size_t cap, size_t *len,
                                 kelp_diag *diag)
{
    if (!d || i >= d->ld.set.n || !out || !len) {
        return kelp_fail(diag, KELP_ERR_ARG, "bad argument");
    }
    const kelp_dccl_msgdef *def = d->ld.set.msgs[i];
    size_t ns = 0;
    for (size_t k = 0; k < d->nvars; k++) {
        const gvar *v = &d->vars[k];
        if (!v->set) continue;
        d->src[ns].name = v->name;
        d->src[ns].is_double = v->is_double;
        d->src[ns].d = v->d;
        d->src[ns].s = v->s;
        ns++;
    }
    gmsg *g = &d->msg[i];
    if (def->repeat > 1) {
        /* Goby buffers `repeat` triggers and sends them as one message */
        if (g->rep_count == 0)
            for (unsigned k = 0; k < def->n_slots; k++) kelp_dccl_val_clear(&g->rep[k]);
        int rc = kelp_dccl_source(def, d->src, ns, g->rep_count, g->rep, def->n_slots);
        if (rc) {
            return kelp_fail(diag, rc, "cannot source values");
        }
        if (++g->rep_count < def->repeat) {
            return kelp_fail(diag, KELP_ERR_PARTIAL, "repeat: collecting");
        }
        g->rep_count = 0;
        return encode_vals(d, def, g->rep, now, out, cap, len, diag);
    }
    for (unsigned k = 0; k < def->n_slots; k++) kelp_dccl_val_clear(&d->vals[k]);
    int rc = kelp_dccl_source(def, d->src, ns, 0, d->vals, def->n_slots);
    if (rc) {
        return kelp_fail(diag, rc, "cannot source values");
    }
    return encode_vals(d, def, d->vals, now, out, cap, len, diag);
}

int kelp_acomms_dccl_encode_string(kelp_acomms_dccl *d, size_t i, const char *kv, double now, uint8_t *out, size_t cap,
                                   size_t *len, kelp_diag *diag)
{
    if (!d || i >= d->ld.set.n || !kv || !out || !len) {
        return kelp_fail(diag, KELP_ERR_ARG, "bad argument");
    }
    const kelp_dccl_msgdef *def = d->ld.set.msgs[i];
    for (unsigned k = 0; k < def->n_slots; k++) kelp_dccl_val_clear(&d->vals[k]);
    const char *p = kv;
    while (*p) {
        while (*p == ',' || *p == ' ') p++;
        if (!*p) break;
        const char *eq = strchr(p, '=');
        if (!eq) {
            return kelp_fail(diag, KELP_ERR_PARSE, "expected field=value");
        }
        char name[KELP_DCCL_MAX_NAME];
        size_t nl = (size_t)(eq - p);
        if (nl == 0 || nl >= sizeof name) {
            return kelp_fail(diag, KELP_ERR_PARSE, "bad field name");
        }
        memcpy(name, p, nl);
        name[nl] = '\0';
        const char *v = eq + 1, *end;
        bool braced = *v == '{';
        if (braced) {
            v++;
            end = strchr(v, '}');
            if (!end) {
                return kelp_fail(diag, KELP_ERR_PARSE, "missing '}'");
            }
        } else {
            end = strchr(v, ',');
            if (!end) end = v + strlen(v);
        }
        int fi = kelp_dccl_field_find(def, name);
        if (fi < 0) {
            return kelp_fail(diag, KELP_ERR_NOTFOUND, "no such field in the message");
        }
        const kelp_dccl_field *f = &def->fields[fi];
        if (braced || f->array_length > 1) {
            unsigned el = 0;
            const char *a = v;
            for (const char *b = v; b <= end && el < f->array_length; b++) {
                if (b == end || *b == ',') {
                    kelp_dccl_val_set_strn(&d->vals[f->slot + el], a, (size_t)(b - a));
                    el++;
                    a = b + 1;
                }
            }
        } else {
            kelp_dccl_val_set_strn(&d->vals[f->slot], v, (size_t)(end - v));
        }
        p = braced ? end + 1 : end;
    }
    return encode_vals(d, def, d->vals, now, out, cap, len, diag);
}

static int decode_into(kelp_acomms_dccl *d, const uint8_t *in, size_t n, double now, const kelp_dccl_msgdef **defp,
                       long *idx, kelp_diag *diag)
{
    unsigned id;
    /* the constant codes are returned as such: *defp is set exactly when 0 is returned */
    if (kelp_dccl_peek_id(in, n, &id) != KELP_OK) {
        (void)kelp_fail(diag, KELP_ERR_TRUNCATED, "too short for a DCCL header");
        return KELP_ERR_TRUNCATED;
    }
    long i = kelp_acomms_dccl_find_id(d, id);
    if (i < 0) {
        (void)kelp_fail(diag, KELP_ERR_NOTFOUND, "no message with this DCCL id");
        return KELP_ERR_NOTFOUND;
    }
    const kelp_dccl_msgdef *def = d->ld.set.msgs[i];
    int rc = kelp_dccl_decode(&d->cx, def, in, n, now, d->vals, def->n_slots);
    if (rc) {
        (void)codec_fail(d, diag, rc, NULL);
        return rc;
    }
    *defp = def;
    *idx = i;
    return KELP_OK;
}

int kelp_acomms_dccl_decode(kelp_acomms_dccl *d, const uint8_t *in, size_t n, double now, kelp_acomms_pub_fn fn,
                            void *user, kelp_diag *diag)
{
    if (!d || !in) return kelp_fail(diag, KELP_ERR_ARG, "bad argument");
    const kelp_dccl_msgdef *def = NULL;
    long i = -1;
    unsigned id;
    if (kelp_dccl_peek_id(in, n, &id) == KELP_OK) {
        long k = kelp_acomms_dccl_find_id(d, id);
        if (k >= 0 && (d->msg[k].manip & KELP_ACOMMS_MANIP_NO_DECODE)) {
            return kelp_fail(diag, KELP_ERR_STATE, "NO_DECODE");
        }
    }
    int rc = decode_into(d, in, n, now, &def, &i, diag);
    if (rc) return rc;
    size_t np = 0;
    rc = kelp_dccl_publish_all(&d->cx, def, d->vals, def->n_slots, d->pubs, d->max_pubs + 1, &np);
    if (rc) return codec_fail(d, diag, rc, "publish failed");
    for (size_t k = 0; k < np && fn; k++) fn(d->pubs[k].var, d->pubs[k].is_double, d->pubs[k].d, d->pubs[k].s, user);
    return KELP_OK;
}

int kelp_acomms_dccl_describe(kelp_acomms_dccl *d, const uint8_t *in, size_t n, double now, char *buf, size_t cap)
{
    kelp_diag why;
    const kelp_dccl_msgdef *def = NULL;
    long i = -1;
    if (!d || !in || !buf || !cap) return KELP_ERR_ARG;
    kelp_diag_clear(&why);
    int rc = decode_into(d, in, n, now, &def, &i, &why);
    if (rc) {
        snprintf(buf, cap, "(cannot decode: %s)", why.code ? kelp_diag_text(&why) : kelp_err_str(rc));
        return rc;
    }
    size_t o = 0;
    int w = snprintf(buf, cap, "%s:", def->name);
    o = w > 0 ? (size_t)w : 0;
    for (unsigned f = 0; f < def->n_fields && o < cap; f++) {
        const kelp_dccl_field *fd = &def->fields[f];
        if (f < KELP_DCCL_N_HEAD && fd->name && fd->name[0] == '_' && f != KELP_DCCL_H_ID && f != KELP_DCCL_H_SRC &&
            f != KELP_DCCL_H_DEST && f != KELP_DCCL_H_TIME)
            continue;
        for (unsigned e = 0; e < fd->array_length && o < cap; e++) {
            char v[KELP_DCCL_MAX_STRLEN + 1];
            if (!kelp_dccl_val_to_str(&d->vals[fd->slot + e], v, sizeof v, NULL)) v[0] = '\0';
            if (fd->array_length > 1)
                w = snprintf(buf + o, cap - o, "%s%s[%u]=%s", f ? "," : " ", fd->name, e, v);
            else
                w = snprintf(buf + o, cap - o, "%s%s=%s", f ? "," : " ", fd->name, v);
            if (w < 0) break;
            o += (size_t)w;
        }
    }
    if (o >= cap) {
        buf[cap - 1] = '\0';
        return KELP_ERR_NOSPACE;
    }
    return KELP_OK;
}
