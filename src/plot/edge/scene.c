/* kelp-plot: gathering tracks and artifacts from bus writes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <kelp/mission.h>
#include <errno.h>
#include <stdio.h>
#include <kelp/edge/lcmlog.h>
#include <kelp/edge/plot.h>

void kelp_plot_scene_init(kelp_plot_scene *s)
{
    memset(s, 0, sizeof *s);
    s->t0 = INFINITY;
    s->t1 = -INFINITY;
}

void kelp_plot_scene_free(kelp_plot_scene *s)
{
    for (size_t i = 0; i < s->ntracks; i++) free(s->tracks[i].pts);
    free(s->tracks);
    free(s->views);
    memset(s, 0, sizeof *s);
}

kelp_plot_track *kelp_plot_scene_track(kelp_plot_scene *s, const char *name)
{
    for (size_t i = 0; i < s->ntracks; i++)
        if (strcasecmp(s->tracks[i].name, name) == 0) return &s->tracks[i];
    return NULL;
}

static kelp_plot_track *track_get(kelp_plot_scene *s, const char *name, kelp_plot_src src)
{
    for (size_t i = 0; i < s->ntracks; i++)
        if (s->tracks[i].src == src && strcasecmp(s->tracks[i].name, name) == 0) return &s->tracks[i];
    if (s->ntracks == s->tcap) {
        size_t nc = s->tcap ? s->tcap * 2 : 8;
        kelp_plot_track *t = realloc(s->tracks, nc * sizeof *t);
        if (!t) return NULL;
        s->tracks = t;
        s->tcap = nc;
    }
    kelp_plot_track *t = &s->tracks[s->ntracks++];
    memset(t, 0, sizeof *t);
    snprintf(t->name, sizeof t->name, "%s", name);
    t->src = src;
    return t;
}

static void track_add(kelp_plot_track *t, double time, double x, double y, double hdg, double spd)
{
    if (t->n == t->cap) {
        size_t nc = t->cap ? t->cap * 2 : 256;
        kelp_plot_pt *p = realloc(t->pts, nc * sizeof *p);
        if (!p) return;
        t->pts = p;
        t->cap = nc;
    }
    t->pts[t->n++] = (kelp_plot_pt){time, x, y, hdg, spd};
}

static void span(kelp_plot_scene *s, double t)
{
    if (!isfinite(t)) return;
    if (t < s->t0) s->t0 = t;
    if (t > s->t1) s->t1 = t;
}

static bool same_key(const kelp_plot_view *a, const kelp_view *b, const char *community)
{
    if (a->v.kind != b->kind || strcmp(a->v.label, b->label) != 0) return false;
    /* a pulse is an event, not a shape that moves: every one is drawn (a picture of a whole
     * run shows all the relays and acoustic messages, not only the last of each label) */
    if (b->kind == KELP_VIEW_COMMS_PULSE || b->kind == KELP_VIEW_RANGE_PULSE) return false;
    /* points of different behaviours may share a label ("alder's next waypoint") */
    if (b->kind == KELP_VIEW_POINT && strcmp(a->v.source, b->source) != 0) return false;
    /* the same label from two communities: two vehicles' behaviours of the same name */
    return strcmp(a->community, community) == 0;
}

static void add_view(kelp_plot_scene *s, const kelp_var *var, kelp_view_kind kind)
{
    kelp_view v;
    kelp_diag dg = { 0 };
    if (kelp_nodereport_view_parse(kind, var->sval, var->slen, &v, &dg) < 0) {
        s->bad_views++;
        snprintf(s->last_bad, sizeof s->last_bad, "%s: %s", var->name, dg.code ? kelp_diag_text(&dg) : "?");
        return;
    }
    /* an unlabelled point/marker is keyed by its position too (several may coexist) */
    for (size_t i = 0; i < s->nviews; i++) {
        kelp_plot_view *pv = &s->views[i];
        if (!same_key(pv, &v, var->community)) continue;
        if (!v.label[0] && (kind == KELP_VIEW_POINT || kind == KELP_VIEW_MARKER || kind == KELP_VIEW_CIRCLE) &&
            (pv->v.x != v.x || pv->v.y != v.y))
            continue;
        /* a newer posting replaces the old; an erase keeps the geometry, marked inactive */
        if (!v.active && ((kind == KELP_VIEW_POLYGON || kind == KELP_VIEW_SEGLIST) && v.npts == 0)) {
            pv->v.active = false;
        } else {
            pv->v = v;
        }
        pv->t_last = var->time;
        pv->posts++;
        return;
    }
    if (!v.active && (kind == KELP_VIEW_POLYGON || kind == KELP_VIEW_SEGLIST) && v.npts == 0) return;
    if (s->nviews == s->vcap) {
        size_t nc = s->vcap ? s->vcap * 2 : 32;
        kelp_plot_view *p = realloc(s->views, nc * sizeof *p);
        if (!p) return;
        s->views = p;
        s->vcap = nc;
    }
    kelp_plot_view *pv = &s->views[s->nviews++];
    memset(pv, 0, sizeof *pv);
    pv->v = v;
    snprintf(pv->community, sizeof pv->community, "%s", var->community);
    pv->t_first = pv->t_last = var->time;
    pv->posts = 1;
}

