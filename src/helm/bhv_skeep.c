/* kelp helm: BHV_StationKeep as MOOS-IvP 24.8 behaves (facts from its BHV_StationKeep.cpp):
 * hold a station point. Outside the inner radius the vehicle steers for the station, at
 * outer_speed scaled by where it is between the inner and outer radius, at extra_speed beyond
 * the outer radius, at 0 inside; with a hibernation radius it drifts (speed 0) until it is
 * farther than that radius, then seeks the station until it is inside the inner radius or, once
 * its approach has started and ended (the distance falling, then no longer falling, over 5 s of
 * a 10 s history), inside the hibernation radius. center_activate takes the vehicle's position
 * as the station when the behaviour starts running (for swing_time seconds). Objective: a speed
 * peak (basewidth 0.4) coupled 50/50 with a course peak (basewidth 180) toward the station.
 * Posts DIST_TO_STATION, PSKEEP_MODE, the radii as VIEW_POLYGONs, BHV_SETTINGS. */
#include <math.h>
#include <string.h>
#include "helm_int.h"

enum { PS_DISABLED, PS_HIBERNATING, PS_SEEKING };
enum { TR_DISABLED, TR_HIBERNATING, TR_PENDING_START, TR_NOTED_START, TR_NOTED_END };

static const char *const PS_NAME[] = {"DISABLED", "HIBERNATING", "SEEKING_STATION"};

static void sk_init(kelp_bhv *b)
{
    kelp_bhv_skeep *s = &b->u.skeep;
    (void)hx_copy(b->name, sizeof b->name, "station_keep", 12);
    bhv_use_subdomain(b, "course,speed");
    s->outer_radius = 15;
    s->inner_radius = 4;
    s->outer_speed = 1.2;
    s->extra_speed = 2.5;
    s->pskeep_radius = -1;
    s->dist = -1;
    s->mark_time = -1;
    s->pskeep_state = PS_DISABLED;
    s->transit_state = TR_DISABLED;
    memcpy(s->vertex_color, "red", 4);
    memcpy(s->edge_color, "light_blue", 11);
    memcpy(s->label_color, "white", 6);
    s->vertex_size = s->edge_size = 1;
    hx_ignore(kelp_helm_bhv_add_info_vars(b, "NAV_X, NAV_Y")); /* a constructor cannot fail */
}

/* XYPoint's string2Point: "x,y", "x:y" or "x=..,y=.." */
static bool parse_point(const char *v, double *x, double *y)
{
    const char *sep = strpbrk(v, ",:");
    if (sep && hx_number(v, (size_t)(sep - v), x) && hx_number(sep + 1, strlen(sep + 1), y))
        return true;
    const char *px = strstr(v, "x="), *py = strstr(v, "y=");
    if (!px || !py)
        return false;
    size_t nx = strcspn(px + 2, ","), ny = strcspn(py + 2, ",");
    return hx_number(px + 2, nx, x) && hx_number(py + 2, ny, y);
}

/* a positive number ("<= 0" or text refused, as 24.8) */
static int positive(const char *v, double *out)
{
    double d;
    if (!hx_number(v, strlen(v), &d) || d <= 0)
        return KELP_ERR_PARSE;
    *out = d;
    return 0;
}

/* one visual hint "key=value": colours and sizes of the radii (others ignored, as 24.8) */
static void hint(kelp_bhv_skeep *s, const char *h, size_t n)
{
    while (n && *h == ' ') h++, n--;
    const char *eq = memchr(h, '=', n);
    if (!eq)
        return;
    size_t kl = (size_t)(eq - h), vl = n - kl - 1;
    while (kl && h[kl - 1] == ' ') kl--;
    const char *v = eq + 1;
    while (vl && *v == ' ') v++, vl--;
    while (vl && v[vl - 1] == ' ') vl--;
    static const char *const ckey[3] = {"vertex_color", "edge_color", "label_color"};
    char *const cdst[3] = {s->vertex_color, s->edge_color, s->label_color};
    for (int k = 0; k < 3; k++)
        if (kl == strlen(ckey[k]) && !strncmp(h, ckey[k], kl)) {
            if (vl && vl < sizeof s->vertex_color) hx_ignore(hx_copy(cdst[k], sizeof s->vertex_color, v, vl));
            return;
        }
    double d;
    if (!hx_number(v, vl, &d))
        return;
    if (kl == 9 && !strncmp(h, "edge_size", 9))
        s->edge_size = d;
    else if (kl == 11 && !strncmp(h, "vertex_size", 11))
        s->vertex_size = d;
}

