/* kelp commander: open messages, value checks and send (see include/kelp/commander.h). */
#include <math.h>
#include <string.h>

#include <kelp/commander.h>
#include <kelp/util.h>

static bool is_static(const kelp_dccl_field *f)
{
    switch (f->type) {
    case KELP_DCCL_T_STATIC:
    case KELP_DCCL_T_HEAD_CCL_ID:
    case KELP_DCCL_T_HEAD_ID:
    case KELP_DCCL_T_HEAD_FLAG:
    case KELP_DCCL_T_HEAD_UNUSED: return true;
    default: return false;
    }
}

void kelp_commander_init(kelp_commander *c, const kelp_dccl_set *set, kelp_dccl_builtin *geo)
{
    memset(c, 0, sizeof *c);
    c->set = set;
    c->geo = geo;
    c->active = -1;
}

int kelp_commander_open(kelp_commander *c, const char *name)
{
    const kelp_dccl_msgdef *def = c->set ? kelp_dccl_set_find_name(c->set, name) : NULL;
    if (!def) return KELP_ERR_NOTFOUND;
    for (unsigned i = 0; i < c->n_open; i++)
        if (c->open[i].def == def) return (int)i;
    if (c->n_open >= KELP_CMDR_MAX_OPEN) return KELP_ERR_NOSPACE;
    kelp_commander_msg *m = &c->open[c->n_open];
    memset(m, 0, sizeof *m);
    m->def = def;
    for (unsigned fi = 0; fi < def->n_fields && m->n_rows < KELP_CMDR_MAX_ROWS; fi++) {
        const kelp_dccl_field *f = &def->fields[fi];
        if (fi < KELP_DCCL_N_HEAD) { /* a header field is the operator's only when renamed */
            const char *dn = kelp_dccl_head_default_name(fi);
            if (!f->name || (dn && strcmp(f->name, dn) == 0)) continue;
        }
        m->field[m->n_rows] = (unsigned short)fi;
        if (f->type == KELP_DCCL_T_STATIC && f->static_value)
            (void)kelp_util_snprintf(m->val[m->n_rows], KELP_CMDR_VAL, "%s", f->static_value);
        m->n_rows++;
    }
    return (int)c->n_open++;
}

int kelp_commander_row(const kelp_commander_msg *m, const char *name)
{
    for (unsigned r = 0; r < m->n_rows; r++)
        if (strcmp(m->def->fields[m->field[r]].name, name) == 0) return (int)r;
    return -1;
}

const kelp_dccl_field *kelp_commander_row_field(const kelp_commander_msg *m, unsigned row)
{
    return row < m->n_rows ? &m->def->fields[m->field[row]] : NULL;
}

const char *kelp_commander_type_name(const kelp_dccl_field *f)
{
    switch (f->type) {
    case KELP_DCCL_T_FLOAT: return "float";
    case KELP_DCCL_T_BOOL: return "bool";
    case KELP_DCCL_T_STRING: return "string";
    case KELP_DCCL_T_ENUM: return "enum";
    case KELP_DCCL_T_HEX: return "hex";
    default: return is_static(f) ? "static" : "int";
    }
}