static double num(const kelp_var *v)
{
    double d = v->dval;
    if (v->kind == KELP_VAR_STRING && kelp_util_parse_double(v->sval, v->slen, &d) < 0) return NAN;
    if (v->kind == KELP_VAR_BINARY) return NAN;
    return d;
}

void kelp_plot_scene_add_var(kelp_plot_scene *s, const kelp_var *v)
{
    s->vars++;
    if (strncmp(v->name, "NODE_REPORT", 11) == 0 && v->kind == KELP_VAR_STRING &&
        (strcmp(v->name, "NODE_REPORT") == 0 || strcmp(v->name, "NODE_REPORT_LOCAL") == 0)) {
        kelp_nodereport r;
        kelp_diag dg = { 0 };
        if (kelp_nodereport_parse(v->sval, v->slen, &r, &dg) < 0 ||
            (r.fields & (KELP_NR_X | KELP_NR_Y)) != (KELP_NR_X | KELP_NR_Y)) {
            s->bad_reports++;
            snprintf(s->last_bad, sizeof s->last_bad, "%s: %s", v->name, dg.code ? kelp_diag_text(&dg) : "no X,Y");
            return;
        }
        kelp_plot_track *t = track_get(s, r.name, KELP_PLOT_SRC_REPORT);
        if (!t) return;
        double time = (r.fields & KELP_NR_TIME) ? r.time : v->time;
        track_add(t, time, r.x, r.y, (r.fields & KELP_NR_HDG) ? r.hdg : NAN, (r.fields & KELP_NR_SPD) ? r.spd : NAN);
        if (t->reports == 0 || time >= t->last.time) {
            t->last = r;
            t->last.time = time;
        }
        t->reports++;
        span(s, time);
        return;
    }
    if (strncmp(v->name, "NAV_", 4) == 0) {
        double d = num(v);
        if (!isfinite(d) || !v->community[0]) return;
        bool is_x = strcmp(v->name, "NAV_X") == 0, is_y = strcmp(v->name, "NAV_Y") == 0;
        bool is_h = strcmp(v->name, "NAV_HEADING") == 0, is_s = strcmp(v->name, "NAV_SPEED") == 0;
        if (!is_x && !is_y && !is_h && !is_s) return;
        kelp_plot_track *t = track_get(s, v->community, KELP_PLOT_SRC_NAV);
        if (!t) return;
        if (is_x) t->nav_x = d, t->have_x = true;
        else if (is_h) t->nav_hdg = d;
        else if (is_s) t->nav_spd = d;
        else if (t->have_x) { /* NAV_Y completes a fix (uSimMarine posts X before Y) */
            track_add(t, v->time, t->nav_x, d, t->nav_hdg, t->nav_spd);
            t->reports++;
            span(s, v->time);
        }
        return;
    }
    if (strncmp(v->name, "VIEW_", 5) == 0 && v->kind == KELP_VAR_STRING) {
        kelp_view_kind k;
        if (kelp_nodereport_view_kind_of(v->name, &k) == 0) {
            add_view(s, v, k);
        }
    }
}

static int cmp_pt(const void *a, const void *b)
{
    double ta = ((const kelp_plot_pt *)a)->t, tb = ((const kelp_plot_pt *)b)->t;
    return ta < tb ? -1 : ta > tb ? 1 : 0;
}

static int cmp_track(const void *a, const void *b)
{
    return strcasecmp(((const kelp_plot_track *)a)->name, ((const kelp_plot_track *)b)->name);
}

