/* kelp DCCL: message definition helpers (widths, slots, checks, lookup). */
#include <math.h>
#include <string.h>

#include "dccl_int.h"

static const char *const HEAD_NAMES[KELP_DCCL_N_HEAD] = {"_ccl_id", "_id", "_time", "_src_id", "_dest_id",
                                                        "_multimessage_flag", "_broadcast_flag", "_unused"};
static const uint16_t HEAD_BITS[KELP_DCCL_N_HEAD] = {8, 9, 17, 5, 5, 1, 1, 2};

const char *kelp_dccl_head_default_name(unsigned h)
{
    return h < KELP_DCCL_N_HEAD ? HEAD_NAMES[h] : NULL;
}

/* Goby (message_var_float.h): ceil(log(range*10^p + 2)/log(2)), in double.
 * Deliberately not log2() or integer bit counting: the expression is one bit
 * too wide at 2^29, 2^31, ... and the wire format depends on it. */
unsigned kelp_dccl_width(double range, int precision)
{
    double x = range * dccl_pow10(precision) + 2;
    double w = ceil(log(x) / log(2.0));
    if (!(w >= 0)) return 0;
    if (w > 65535) return 65535;
    return (unsigned)w;
}

static unsigned enum_width(unsigned n)
{
    /* Goby: ceil(log(n + 1)/log(2)), not log1p */
    // cppcheck-suppress unpreciseMathCall
    double w = ceil(log((double)n + 1) / log(2.0));
    return w > 0 ? (unsigned)w : 0;
}

static uint32_t fnv(uint32_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= c[i];
        h *= 16777619u;
    }
    return h;
}

static uint32_t fnv_str(uint32_t h, const char *s)
{
    return s ? fnv(h, s, strlen(s) + 1) : fnv(h, "", 1);
}

static uint32_t fnv_u32(uint32_t h, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)(v >> 24), (unsigned char)(v >> 16), (unsigned char)(v >> 8),
                          (unsigned char)v};
    return fnv(h, b, 4);
}

static uint32_t fnv_dbl(uint32_t h, double d)
{
    /* hash the decimal-independent bit pattern, big-endian */
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    h = fnv_u32(h, (uint32_t)(u >> 32));
    return fnv_u32(h, (uint32_t)u);
}

