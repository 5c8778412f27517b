/* kelp helm: BHV_SimpleWaypoint, exactly as seed 004 chapter 5 describes it. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

#define DEG_PER_RAD 57.29577951308232
#define SWPT_REFLECTOR_PIECES 1000  /* Listing 14: reflector.create(1000) */

static void swpt_init(kelp_bhv *b)
{
    kelp_bhv_swpt *s = &b->u.swpt;
    /* Listing 9: name "simple_waypoint", subDomain "course,speed", defaults, NAV_X/NAV_Y */
    (void)hx_copy(b->name, sizeof b->name, "simple_waypoint", 15);
    bhv_use_subdomain(b, "course,speed");
    s->desired_speed = 0;
    s->arrival_radius = 10;
    s->reflector = false;
    s->osx = s->osy = 0;
    s->nextpt.x = s->nextpt.y = 0;
    hx_ignore(kelp_helm_bhv_add_info_vars(b, "NAV_X, NAV_Y")); /* a constructor cannot fail: a full list only skips the registration */
}

/* Listing 10 */
static int swpt_set_param(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_swpt *s = &b->u.swpt;
    double d;
    bool num = hx_number(v, strlen(v), &d);
    if (!strcmp(p, "ptx") && num) {
        s->nextpt.x = d;
        return 0;
    }
    if (!strcmp(p, "pty") && num) {
        s->nextpt.y = d;
        return 0;
    }
    if (!strcmp(p, "speed") && num && d > 0) {
        s->desired_speed = d;
        return 0;
    }
    if (!strcmp(p, "radius") && num && d > 0) {
        s->arrival_radius = d;
        return 0;
    }
    if (!strcmp(p, "ipf_type")) {
        if (hx_ieq(v, "zaic")) {
            s->reflector = false;
            return 0;
        }
        if (hx_ieq(v, "reflector")) {
            s->reflector = true;
            return 0;
        }
        return KELP_ERR_PARSE;
    }
    if (!strcmp(p, "ptx") || !strcmp(p, "pty") || !strcmp(p, "speed") || !strcmp(p, "radius"))
        return KELP_ERR_PARSE;
    return KELP_ERR_NOTFOUND;
}

/* Listing 11: VIEW_POINT (kelp writes one key=value form for both states, see H10) */
static void post_view_point(kelp_bhv *b, bool viewable)
{
    const kelp_bhv_swpt *s = &b->u.swpt;
    /* composed in the helm's behaviour workspace (the text's bound as before: two names and 128) */
    char *spec = b->helm->ws_bhv.post, *x = b->helm->ws_bhv.num[0], *y = b->helm->ws_bhv.num[1];
    const size_t cap = KELP_MAX_NAME * 2 + 128;
    KELP_STATIC_ASSERT(KELP_MAX_NAME * 2 + 128 <= sizeof b->helm->ws_bhv.post, "VIEW_POINT text fits ws_bhv.post");
    hx_fmt_double(x, sizeof b->helm->ws_bhv.num[0], s->nextpt.x);
    hx_fmt_double(y, sizeof b->helm->ws_bhv.num[1], s->nextpt.y);
    hx_cat(spec, cap, "label=", b->us[0] ? b->us : "vehicle", "'s next waypoint,type=waypoint,source=", b->name,
           ",x=", x, ",y=", y, ",active=", viewable ? "true" : "false", HX_END);
    kelp_helm_bhv_post_string(b, "VIEW_POINT", spec, NULL);
}

static void swpt_idle(kelp_bhv *b)
{
    post_view_point(b, false);
}

static double angle360(double a)
{
    a = fmod(a, 360.0);
    return a < 0 ? a + 360.0 : a;
}