static int sk_set_param(kelp_bhv *b, const char *p, const char *v)
{
    kelp_bhv_skeep *s = &b->u.skeep;
    double d;
    if (!strcmp(p, "station_pt") || !strcmp(p, "point")) {
        if (!parse_point(v, &s->static_x, &s->static_y))
            return KELP_ERR_PARSE;
        s->static_defined = true;
        s->center_pending = true;
        return 0;
    }
    if (!strcmp(p, "hibernation_radius")) {
        if (hx_ieq(v, "off") || !strcmp(v, "-1")) {
            s->pskeep_state = PS_DISABLED;
            s->pskeep_radius = -1;
            return 0;
        }
        if (positive(v, &s->pskeep_radius) < 0)
            return KELP_ERR_PARSE;
        if (s->pskeep_state == PS_DISABLED)
            s->pskeep_state = PS_HIBERNATING;
        return 0;
    }
    if (!strcmp(p, "center_activate")) {
        bool t;
        if (!bhv_parse_true_false(v, &t))
            return KELP_ERR_PARSE;
        s->center_activate = t;
        s->center_pending = true;
        return 0;
    }
    if (!strcmp(p, "outer_radius"))
        return positive(v, &s->outer_radius);
    if (!strcmp(p, "inner_radius"))
        return positive(v, &s->inner_radius);
    if (!strcmp(p, "outer_speed")) {
        if (positive(v, &s->outer_speed) < 0)
            return KELP_ERR_PARSE;
        if (s->extra_speed < s->outer_speed)
            s->extra_speed = s->outer_speed;
        return 0;
    }
    if (!strcmp(p, "swing_time")) {
        if (!hx_number(v, strlen(v), &d))
            return KELP_ERR_PARSE;
        s->swing_time = d < 0 ? 0 : d > 60 ? 60 : d;
        return 0;
    }
    if (!strcmp(p, "extra_speed") || !strcmp(p, "transit_speed"))
        return positive(v, &s->extra_speed);
    if (!strcmp(p, "visual_hints")) {
        for (const char *h = v; *h;) {
            size_t n = strcspn(h, ",");
            hint(s, h, n);
            h += n + (h[n] == ',');
        }
        return 0;
    }
    return KELP_ERR_NOTFOUND;
}

/* postConfigStatus: BHV_SETTINGS, repeatable */
static void sk_post_config(kelp_bhv *b)
{
    const kelp_bhv_skeep *s = &b->u.skeep;
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    hx_fmt_fixed(nb[0], sizeof nb[0], s->static_x, 2);
    hx_fmt_fixed(nb[1], sizeof nb[0], s->static_y, 2);
    hx_fmt_fixed(nb[2], sizeof nb[0], s->inner_radius, 1);
    hx_fmt_fixed(nb[3], sizeof nb[0], s->outer_radius, 1);
    hx_fmt_fixed(nb[4], sizeof nb[0], s->pskeep_radius, 1);
    hx_fmt_fixed(nb[5], sizeof nb[0], s->outer_speed, 1);
    hx_cat(buf, sizeof b->helm->ws_bhv.post, "type=BHV_StationKeep,name=", b->name, ",x=", nb[0], ",y=", nb[1],
           ",inner_radius=", nb[2], ",outer_radius=", nb[3], ",hibernation_radius=", nb[4], ",outer_speed=", nb[5],
           ",center_activate=", s->center_activate ? "true" : "false", HX_END);
    kelp_helm_bhv_post_string(b, "BHV_SETTINGS", buf, "repeatable");
}

/* postStationMessage: the outer, inner and hibernation circles as radial VIEW_POLYGONs (made
 * inactive when the behaviour stops running) */