int kelp_dccl_def_finalize(kelp_dccl_msgdef *def, kelp_dccl_field *fields, kelp_diag *d)
{
    uint32_t body = 0, hash = 2166136261u;
    uint16_t slot = 0;
    unsigned i, j;
    if (!def || !fields || def->n_fields < KELP_DCCL_N_HEAD) {
        return kelp_fail(d, KELP_ERR_ARG, "definition without the 8 header fields");
    }
    def->fields = fields;
    if (def->repeat == 0) def->repeat = 1;
    if (def->repeat > 1) {
        for (i = KELP_DCCL_N_HEAD; i < def->n_fields; i++) {
            if (fields[i].array_length != 1 && fields[i].array_length != def->repeat) {
                return kelp_fail(d, KELP_ERR_RANGE, "<repeat> is not allowed on messages with arrays (<array_length> not 1)");
            }
        }
    }
    for (i = 0; i < def->n_fields; i++) {
        kelp_dccl_field *f = &fields[i];
        if (i < KELP_DCCL_N_HEAD) {
            f->type = (kelp_dccl_type)(KELP_DCCL_T_HEAD_CCL_ID + (i <= KELP_DCCL_H_DEST ? i : (i == KELP_DCCL_H_UNUSED ? 6 : 5)));
            if (!f->name) f->name = HEAD_NAMES[i];
            f->array_length = 1;
            f->bits = f->delta_bits = HEAD_BITS[i];
            f->total_bits = HEAD_BITS[i];
            f->precision = 0;
            f->has_delta = false;
        } else {
            if (f->type > KELP_DCCL_T_HEX) {
                return kelp_fail(d, KELP_ERR_ARG, "layout field with a header type");
            }
            if (def->repeat > 1) f->array_length = def->repeat;
            if (f->array_length == 0) f->array_length = 1;
            f->has_delta = f->has_delta && (f->type == KELP_DCCL_T_INT || f->type == KELP_DCCL_T_FLOAT);
            switch (f->type) {
            case KELP_DCCL_T_INT:
            case KELP_DCCL_T_FLOAT:
                if (f->type == KELP_DCCL_T_INT) f->precision = 0;
                if (f->max < f->min) {
                    double t = f->max;
                    f->max = f->min;
                    f->min = t;
                }
                if (f->has_delta && f->max_delta < 0) f->max_delta = -f->max_delta;
                f->bits = (uint16_t)kelp_dccl_width(f->max - f->min, f->precision);
                f->delta_bits = (f->has_delta && f->array_length > 1) ? (uint16_t)kelp_dccl_width(2 * f->max_delta, f->precision)
                                                                       : f->bits;
                break;
            case KELP_DCCL_T_BOOL: f->bits = f->delta_bits = 2; break;
            case KELP_DCCL_T_STRING:
                if (f->max_length > KELP_DCCL_MAX_STRLEN) {
                    return kelp_fail(d, KELP_ERR_RANGE, "<max_length> exceeds KELP_DCCL_MAX_STRLEN");
                }
                f->bits = f->delta_bits = (uint16_t)(8u * f->max_length);
                break;
            case KELP_DCCL_T_HEX:
                if (2u * f->num_bytes > KELP_DCCL_MAX_STRLEN) {
                    return kelp_fail(d, KELP_ERR_RANGE, "<num_bytes> exceeds KELP_DCCL_MAX_STRLEN/2");
                }
                f->bits = f->delta_bits = (uint16_t)(8u * f->num_bytes);
                break;
            case KELP_DCCL_T_ENUM: f->bits = f->delta_bits = (uint16_t)enum_width(f->n_enum); break;
            default: f->bits = f->delta_bits = 0; break;
            }
            f->total_bits = (uint32_t)f->bits + (uint32_t)(f->array_length - 1u) * f->delta_bits;
            body += f->total_bits;
        }
        if ((uint32_t)slot + f->array_length > 65535u) {
            return kelp_fail(d, KELP_ERR_RANGE, "too many value slots");
        }
        f->slot = slot;
        slot = (uint16_t)(slot + f->array_length);
        for (j = 0; j < f->n_algs; j++) {
            unsigned r;
            for (r = 0; r < f->algs[j].n_refs; r++) {
                if (f->algs[j].refs[r] < 0 || f->algs[j].refs[r] >= (int)def->n_fields) {
                    return kelp_fail(d, KELP_ERR_ARG, "algorithm reference out of range");
                }
            }
        }
    }
    def->n_slots = slot;
    def->body_bits = body;
    if (def->size <= KELP_DCCL_HEAD_BYTES) {
        return kelp_fail(d, KELP_ERR_RANGE, "<size> must be larger than the 6-byte header");
    }
    if (def->size > KELP_DCCL_MAX_SIZE) {
        return kelp_fail(d, KELP_ERR_RANGE, "<size> exceeds KELP_DCCL_MAX_SIZE");
    }
    if (body > 8u * (uint32_t)(def->size - KELP_DCCL_HEAD_BYTES)) {
        return kelp_fail(d, KELP_ERR_RANGE, "the message will not fit within specified size. remove parameters, tighten bounds, or increase "
               "allowed size");
    }
    for (i = 0; i < def->n_publishes; i++) {
        for (j = 0; j < def->publishes[i].n_args; j++) {
            if (def->publishes[i].args[j].field >= def->n_fields) {
                return kelp_fail(d, KELP_ERR_ARG, "publish argument out of range");
            }
        }
    }
    /* fingerprint: what the wire depends on */
    hash = fnv_u32(hash, def->id);
    hash = fnv_u32(hash, def->size);
    hash = fnv_u32(hash, def->repeat);
    for (i = 0; i < def->n_fields; i++) {
        const kelp_dccl_field *f = &fields[i];
        hash = fnv_str(hash, f->name);
        hash = fnv_u32(hash, (uint32_t)f->type);
        hash = fnv_u32(hash, f->array_length);
        hash = fnv_u32(hash, f->bits);
        hash = fnv_u32(hash, f->delta_bits);
        hash = fnv_dbl(hash, f->min);
        hash = fnv_dbl(hash, f->max);
        hash = fnv_dbl(hash, f->has_delta ? f->max_delta : 0);
        hash = fnv_u32(hash, (uint32_t)f->precision);
        hash = fnv_str(hash, f->static_value);
        for (j = 0; j < f->n_enum; j++) hash = fnv_str(hash, f->enum_values[j]);
        for (j = 0; j < f->n_algs; j++) hash = fnv_str(hash, f->algs[j].name);
    }
    def->hash = hash;
    return KELP_OK;
}

int kelp_dccl_field_find(const kelp_dccl_msgdef *def, const char *name)
{
    unsigned i;
    /* Goby's name2message_var: layout first, then header */
    for (i = KELP_DCCL_N_HEAD; i < def->n_fields; i++)
        if (def->fields[i].name && strcmp(def->fields[i].name, name) == 0) return (int)i;
    for (i = 0; i < KELP_DCCL_N_HEAD && i < def->n_fields; i++)
        if (def->fields[i].name && strcmp(def->fields[i].name, name) == 0) return (int)i;
    return -1;
}

const kelp_dccl_msgdef *kelp_dccl_set_find_id(const kelp_dccl_set *set, unsigned id)
{
    size_t i;
    for (i = 0; i < set->n; i++)
        if (set->msgs[i]->id == id) return set->msgs[i];
    return NULL;
}

const kelp_dccl_msgdef *kelp_dccl_set_find_name(const kelp_dccl_set *set, const char *name)
{
    size_t i;
    for (i = 0; i < set->n; i++)
        if (strcmp(set->msgs[i]->name, name) == 0) return set->msgs[i];
    return NULL;
}

size_t kelp_dccl_max_len(const kelp_dccl_msgdef *def)
{
    return KELP_DCCL_HEAD_BYTES + (def->body_bits + 7u) / 8u;
}