void kelp_plot_scene_finish(kelp_plot_scene *s)
{
    s->t0 = INFINITY;
    s->t1 = -INFINITY;
    /* a vehicle with node reports is drawn from them; its NAV_* track is dropped. Decide
     * first (no entry moves), then compact. */
    bool *drop = calloc(s->ntracks ? s->ntracks : 1, sizeof *drop);
    if (!drop) return;
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        drop[i] = t->n == 0;
        if (!drop[i] && t->src == KELP_PLOT_SRC_NAV)
            for (size_t j = 0; j < s->ntracks; j++)
                if (s->tracks[j].src == KELP_PLOT_SRC_REPORT && s->tracks[j].n > 0 &&
                    strcasecmp(s->tracks[j].name, t->name) == 0)
                    drop[i] = true;
    }
    kelp_plot_track *kept = calloc(s->ntracks ? s->ntracks : 1, sizeof *kept);
    if (!kept) {
        free(drop);
        return;
    }
    size_t w = 0;
    for (size_t i = 0; i < s->ntracks; i++) {
        if (drop[i]) free(s->tracks[i].pts);
        else kept[w++] = s->tracks[i];
    }
    free(drop);
    free(s->tracks);
    s->tracks = kept;
    s->tcap = s->ntracks ? s->ntracks : 1;
    s->ntracks = w;
    for (size_t i = 0; i < s->ntracks; i++) {
        kelp_plot_track *t = &s->tracks[i];
        qsort(t->pts, t->n, sizeof *t->pts, cmp_pt);
        size_t k = 0;
        for (size_t j = 0; j < t->n; j++) {
            if (k > 0 && t->pts[j].t == t->pts[k - 1].t && t->pts[j].x == t->pts[k - 1].x &&
                t->pts[j].y == t->pts[k - 1].y)
                continue; /* the same fix from two logs */
            t->pts[k++] = t->pts[j];
        }
        t->n = k;
        t->dist = 0;
        for (size_t j = 1; j < t->n; j++)
            t->dist += hypot(t->pts[j].x - t->pts[j - 1].x, t->pts[j].y - t->pts[j - 1].y);
        if (t->n) span(s, t->pts[0].t), span(s, t->pts[t->n - 1].t);
    }
    if (!s->ntracks)
        for (size_t i = 0; i < s->nviews; i++) span(s, s->views[i].t_first), span(s, s->views[i].t_last);
    /* stable colours: tracks in name order */
    qsort(s->tracks, s->ntracks, sizeof *s->tracks, cmp_track);
}

void kelp_plot_print_summary(const kelp_plot_scene *s, FILE *out)
{
    fprintf(out, "%-12s %-7s %7s %10s %9s %19s %19s\n", "vehicle", "from", "fixes", "dist(m)", "time(s)", "start (x,y)",
            "end (x,y)");
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        if (!t->n) continue;
        const kelp_plot_pt *a = &t->pts[0], *b = &t->pts[t->n - 1];
        char st[40], en[40];
        snprintf(st, sizeof st, "(%.1f,%.1f)", a->x, a->y);
        snprintf(en, sizeof en, "(%.1f,%.1f)", b->x, b->y);
        fprintf(out, "%-12s %-7s %7zu %10.1f %9.1f %19s %19s\n", t->name, t->src == KELP_PLOT_SRC_REPORT ? "report" : "nav",
                t->n, t->dist, b->t - a->t, st, en);
    }
    unsigned long nk[KELP_VIEW_NKINDS] = {0};
    for (size_t i = 0; i < s->nviews; i++) nk[s->views[i].v.kind]++;
    fprintf(out, "artifacts:");
    for (int k = 0; k < KELP_VIEW_NKINDS; k++)
        if (nk[k]) fprintf(out, " %s=%lu", kelp_nodereport_view_var((kelp_view_kind)k), nk[k]);
    if (!s->nviews) fprintf(out, " none");
    fprintf(out, "\n");
    if (s->bad_reports || s->bad_views)
        fprintf(out, "rejected: %lu node reports, %lu VIEW_* postings (last: %s)\n", s->bad_reports, s->bad_views,
                s->last_bad);
}

/* ------------------------------------------------------------------ closest approach */

/* the position of track t at time x (t->pts sorted; x within the track's span); *k is a
 * cursor that only moves forward */
static void at_time(const kelp_plot_track *t, size_t *k, double x, double *px, double *py)
{
    while (*k + 1 < t->n && t->pts[*k + 1].t <= x) (*k)++;
    const kelp_plot_pt *p = &t->pts[*k];
    if (*k + 1 >= t->n || t->pts[*k + 1].t <= p->t) {
        *px = p->x;
        *py = p->y;
        return;
    }
    const kelp_plot_pt *q = &t->pts[*k + 1];
    double f = (x - p->t) / (q->t - p->t);
    *px = p->x + f * (q->x - p->x);
    *py = p->y + f * (q->y - p->y);
}

