/* VIEW_* artifact parsing (see include/kelp/nodereport.h). */
#include <math.h>
#include <string.h>
#include <kelp/nodereport.h>
#include <kelp/mission.h>
#include "field_int.h"

static const char *const var_names[KELP_VIEW_NKINDS] = {
    "VIEW_POINT", "VIEW_CIRCLE", "VIEW_POLYGON", "VIEW_SEGLIST", "VIEW_MARKER", "VIEW_COMMS_PULSE", "VIEW_RANGE_PULSE",
};

const char *kelp_nodereport_view_var(kelp_view_kind kind)
{
    return (unsigned)kind < KELP_VIEW_NKINDS ? var_names[kind] : "?";
}

int kelp_nodereport_view_kind_of(const char *var, kelp_view_kind *out)
{
    if (!var) return KELP_ERR_NOTFOUND;
    for (int k = 0; k < KELP_VIEW_NKINDS; k++)
        if (kelp_util_strieq_n(var, strlen(var), var_names[k])) {
            *out = (kelp_view_kind)k;
            return KELP_OK;
        }
    if (kelp_util_strieq_n(var, strlen(var), "VIEW_COMM_PULSE")) { /* seed 000 spelling */
        *out = KELP_VIEW_COMMS_PULSE;
        return KELP_OK;
    }
    return KELP_ERR_NOTFOUND;
}

typedef struct vparse {
    kelp_view *v;
    kelp_diag *d;
} vparse;

/* "x,y[,z]" -> a vertex */
static int add_vertex(vparse *p, const char *s, size_t n)
{
    double c[3];
    int k = 0;
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(s, n, &pos, ',', &it, &il)) == 1) {
        if (k >= 3 || sim_number(it, il, &c[k]) < 0) {
            return kelp_fail(p->d, KELP_ERR_PARSE, "bad vertex");
        }
        k++;
    }
    if (rc < 0 || k < 2) {
        return kelp_fail(p->d, KELP_ERR_PARSE, "bad vertex");
    }
    kelp_view *v = p->v;
    if (v->npts >= KELP_VIEW_MAX_PTS) {
        return kelp_fail(p->d, KELP_ERR_NOSPACE, "too many vertices");
    }
    v->pts[v->npts][0] = c[0];
    v->pts[v->npts][1] = c[1];
    v->npts++;
    return KELP_OK;
}

/* pts={x1,y1:x2,y2:...} (braces already removed) */
static int add_pts(vparse *p, const char *s, size_t n)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(s, n, &pos, ':', &it, &il)) == 1) {
        int r2 = add_vertex(p, it, il);
        if (r2 < 0) return r2;
    }
    if (rc < 0) {
        return kelp_fail(p->d, KELP_ERR_PARSE, "bad pts");
    }
    return KELP_OK;
}

static int set_text(vparse *p, char *dst, const char *v, size_t vl)
{
    if (field_copy_text(dst, KELP_VIEW_MAX_FIELD, v, vl) < 0) {
        return kelp_fail(p->d, KELP_ERR_RANGE, "text field too long");
    }
    return KELP_OK;
}

static int on_pair(void *ctx, const char *k, size_t kl, const char *v, size_t vl)
{
    vparse *p = ctx;
    kelp_view *w = p->v;
    static const struct {
        const char *key;
        uint32_t bit;
        size_t off;
    } nums[] = {
        {"x", KELP_VF_X, offsetof(kelp_view, x)},
        {"sx", KELP_VF_X, offsetof(kelp_view, x)},
        {"y", KELP_VF_Y, offsetof(kelp_view, y)},
        {"sy", KELP_VF_Y, offsetof(kelp_view, y)},
        {"tx", KELP_VF_TX, offsetof(kelp_view, tx)},
        {"ty", KELP_VF_TY, offsetof(kelp_view, ty)},
        {"radius", KELP_VF_RADIUS, offsetof(kelp_view, radius)},
        {"duration", KELP_VF_DURATION, offsetof(kelp_view, duration)},
        {"time", KELP_VF_TIME, offsetof(kelp_view, time)},
        {"fill", KELP_VF_FILL, offsetof(kelp_view, fill)},
        {"fill_transparency", KELP_VF_FILL, offsetof(kelp_view, fill)},
        {"width", KELP_VF_WIDTH, offsetof(kelp_view, width)},
        {"edge_size", KELP_VF_EDGE_SIZE, offsetof(kelp_view, edge_size)},
        {"vertex_size", KELP_VF_VERTEX_SIZE, offsetof(kelp_view, vertex_size)},
        {"beam_width", 0, offsetof(kelp_view, beam_width)},
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if (kelp_util_strieq_n(k, kl, nums[i].key)) {
            double d;
            if (sim_number(v, vl, &d) < 0) {
                return kelp_fail(p->d, KELP_ERR_PARSE, "bad number");
            }
            memcpy((char *)w + nums[i].off, &d, sizeof d);
            w->fields |= nums[i].bit;
            return KELP_OK;
        }
    static const struct {
        const char *key;
        size_t off;
    } texts[] = {
        {"label", offsetof(kelp_view, label)},
        {"type", offsetof(kelp_view, type)},
        {"source", offsetof(kelp_view, source)},
        {"msg", offsetof(kelp_view, msg)},
        {"edge_color", offsetof(kelp_view, edge_color)},
        {"fill_color", offsetof(kelp_view, fill_color)},
        {"color", offsetof(kelp_view, fill_color)},
        {"primary_color", offsetof(kelp_view, fill_color)},
        {"vertex_color", offsetof(kelp_view, vertex_color)},
        {"label_color", offsetof(kelp_view, label_color)},
    };
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        if (kelp_util_strieq_n(k, kl, texts[i].key)) return set_text(p, (char *)w + texts[i].off, v, vl);
    if (kelp_util_strieq_n(k, kl, "active")) {
        if (kelp_util_strieq_n(v, vl, "true")) w->active = true;
        else if (kelp_util_strieq_n(v, vl, "false")) w->active = false;
        else {
            return kelp_fail(p->d, KELP_ERR_PARSE, "active must be true or false");
        }
        return KELP_OK;
    }
    if (kelp_util_strieq_n(k, kl, "pts")) {
        if (vl < 2 || v[0] != '{' || v[vl - 1] != '}') {
            return kelp_fail(p->d, KELP_ERR_PARSE, "pts must be {x,y:x,y:...}");
        }
        return add_pts(p, v + 1, vl - 2);
    }
    return KELP_OK; /* unknown key: ignored */
}

static bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }

/* the colon form: "active,false:label,L:type,waypoint:source,S:0,0,0" */
static int parse_colon(vparse *p, const char *s, size_t len)
{
    size_t pos = 0;
    const char *it;
    size_t il;
    int rc;
    while ((rc = field_next_item(s, len, &pos, ':', &it, &il)) == 1) {
        if (is_alpha(it[0])) {
            const char *c = memchr(it, ',', il);
            if (!c) {
                return kelp_fail(p->d, KELP_ERR_PARSE, "segment without ','");
            }
            const char *k = it, *v = c + 1;
            size_t kl = (size_t)(c - it), vl = il - kl - 1;
            while (kl && k[kl - 1] == ' ') kl--;
            while (vl && *v == ' ') v++, vl--;
            int r2 = on_pair(p, k, kl, v, vl);
            if (r2 < 0) return r2;
        } else {
            int r2 = add_vertex(p, it, il);
            if (r2 < 0) return r2;
        }
    }
    if (rc < 0) {
        return kelp_fail(p->d, KELP_ERR_PARSE, "unbalanced brace or quote");
    }
    return KELP_OK;
}

static bool has_eq_outside_braces(const char *s, size_t len)
{
    int depth = 0;
    for (size_t i = 0; i < len && s[i]; i++) {
        if (s[i] == '{') depth++;
        else if (s[i] == '}') depth--;
        else if (s[i] == '=' && depth == 0) return true;
    }
    return false;
}

int kelp_nodereport_view_parse(kelp_view_kind kind, const char *s, size_t len, kelp_view *out, kelp_diag *d)
{
    if (!s || !out || (unsigned)kind >= KELP_VIEW_NKINDS) {
        return kelp_fail(d, KELP_ERR_ARG, "bad argument");
    }
    kelp_view *v = out;
    memset(v, 0, sizeof *v);
    v->kind = kind;
    v->active = true;
    v->edge_size = 1;
    if (kind == KELP_VIEW_RANGE_PULSE) { /* defaults of the uField seed */
        v->radius = 40;
        v->duration = 15;
        v->fill = 0.25;
        memcpy(v->fill_color, "green", 6);
        memcpy(v->edge_color, "green", 6);
    } else if (kind == KELP_VIEW_COMMS_PULSE) {
        v->beam_width = 7;
        v->duration = 10;
        v->fill = 0.35;
    }
    while (len && (s[len - 1] == ' ' || s[len - 1] == '\n' || s[len - 1] == '\r')) len--;
    while (len && *s == ' ') s++, len--;
    if (len >= 2 && s[0] == '"' && s[len - 1] == '"') s++, len -= 2;
    vparse p = {v, d};
    int rc = has_eq_outside_braces(s, len) ? field_for_pairs(s, len, ',', on_pair, &p, d) : parse_colon(&p, s, len);
    if (rc < 0) return rc;
    /* the colon form gives a point as its vertex */
    if ((kind == KELP_VIEW_POINT || kind == KELP_VIEW_MARKER || kind == KELP_VIEW_CIRCLE) &&
        !(v->fields & (KELP_VF_X | KELP_VF_Y)) && v->npts >= 1) {
        v->x = v->pts[0][0];
        v->y = v->pts[0][1];
        v->fields |= KELP_VF_X | KELP_VF_Y;
    }
    const uint32_t XY = KELP_VF_X | KELP_VF_Y;
    switch (kind) {
    case KELP_VIEW_POINT:
    case KELP_VIEW_MARKER:
    case KELP_VIEW_RANGE_PULSE:
        if ((v->fields & XY) != XY) return kelp_fail(d, KELP_ERR_PARSE, "needs x and y");
        break;
    case KELP_VIEW_CIRCLE:
        if ((v->fields & XY) != XY) return kelp_fail(d, KELP_ERR_PARSE, "needs x and y");
        if (!(v->fields & KELP_VF_RADIUS) || v->radius <= 0) return kelp_fail(d, KELP_ERR_PARSE, "needs a radius > 0");
        break;
    case KELP_VIEW_COMMS_PULSE:
        if ((v->fields & (XY | KELP_VF_TX | KELP_VF_TY)) != (XY | KELP_VF_TX | KELP_VF_TY))
            return kelp_fail(d, KELP_ERR_PARSE, "needs sx, sy, tx and ty");
        break;
    default: /* polygon, seglist */
        if (v->npts == 0 && v->active) return kelp_fail(d, KELP_ERR_PARSE, "needs at least one vertex");
        break;
    }
    if (v->fill < 0) v->fill = 0;
    if (v->fill > 1) v->fill = 1;
    return KELP_OK;
}