KELP_NOINLINE static void post_station(kelp_bhv *b, bool on)
{
    const kelp_bhv_skeep *s = &b->u.skeep;
    char *buf = b->helm->ws_bhv.post, (*nb)[32] = b->helm->ws_bhv.num;
    const size_t cap = sizeof b->helm->ws_bhv.post;
    hx_fmt_fixed(nb[0], sizeof nb[0], s->station_x, 1);
    hx_fmt_fixed(nb[1], sizeof nb[0], s->station_y, 1);
    hx_fmt_x(nb[2], sizeof nb[0], s->edge_size, 5);
    hx_fmt_x(nb[3], sizeof nb[0], s->vertex_size, 5);
    static const char *const key[3] = {"outer", "inner", "hiber"};
    static const char *const lab[3] = {":station-keep-out", ":station-keep-in", ":station-keep-hiber"};
    const double rad[3] = {s->outer_radius, s->inner_radius, s->pskeep_radius};
    const bool want[3] = {true, !on || s->inner_radius < s->outer_radius, !on || s->pskeep_radius > s->outer_radius};
    for (int k = 0; k < 3; k++) {
        if (!want[k])
            continue;
        hx_fmt_fixed(nb[4], sizeof nb[0], rad[k], 1);
        size_t n = hx_cat(buf, cap, "radial:: x=", nb[0], ",y=", nb[1], ",source=", b->us, ":", b->name, ",pts=32",
                          s->edge_size >= 0 ? ",edge_size=" : "", s->edge_size >= 0 ? nb[2] : "",
                          s->vertex_size >= 0 ? ",vertex_size=" : "", s->vertex_size >= 0 ? nb[3] : "", HX_END);
        if (s->edge_color[0]) n += hx_cat(buf + n, cap - n, ",edge_color=", s->edge_color, HX_END);
        if (s->label_color[0]) n += hx_cat(buf + n, cap - n, ",label_color=", s->label_color, HX_END);
        if (s->vertex_color[0]) n += hx_cat(buf + n, cap - n, ",vertex_color=", s->vertex_color, HX_END);
        hx_cat(buf + n, cap - n, ",label=", b->us, lab[k], ",radius=", nb[4], on ? "" : ",active=false", HX_END);
        kelp_helm_bhv_post_string(b, "VIEW_POLYGON", buf, key[k]);
    }
}

static void hist_clear(kelp_bhv_skeep *s)
{
    s->hist_n = 0;
    s->hist_head = 0;
}

/* the approach's rate over the history (newest minus oldest over their time apart), when the
 * history spans more than 5 s */
static bool hist_rate(const kelp_bhv_skeep *s, double *rate)
{
    if (s->hist_n == 0)
        return false;
    unsigned old = (s->hist_head + KELP_SKEEP_HIST - (s->hist_n - 1)) % KELP_SKEEP_HIST;
    double dt = s->hist_t[s->hist_head] - s->hist_t[old];
    if (dt <= 5)
        return false;
    *rate = (s->hist_d[s->hist_head] - s->hist_d[old]) / dt;
    return true;
}

/* updateInfoIn: ownship, the station (set from the static point or, center_activate, from
 * ownship), the distance and its 10 s history. false: nothing to do this time */
KELP_NOINLINE static bool sk_info_in(kelp_bhv *b)
{
    kelp_bhv_skeep *s = &b->u.skeep;
    if (!bhv_platform_info(b, &s->osx, &s->osy, &s->osh))
        return false;
    double now = kelp_helm_bhv_buf_now(b);
    if (s->mark_time == -1)
        s->mark_time = now;
    bool moved = false;
    if (s->center_pending) {
        if (s->center_activate) {
            s->station_x = s->osx;
            s->station_y = s->osy;
            s->station_set = moved = true;
            if (now >= s->mark_time + s->swing_time)
                s->center_pending = false;
        } else if (s->static_defined) {
            s->station_x = s->static_x;
            s->station_y = s->static_y;
            s->station_set = moved = true;
            s->center_pending = false;
        }
    }
    if (moved) { /* 24.8 returns here: the distance and its history wait for the next run */
        s->pskeep_state = PS_HIBERNATING;
        s->transit_state = TR_HIBERNATING;
        return true;
    }
    s->dist = hypot(s->osx - s->station_x, s->osy - s->station_y);
    s->hist_head = (s->hist_head + 1) % KELP_SKEEP_HIST;
    s->hist_d[s->hist_head] = s->dist;
    s->hist_t[s->hist_head] = now;
    if (s->hist_n < KELP_SKEEP_HIST)
        s->hist_n++;
    while (s->hist_n > 1) { /* older than 10 s */
        unsigned old = (s->hist_head + KELP_SKEEP_HIST - (s->hist_n - 1)) % KELP_SKEEP_HIST;
        if (now - s->hist_t[old] <= 10)
            break;
        s->hist_n--;
    }
    return true;
}