void kelp_commander_describe(const kelp_dccl_field *f, char *out, size_t cap)
{
    char lo[40], hi[40];
    int n = 0;
    switch (f->type) {
    case KELP_DCCL_T_INT:
    case KELP_DCCL_T_FLOAT:
        (void)kelp_util_fmt_fixed(lo, sizeof lo, f->min, (unsigned)(f->precision > 0 ? f->precision : 0), false);
        (void)kelp_util_fmt_fixed(hi, sizeof hi, f->max, (unsigned)(f->precision > 0 ? f->precision : 0), false);
        n = kelp_util_snprintf(out, cap, "(%s) range: %s to %s", kelp_commander_type_name(f), lo, hi);
        if (f->type == KELP_DCCL_T_FLOAT && n > 0 && (size_t)n < cap)
            n += kelp_util_snprintf(out + n, cap - (size_t)n, ", %d decimal places", f->precision);
        break;
    case KELP_DCCL_T_HEAD_SRC:
    case KELP_DCCL_T_HEAD_DEST: n = kelp_util_snprintf(out, cap, "(int) modem id: 0 to 31"); break;
    case KELP_DCCL_T_HEAD_TIME: n = kelp_util_snprintf(out, cap, "(int) UNIX time (t: current time)"); break;
    case KELP_DCCL_T_BOOL: n = kelp_util_snprintf(out, cap, "(bool) true or false"); break;
    case KELP_DCCL_T_STRING: n = kelp_util_snprintf(out, cap, "(string) at most %u characters", f->max_length); break;
    case KELP_DCCL_T_HEX: n = kelp_util_snprintf(out, cap, "(hex) exactly %u bytes (%u hex digits)", f->num_bytes,
                                            2u * f->num_bytes); break;
    case KELP_DCCL_T_ENUM:
        n = kelp_util_snprintf(out, cap, "(enum) one of:");
        for (unsigned i = 0; i < f->n_enum && n > 0 && (size_t)n < cap; i++)
            n += kelp_util_snprintf(out + n, cap - (size_t)n, " %s", f->enum_values[i]);
        break;
    default: n = kelp_util_snprintf(out, cap, "(static) you cannot change the value of this field"); break;
    }
    if (f->array_length > 1 && n > 0 && (size_t)n < cap)
        (void)kelp_util_snprintf(out + n, cap - (size_t)n, "; up to %u values separated by ','", f->array_length);
}

/* "y(lat)N:M" / "x(lon)N:M": *pair N, *metres M */
static bool xy_special(const char *s, size_t n, char *axis, long *pair, double *metres)
{
    if (n < 8 || (memcmp(s, "y(lat)", 6) != 0 && memcmp(s, "x(lon)", 6) != 0)) return false;
    const char *colon = memchr(s, ':', n);
    if (!colon || colon == s + 6) return false;
    if (kelp_util_parse_long(s + 6, (size_t)(colon - s) - 6, pair) < 0 || *pair < 1) return false;
    if (kelp_util_parse_finite(colon + 1, n - (size_t)(colon - s) - 1, metres) < 0) return false;
    *axis = s[0];
    return true;
}

static bool latlon_name(const char *name)
{
    for (const char *p = name; *p; p++)
        if (kelp_util_strieq_n(p, 3, "lat") || kelp_util_strieq_n(p, 3, "lon")) return true;
    return false;
}

static int check_one(const kelp_commander *c, const kelp_dccl_field *f, const char *s, size_t n, kelp_diag *d)
{
    double x;
    long l;
    char axis;
    bool special_time = n == 5 && memcmp(s, "_time", 5) == 0;
    switch (f->type) {
    case KELP_DCCL_T_INT:
    case KELP_DCCL_T_FLOAT:
        if (special_time) return KELP_OK;
        if (xy_special(s, n, &axis, &l, &x)) return KELP_OK;
        if (c->force_xy_only && f->type == KELP_DCCL_T_FLOAT && latlon_name(f->name)) {
            return kelp_fail(d, KELP_ERR_PARSE, "force_xy_only: give y(lat)N:metres or x(lon)N:metres");
        }
        if (kelp_util_parse_finite(s, n, &x) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "not a number");
        }
        if (f->type == KELP_DCCL_T_INT && x != floor(x)) {
            return kelp_fail(d, KELP_ERR_PARSE, "not a whole number");
        }
        if (x < f->min || x > f->max) {
            return kelp_fail(d, KELP_ERR_RANGE, "out of range");
        }
        return KELP_OK;
    case KELP_DCCL_T_HEAD_SRC:
    case KELP_DCCL_T_HEAD_DEST:
        if (kelp_util_parse_long(s, n, &l) < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "not a whole number");
        }
        if (l < 0 || l > 31) {
            return kelp_fail(d, KELP_ERR_RANGE, "out of range");
        }
        return KELP_OK;
    case KELP_DCCL_T_HEAD_TIME:
        if (special_time) return KELP_OK;
        if (kelp_util_parse_finite(s, n, &x) < 0 || x < 0) {
            return kelp_fail(d, KELP_ERR_PARSE, "not a UNIX time");
        }
        return KELP_OK;
    case KELP_DCCL_T_BOOL:
        /* what kelp_dccl_val_to_bool takes from a string: true/1/false/0, any case */
        if (!kelp_util_strieq_n(s, n, "true") && !kelp_util_strieq_n(s, n, "1") && !kelp_util_strieq_n(s, n, "false") &&
            !kelp_util_strieq_n(s, n, "0")) {
            return kelp_fail(d, KELP_ERR_PARSE, "not true or false");
        }
        return KELP_OK;
    case KELP_DCCL_T_ENUM:
        for (unsigned i = 0; i < f->n_enum; i++)
            if (strlen(f->enum_values[i]) == n && memcmp(f->enum_values[i], s, n) == 0) return KELP_OK;
        return kelp_fail(d, KELP_ERR_RANGE, "not one of the enum values");
    case KELP_DCCL_T_STRING:
        if (special_time) return KELP_OK;
        if (n > f->max_length) {
            return kelp_fail(d, KELP_ERR_RANGE, "longer than max_length");
        }
        if (memchr(s, '{', n) || memchr(s, '}', n)) {
            return kelp_fail(d, KELP_ERR_PARSE, "'{' and '}' cannot be sent");
        }
        return KELP_OK;
    case KELP_DCCL_T_HEX:
        if (n != 2u * f->num_bytes) {
            return kelp_fail(d, KELP_ERR_RANGE, "wrong number of hex digits");
        }
        for (size_t i = 0; i < n; i++)
            if (kelp_util_hex_digit(s[i]) < 0) {
                return kelp_fail(d, KELP_ERR_PARSE, "not hexadecimal");
            }
        return KELP_OK;
    default: return kelp_fail(d, KELP_ERR_RANGE, "(static) you cannot change the value of this field");
    }
}