int kelp_plot_closest(const kelp_plot_track *a, const kelp_plot_track *b, kelp_plot_cpa *out)
{
    if (!a->n || !b->n) return -1;
    double lo = fmax(a->pts[0].t, b->pts[0].t), hi = fmin(a->pts[a->n - 1].t, b->pts[b->n - 1].t);
    if (!(lo <= hi)) return -1;
    size_t ia = 0, ib = 0, ka = 0, kb = 0;
    *out = (kelp_plot_cpa){ .t = lo, .d = INFINITY, .ax = a->pts[0].x, .ay = a->pts[0].y, .bx = b->pts[0].x, .by = b->pts[0].y };
    double t0 = lo;
    /* walk the merged fix times: between two consecutive ones both move linearly, so the
     * separation is |d0 + w s| on [0, dt], least at s = -d0.w / w.w (clamped) */
    while (t0 <= hi) {
        while (ia < a->n && a->pts[ia].t <= t0) ia++;
        while (ib < b->n && b->pts[ib].t <= t0) ib++;
        double t1 = hi;
        if (ia < a->n && a->pts[ia].t < t1) t1 = a->pts[ia].t;
        if (ib < b->n && b->pts[ib].t < t1) t1 = b->pts[ib].t;
        double ax0, ay0, bx0, by0, ax1, ay1, bx1, by1;
        at_time(a, &ka, t0, &ax0, &ay0);
        at_time(b, &kb, t0, &bx0, &by0);
        size_t ka1 = ka, kb1 = kb;
        at_time(a, &ka1, t1, &ax1, &ay1);
        at_time(b, &kb1, t1, &bx1, &by1);
        double dt = t1 - t0, s = 0;
        double dx = bx0 - ax0, dy = by0 - ay0;
        double wx = (bx1 - ax1) - dx, wy = (by1 - ay1) - dy; /* change over the stretch */
        double ww = wx * wx + wy * wy;
        if (dt > 0 && ww > 0) {
            s = -(dx * wx + dy * wy) / ww;
            s = s < 0 ? 0 : s > 1 ? 1 : s;
        }
        double d = hypot(dx + wx * s, dy + wy * s);
        if (d < out->d) {
            out->d = d;
            out->t = t0 + s * dt;
            out->ax = ax0 + s * (ax1 - ax0);
            out->ay = ay0 + s * (ay1 - ay0);
            out->bx = bx0 + s * (bx1 - bx0);
            out->by = by0 + s * (by1 - by0);
        }
        if (t1 >= hi) break;
        t0 = t1;
    }
    return 0;
}

void kelp_plot_print_closest(const kelp_plot_scene *s, FILE *out)
{
    for (size_t i = 0; i < s->ntracks; i++)
        for (size_t j = i + 1; j < s->ntracks; j++) {
            kelp_plot_cpa c;
            if (kelp_plot_closest(&s->tracks[i], &s->tracks[j], &c) < 0) continue;
            fprintf(out, "closest %s %s %.2f m at %.1f s (%.1f,%.1f) (%.1f,%.1f)\n", s->tracks[i].name,
                    s->tracks[j].name, c.d, c.t - s->t0, c.ax, c.ay, c.bx, c.by);
        }
}

/* ------------------------------------------------------------------ LCM logs */

int kelp_plot_scene_read_log(kelp_plot_scene *s, const char *path, unsigned long *events, unsigned long *undecoded)
{
    kelp_diag err = {0};
    kelp_lcmlog_reader *log = kelp_lcmlog_open(path, 0, &err);
    if (!log) {
        fprintf(stderr, "kelp-plot: %s\n", kelp_diag_text(&err));
        return -1;
    }
    kelp_var *v = malloc(sizeof *v);
    if (!v) {
        kelp_lcmlog_close(log);
        return -1;
    }
    kelp_lcmlog_event ev;
    const char *channel;
    unsigned long n = 0;
    while (kelp_lcmlog_next(log, &ev, &channel) > 0) {
        n++;
        if (kelp_var_decode(ev.data, ev.data_len, v) == 0) {
            if (!(v->flags & KELP_VAR_FLAG_SYNC)) kelp_plot_scene_add_var(s, v);
        } else {
            (*undecoded)++;
        }
    }
    kelp_lcmlog_stats st = kelp_lcmlog_get_stats(log);
    if (st.damaged)
        fprintf(stderr, "kelp-plot: %s: %zu damaged stretch(es) skipped (%zu bytes)\n", path, st.damaged,
                st.skipped_bytes);
    *events += n;
    free(v);
    kelp_lcmlog_close(log);
    if (n == 0) {
        fprintf(stderr, "kelp-plot: %s: no events (empty or not an LCM log)\n", path);
        return -1;
    }
    return 0;
}