/* updateHibernationState */
static void sk_hibernation(kelp_bhv_skeep *s)
{
    if (s->pskeep_state == PS_DISABLED)
        return;
    double rate;
    if (s->transit_state == TR_PENDING_START) {
        if (s->dist <= s->pskeep_radius && hist_rate(s, &rate) && rate <= 0) {
            hist_clear(s);
            s->transit_state = TR_NOTED_START;
        }
    } else if (s->transit_state == TR_NOTED_START) {
        if (hist_rate(s, &rate) && rate >= 0)
            s->transit_state = TR_NOTED_END;
    }
    if (s->pskeep_state == PS_HIBERNATING) {
        if (s->dist > s->pskeep_radius) {
            s->pskeep_state = PS_SEEKING;
            hist_clear(s);
            s->transit_state = TR_PENDING_START;
        }
        return;
    }
    if (s->dist <= s->inner_radius || (s->transit_state == TR_NOTED_END && s->dist <= s->pskeep_radius)) {
        s->pskeep_state = PS_HIBERNATING;
        s->transit_state = TR_HIBERNATING;
        hist_clear(s);
    }
}

static void sk_on_idle(kelp_bhv *b)
{
    kelp_bhv_skeep *s = &b->u.skeep;
    if (!s->was_running)
        return;
    s->was_running = false; /* onRunToIdleState */
    hist_clear(s);
    post_station(b, false);
    if (s->center_activate)
        s->center_pending = true;
    s->mark_time = -1;
}

static int sk_run(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out)
{
    kelp_bhv_skeep *s = &b->u.skeep;
    if (!s->was_running) { /* onIdleToRunState */
        s->was_running = true;
        sk_post_config(b);
    }
    if (!sk_info_in(b))
        return 0;
    kelp_helm_bhv_post_double(b, "DIST_TO_STATION", s->dist, NULL);
    if (!s->station_set) {
        kelp_helm_bhv_post_warning(b, "STATION_POINT_NOT_SET");
        post_station(b, false);
        return 0;
    }
    if (s->inner_radius > s->outer_radius)
        s->outer_radius = s->inner_radius;
    sk_hibernation(s);
    kelp_helm_bhv_post_string(b, "PSKEEP_MODE", PS_NAME[s->pskeep_state], NULL);
    post_station(b, true);
    double crs = s->center_pending ? s->osh : kelp_helm_relang(s->osx, s->osy, s->station_x, s->station_y);
    double speed = 0;
    if (s->pskeep_state == PS_HIBERNATING || s->dist <= s->inner_radius)
        speed = 0;
    else if (s->dist < s->outer_radius)
        speed = (s->dist - s->inner_radius) / (s->outer_radius - s->inner_radius) * s->outer_speed;
    else
        speed = s->extra_speed;
    if (bhv_course_speed_zaic(b, w, crs, speed, 0, 0.4, 0, out) < 0) {
        kelp_helm_bhv_post_warning(b, "Problem Creating the IvP Function");
        return 0;
    }
    return 1;
}

const kelp_bhv_ops kelp_bhv_station_keep_ops = {
    .type = "BHV_StationKeep", .init = sk_init, .set_param = sk_set_param, .on_idle = sk_on_idle,
    .on_run = sk_run, .post_config = sk_post_config,
};