int kelp_commander_check(const kelp_commander *c, const kelp_dccl_field *f, const char *val, kelp_diag *d)
{
    size_t n = strlen(val);
    if (is_static(f)) {
        if (f->type == KELP_DCCL_T_STATIC && f->static_value && strcmp(val, f->static_value) == 0) return KELP_OK;
        return kelp_fail(d, KELP_ERR_RANGE, "(static) you cannot change the value of this field");
    }
    if (n == 0) return KELP_OK;
    if (n >= KELP_CMDR_VAL) {
        return kelp_fail(d, KELP_ERR_RANGE, "too long");
    }
    if (f->array_length <= 1 || f->type == KELP_DCCL_T_STRING) return check_one(c, f, val, n, d);
    size_t a = 0;
    unsigned k = 0;
    for (size_t b = 0; b <= n; b++) {
        if (b < n && val[b] != ',') continue;
        if (++k > f->array_length) {
            return kelp_fail(d, KELP_ERR_RANGE, "more values than array_length");
        }
        if (b > a) {
            int rc = check_one(c, f, val + a, b - a, d);
            if (rc < 0) return rc;
        }
        a = b + 1;
    }
    return KELP_OK;
}

int kelp_commander_set(kelp_commander *c, unsigned msg, unsigned row, const char *val, kelp_diag *d)
{
    if (msg >= c->n_open || row >= c->open[msg].n_rows) return kelp_fail(d, KELP_ERR_ARG, "no such message or field");
    kelp_commander_msg *m = &c->open[msg];
    int rc = kelp_commander_check(c, kelp_commander_row_field(m, row), val, d);
    if (rc < 0) return rc;
    (void)kelp_util_snprintf(m->val[row], KELP_CMDR_VAL, "%s", val);
    m->edited = true;
    c->active = (int)msg;
    return KELP_OK;
}

void kelp_commander_clear(kelp_commander *c, unsigned msg)
{
    if (msg >= c->n_open) return;
    kelp_commander_msg *m = &c->open[msg];
    for (unsigned r = 0; r < m->n_rows; r++)
        if (!is_static(kelp_commander_row_field(m, r))) m->val[r][0] = 0;
}

unsigned kelp_commander_next_xy(const kelp_commander_msg *m)
{
    unsigned next = 1;
    for (unsigned r = 0; r < m->n_rows; r++) {
        char axis;
        long pair;
        double d;
        if (xy_special(m->val[r], strlen(m->val[r]), &axis, &pair, &d) && (unsigned long)pair >= next)
            next = (unsigned)pair + (axis == 'x' ? 1u : 0u);
    }
    return next;
}
