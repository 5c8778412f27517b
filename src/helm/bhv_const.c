/* kelp helm: BHV_ConstantDepth, BHV_ConstantSpeed, BHV_ConstantHeading: one ZAIC_PEAK over
 * one decision variable (depth: peakwidth 3, basewidth 100, summitdelta 50 by default). */
#include <math.h>
#include <string.h>
#include "helm_int.h"

typedef struct c1_kind {
    const char *var;       /* domain variable */
    const char *param;     /* the value parameter */
    double pw, bw, sd;     /* defaults */
    bool wrap;
    const char *nav;       /* the navigation variable compared for the mismatch */
    const char *mismatch;  /* its parameter */
} c1_kind;

static const c1_kind K_DEPTH = {"depth", "depth", 3, 100, 50, false, "NAV_DEPTH", "depth_mismatch_var"};
static const c1_kind K_SPEED = {"speed", "speed", 0, 1, 0, false, "NAV_SPEED", "speed_mismatch_var"};
static const c1_kind K_HEADING = {"course", "heading", 0, 180, 0, true, "NAV_HEADING", "heading_mismatch_var"};

static const c1_kind *kind_of(const kelp_bhv *b)
{
    if (b->ops == &kelp_bhv_constant_depth_ops)
        return &K_DEPTH;
    if (b->ops == &kelp_bhv_constant_speed_ops)
        return &K_SPEED;
    return &K_HEADING;
}

static void c1_init(kelp_bhv *b)
{
    const c1_kind *k = kind_of(b);
    kelp_bhv_c1 *s = &b->u.c1;
    bhv_use_subdomain(b, k->var);
    s->value = 0;
    s->have_value = false;
    s->peakwidth = k->pw;
    s->basewidth = k->bw;
    s->summitdelta = k->sd;
}

static int c1_set_param(kelp_bhv *b, const char *p, const char *v)
{
    const c1_kind *k = kind_of(b);
    kelp_bhv_c1 *s = &b->u.c1;
    double d;
    bool num = hx_number(v, strlen(v), &d);
    if (!strcmp(p, k->param) || (k == &K_HEADING && !strcmp(p, "course"))) {
        if (!num || (k != &K_HEADING && d < 0))
            return KELP_ERR_PARSE;
        s->value = d;
        s->have_value = true;
        return 0;
    }
    if (!strcmp(p, k->mismatch)) {
        if (!hx_copy(s->mismatch_var, sizeof s->mismatch_var, v, strlen(v)) || strpbrk(v, " ,="))
            return KELP_ERR_PARSE;
        return kelp_helm_bhv_add_info_vars(b, k->nav) < 0 ? KELP_ERR_NOSPACE : 0;
    }
    if (k == &K_HEADING && !strcmp(p, "complete_thresh")) {
        if (!num || d < 0)
            return KELP_ERR_PARSE;
        s->complete_thresh = d;
        return kelp_helm_bhv_add_info_vars(b, k->nav) < 0 ? KELP_ERR_NOSPACE : 0;
    }
    double *dst = !strcmp(p, "peakwidth") ? &s->peakwidth
                  : !strcmp(p, "basewidth") ? &s->basewidth
                  : !strcmp(p, "summitdelta") ? &s->summitdelta
                  : NULL;
    if (!dst)
        return KELP_ERR_NOTFOUND;
    if (!num || d < 0)
        return KELP_ERR_PARSE;
    *dst = d;
    return 0;
}

static int c1_params_done(kelp_bhv *b)
{
    if (!b->u.c1.have_value)
        return kelp_helm_bhv_fail(b, kind_of(b) == &K_DEPTH ? "depth not set"
                                : kind_of(b) == &K_SPEED ? "speed not set" : "heading not set");
    return 0;
}

static int c1_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    const c1_kind *k = kind_of(b);
    const kelp_bhv_c1 *s = &b->u.c1;
    double v = s->value;
    if (k->wrap) {
        while (v < 0)
            v += 360;
        while (v >= 360)
            v -= 360;
    }
    kelp_time now;
    if ((s->mismatch_var[0] || s->complete_thresh > 0) && kelp_helm_bhv_buf_double(b, k->nav, &now)) {
        double diff = fabs(v - now);
        if (k->wrap) {
            diff = fmod(diff, 360.0);
            if (diff > 180)
                diff = 360 - diff;
        }
        if (s->mismatch_var[0])
            kelp_helm_bhv_post_double(b, s->mismatch_var, diff, NULL);
        if (s->complete_thresh > 0 && diff <= s->complete_thresh) {
            kelp_helm_bhv_set_complete(b);
            return 0;
        }
    }
    if (bhv_zaic1(b, w, k->var, v, s->peakwidth, s->basewidth, s->summitdelta, k->wrap, out) < 0) {
        kelp_helm_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

const kelp_bhv_ops kelp_bhv_constant_depth_ops = {
    .type = "BHV_ConstantDepth", .init = c1_init, .set_param = c1_set_param,
    .params_done = c1_params_done, .on_run = c1_run,
};
const kelp_bhv_ops kelp_bhv_constant_speed_ops = {
    .type = "BHV_ConstantSpeed", .init = c1_init, .set_param = c1_set_param,
    .params_done = c1_params_done, .on_run = c1_run,
};
const kelp_bhv_ops kelp_bhv_constant_heading_ops = {
    .type = "BHV_ConstantHeading", .init = c1_init, .set_param = c1_set_param,
    .params_done = c1_params_done, .on_run = c1_run,
};

const kelp_bhv_ops *const kelp_bhv_builtin_types[] = {
    &kelp_bhv_simple_waypoint_ops, &kelp_bhv_waypoint_ops, &kelp_bhv_loiter_ops,
    &kelp_bhv_constant_depth_ops, &kelp_bhv_constant_speed_ops, &kelp_bhv_constant_heading_ops, &kelp_bhv_avoid_collision_ops,
    &kelp_bhv_station_keep_ops, NULL,
};