double kelp_helm_bhv_swpt_aof_eval(const double *pt, void *user)
{
    const kelp_bhv_swpt_aof *a = user;
    double crs = pt[a->icrs], spd = pt[a->ispd];
    double diff = angle360(crs - a->angle_to_wpt);
    /* (a) rate of closure */
    double roc = cos(diff / DEG_PER_RAD) * spd;
    double roc_diff = a->desired_speed - roc;
    if (roc_diff < 0)
        roc_diff *= -0.5;
    if (roc_diff > 2 * a->max_speed)
        roc_diff = 2 * a->max_speed;
    double score_roc = (1 - roc_diff / (2 * a->max_speed)) * 100;
    /* (b) rate of detour */
    double a180 = diff > 180 ? 360 - diff : diff;
    double rod = a180 * (spd > 0 ? spd : 0);
    double score_rod = (1 - rod / (a->max_speed * 180)) * 100;
    /* (c) deviation from the desired speed */
    double range = fmax(a->max_speed - a->desired_speed, a->desired_speed - a->min_speed);
    double score_spd = 100;
    if (range > 0) {
        double sd = fmin(fabs(a->desired_speed - spd), range);
        score_spd = (1 - sd / range) * 100;
    }
    return 0.75 * score_roc + 0.2 * score_rod + 0.05 * score_spd;
}

/* Listing 14 */
static int build_reflector(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    const kelp_bhv_swpt *s = &b->u.swpt;
    kelp_bhv_swpt_aof *a = &b->helm->ws_bhv.swpt_aof; /* the helm's workspace, not the stack */
    a->icrs = kelp_ivp_domain_index(&b->dom, "course");
    a->ispd = kelp_ivp_domain_index(&b->dom, "speed");
    if (a->icrs < 0 || a->ispd < 0)
        return KELP_ERR_NOTFOUND;
    a->desired_speed = s->desired_speed;
    a->osx = s->osx;
    a->osy = s->osy;
    a->ptx = s->nextpt.x;
    a->pty = s->nextpt.y;
    a->angle_to_wpt = kelp_helm_relang(a->osx, a->osy, a->ptx, a->pty);
    a->min_speed = b->dom.var[a->ispd].low;
    a->max_speed = b->dom.var[a->ispd].high;
    if (a->max_speed <= 0)
        return KELP_ERR_RANGE; /* initialize() fails */
    kelp_ivp_reflector *r = &b->helm->ws_bhv.refl;   /* the helm's workspace, not the stack */
    hx_ignore(kelp_ivp_reflector_init(r, &b->dom, kelp_helm_bhv_swpt_aof_eval, a));
    /* the Reflector wants as many work entries as piece capacity */
    size_t cap = w->out_cap < w->pq_cap ? w->out_cap : w->pq_cap;
    int rc = kelp_ivp_reflector_create(r, SWPT_REFLECTOR_PIECES, -1, 0, w->out, cap, w->pq, kelp_ivp_reflector_work_len(cap), out);
    return rc < 0 ? rc : 0;
}

/* Listing 12 */
static int swpt_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    kelp_bhv_swpt *s = &b->u.swpt;
    bool ok1 = kelp_helm_bhv_buf_double(b, "NAV_X", &s->osx);
    bool ok2 = kelp_helm_bhv_buf_double(b, "NAV_Y", &s->osy);
    if (!ok1 || !ok2) {
        kelp_helm_bhv_post_warning(b, "No ownship X/Y info in info_buffer.");
        return 0;
    }
    double dist = hypot(s->nextpt.x - s->osx, s->nextpt.y - s->osy);
    if (dist <= s->arrival_radius) {
        kelp_helm_bhv_set_complete(b);
        post_view_point(b, false);
        return 0;
    }
    post_view_point(b, true);
    int rc;
    if (!s->reflector) {
        /* Listing 13: speed peak (0.5, 1.0, 0.8), course peak (0, 180, 0, wrap), 50/50 */
        double crs = kelp_helm_relang(s->osx, s->osy, s->nextpt.x, s->nextpt.y);
        rc = bhv_course_speed_zaic(b, w, crs, s->desired_speed, 0.5, 1.0, 0.8, out);
    } else {
        rc = build_reflector(b, w, out);
    }
    if (rc < 0) {
        kelp_helm_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

const kelp_bhv_ops kelp_bhv_simple_waypoint_ops = {
    .type = "BHV_SimpleWaypoint",
    .init = swpt_init,
    .set_param = swpt_set_param,
    .on_idle = swpt_idle,
    .on_run = swpt_run,
};
