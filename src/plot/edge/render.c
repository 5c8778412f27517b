/* kelp-plot: drawing a scene with cairo (PNG and SVG from one drawing routine). */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <cairo/cairo.h>
#include <cairo/cairo-svg.h>
#include <kelp/edge/plot.h>

#define FONT "DejaVu Sans"
#define LEGEND_W 310.0
#define MAX_COORD 1e7

/* vehicle palette: distinct, print-friendly */
static const double palette[][3] = {
    {0.122, 0.467, 0.706}, {0.839, 0.153, 0.157}, {0.173, 0.627, 0.173}, {1.000, 0.498, 0.055},
    {0.580, 0.404, 0.741}, {0.090, 0.745, 0.812}, {0.549, 0.337, 0.294}, {0.890, 0.467, 0.761},
};
#define NPAL (sizeof palette / sizeof palette[0])

typedef struct view_map {
    double ox, oy;   /* pixel position of the data centre */
    double cx, cy;   /* data centre */
    double s;        /* pixels per metre */
    double px0, py0, pw, ph;  /* plot area */
} view_map;

static double X(const view_map *m, double x) { return m->ox + (x - m->cx) * m->s; }
static double Y(const view_map *m, double y) { return m->oy - (y - m->cy) * m->s; }

static bool ok_coord(double v) { return isfinite(v) && fabs(v) < MAX_COORD; }

static void set_rgb(cairo_t *cr, const double c[3], double a) { cairo_set_source_rgba(cr, c[0], c[1], c[2], a); }

static double luminance(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static void hex_rgb(unsigned v, double c[3])
{
    c[0] = ((v >> 16) & 0xff) / 255.0;
    c[1] = ((v >> 8) & 0xff) / 255.0;
    c[2] = (v & 0xff) / 255.0;
}

static const double *track_color(const kelp_plot_scene *s, const char *name)
{
    for (size_t i = 0; i < s->ntracks; i++)
        if (strcasecmp(s->tracks[i].name, name) == 0) return palette[i % NPAL];
    return NULL;
}

/* The colour to draw an artifact with: its own unless missing or too pale for a light
 * background (MOOS viewers draw on dark water), then its vehicle's, else `def`.
 * Returns false when the artifact asks not to be drawn. */
static bool art_color(const kelp_plot_scene *s, const kelp_plot_view *pv, const char *name, unsigned def, double out[3])
{
    double c[3];
    int rc = name[0] ? kelp_plot_color(name, c) : -1;
    if (rc == 1) return false;
    const double *tc = track_color(s, pv->community);
    if (rc != 0) { /* no colour given (or unknown): the vehicle's, else the default */
        if (tc) memcpy(out, tc, 3 * sizeof *tc);
        else hex_rgb(def, out);
        return true;
    }
    if (luminance(c) < 0.78) {
        memcpy(out, c, sizeof c);
        return true;
    }
    /* too pale for a light background: a white/grey one takes its vehicle's colour (or a
     * slate grey), a pale hue is darkened */
    double mx = fmax(c[0], fmax(c[1], c[2])), mn = fmin(c[0], fmin(c[1], c[2]));
    if (mx - mn < 0.25) {
        if (tc) memcpy(out, tc, 3 * sizeof *tc);
        else hex_rgb(0x5b6b7f, out);
    } else {
        for (int i = 0; i < 3; i++) out[i] = c[i] * 0.68;
    }
    return true;
}

/* ------------------------------------------------------------------ text */

typedef enum { A_LEFT, A_CENTER, A_RIGHT } anchor;

static void text(cairo_t *cr, double x, double y, const char *str, double size, bool bold, const double rgb[3],
                 anchor a, bool halo)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr, str, &e);
    double tx = a == A_LEFT ? x : a == A_CENTER ? x - e.x_advance / 2 : x - e.x_advance;
    if (halo) {
        cairo_move_to(cr, tx, y);
        cairo_text_path(cr, str);
        cairo_set_source_rgba(cr, 1, 1, 1, 0.9);
        cairo_set_line_width(cr, 3.5);
        cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
        cairo_stroke(cr);
    }
    cairo_move_to(cr, tx, y);
    set_rgb(cr, rgb, 1);
    cairo_show_text(cr, str);
    cairo_new_path(cr);
}

/* labels that avoid each other: candidate spots around the anchor, the first free one wins */
typedef struct lbox {
    double x0, y0, x1, y1;
} lbox;

typedef struct placer {
    lbox b[1024];
    int n;
} placer;

static void placer_add(placer *p, double x0, double y0, double x1, double y1)
{
    if (p->n < (int)(sizeof p->b / sizeof p->b[0])) p->b[p->n++] = (lbox){x0, y0, x1, y1};
}

static bool placer_free(const placer *p, lbox b)
{
    for (int i = 0; i < p->n; i++)
        if (b.x0 < p->b[i].x1 && b.x1 > p->b[i].x0 && b.y0 < p->b[i].y1 && b.y1 > p->b[i].y0) return false;
    return true;
}

/* choose where to put `str` near (ax, ay): baseline-left in *tx, *ty; the spot is taken */
static void place(cairo_t *cr, placer *p, double ax, double ay, const char *str, double size, bool bold, double *tx,
                  double *ty)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr, str, &e);
    double w = e.x_advance;
    const double cand[][2] = {{12, -10}, {12, 18}, {-12 - w, -10}, {-12 - w, 18}, {-w / 2, -16}, {-w / 2, 28},
                              {16, -30}, {-16 - w, -30}, {16, 38}, {-16 - w, 38}, {-w / 2, -40}, {-w / 2, 52}};
    int best = 0;
    for (int i = 0; i < (int)(sizeof cand / sizeof cand[0]); i++) {
        lbox b = {ax + cand[i][0] - 2, ay + cand[i][1] - size, ax + cand[i][0] + w + 2, ay + cand[i][1] + 4};
        if (placer_free(p, b)) {
            best = i;
            break;
        }
    }
    *tx = ax + cand[best][0];
    *ty = ay + cand[best][1];
    placer_add(p, *tx - 2, *ty - size, *tx + w + 2, *ty + 4);
}

/* ------------------------------------------------------------------ bounds, grid */

typedef struct bbox {
    double x0, y0, x1, y1;
    bool any;
} bbox;

static void bb_add(bbox *b, double x, double y)
{
    if (!ok_coord(x) || !ok_coord(y)) return;
    if (!b->any) {
        b->x0 = b->x1 = x;
        b->y0 = b->y1 = y;
        b->any = true;
        return;
    }
    if (x < b->x0) b->x0 = x;
    if (x > b->x1) b->x1 = x;
    if (y < b->y0) b->y0 = y;
    if (y > b->y1) b->y1 = y;
}

static bbox scene_bounds(const kelp_plot_scene *s, bool pulses)
{
    bbox b = {0, 0, 0, 0, false};
    for (size_t i = 0; i < s->ntracks; i++)
        for (size_t j = 0; j < s->tracks[i].n; j++) bb_add(&b, s->tracks[i].pts[j].x, s->tracks[i].pts[j].y);
    for (size_t i = 0; i < s->nviews; i++) {
        const kelp_view *v = &s->views[i].v;
        switch (v->kind) {
        case KELP_VIEW_POLYGON:
        case KELP_VIEW_SEGLIST:
            for (size_t j = 0; j < v->npts; j++) bb_add(&b, v->pts[j][0], v->pts[j][1]);
            break;
        case KELP_VIEW_CIRCLE:
            bb_add(&b, v->x - v->radius, v->y - v->radius);
            bb_add(&b, v->x + v->radius, v->y + v->radius);
            break;
        case KELP_VIEW_RANGE_PULSE:
            if (pulses) {
                bb_add(&b, v->x - v->radius, v->y - v->radius);
                bb_add(&b, v->x + v->radius, v->y + v->radius);
            }
            break;
        case KELP_VIEW_COMMS_PULSE:
            if (pulses) {
                bb_add(&b, v->x, v->y);
                bb_add(&b, v->tx, v->ty);
            }
            break;
        default:
            bb_add(&b, v->x, v->y);
            break;
        }
    }
    return b;
}

static double nice_step(double span, int target)
{
    double raw = span / target;
    double p = pow(10, floor(log10(raw)));
    double f = raw / p;
    double n = f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10;
    return n * p;
}

static void fmt_num(char *buf, size_t cap, double v, double step)
{
    int dec = step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9);
    if (fabs(v) < step * 1e-6) v = 0;
    snprintf(buf, cap, "%.*f", dec, v);
}

/* ------------------------------------------------------------------ glyphs */

static void diamond(cairo_t *cr, double x, double y, double r)
{
    cairo_move_to(cr, x, y - r);
    cairo_line_to(cr, x + r, y);
    cairo_line_to(cr, x, y + r);
    cairo_line_to(cr, x - r, y);
    cairo_close_path(cr);
}

static void shape(cairo_t *cr, const char *type, double x, double y, double r)
{
    if (!strcasecmp(type, "square") || !strcasecmp(type, "gateway")) {
        cairo_rectangle(cr, x - r, y - r, 2 * r, 2 * r);
    } else if (!strcasecmp(type, "diamond") || !strcasecmp(type, "efield")) {
        diamond(cr, x, y, r * 1.25);
    } else if (!strcasecmp(type, "triangle")) {
        cairo_move_to(cr, x, y - r * 1.2);
        cairo_line_to(cr, x + r * 1.1, y + r * 0.8);
        cairo_line_to(cr, x - r * 1.1, y + r * 0.8);
        cairo_close_path(cr);
    } else {
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, r, 0, 2 * M_PI);
    }
}

/* a vehicle glyph (a hull pointing along the compass heading) */
static void vehicle(cairo_t *cr, double x, double y, double hdg, double len, const double c[3])
{
    double a = (isfinite(hdg) ? hdg : 0) * M_PI / 180.0;
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_rotate(cr, a); /* screen y is down: rotating by +heading turns "up" clockwise */
    double h = len / 2, w = len * 0.36;
    cairo_move_to(cr, 0, -h);
    cairo_curve_to(cr, w * 0.9, -h * 0.35, w, h * 0.4, w * 0.7, h);
    cairo_line_to(cr, -w * 0.7, h);
    cairo_curve_to(cr, -w, h * 0.4, -w * 0.9, -h * 0.35, 0, -h);
    cairo_close_path(cr);
    set_rgb(cr, c, 1);
    cairo_fill_preserve(cr);
    cairo_set_source_rgba(cr, 1, 1, 1, 1);
    cairo_set_line_width(cr, 1.6);
    cairo_stroke(cr);
    cairo_restore(cr);
}

/* ------------------------------------------------------------------ artifacts */

static void draw_views(cairo_t *cr, const kelp_plot_scene *s, const view_map *m, const kelp_plot_opts *o, int pass)
{
    static const double label_c[3] = {0.29, 0.35, 0.42};
    for (size_t i = 0; i < s->nviews; i++) {
        const kelp_plot_view *pv = &s->views[i];
        const kelp_view *v = &pv->v;
        double ec[3], fc[3];
        bool drawn_e, drawn_f;
        double fill = (v->fields & KELP_VF_FILL) ? v->fill : 0.12;
        double lw = (v->fields & KELP_VF_EDGE_SIZE) && v->edge_size > 0 ? v->edge_size * 1.4 : 1.4;
        if (lw > 6) lw = 6;
        switch (v->kind) {
        case KELP_VIEW_POLYGON:
        case KELP_VIEW_CIRCLE:
            if (pass != 0) break;
            drawn_e = art_color(s, pv, v->edge_color, 0x5b6b7f, ec);
            drawn_f = art_color(s, pv, v->fill_color[0] ? v->fill_color : v->edge_color, 0x5b6b7f, fc);
            if (v->kind == KELP_VIEW_POLYGON) {
                bool first = true;
                for (size_t j = 0; j < v->npts; j++) {
                    if (!ok_coord(v->pts[j][0]) || !ok_coord(v->pts[j][1])) continue;
                    if (first) cairo_move_to(cr, X(m, v->pts[j][0]), Y(m, v->pts[j][1]));
                    else cairo_line_to(cr, X(m, v->pts[j][0]), Y(m, v->pts[j][1]));
                    first = false;
                }
                if (first) break;
                cairo_close_path(cr);
            } else {
                if (!ok_coord(v->x) || !ok_coord(v->y)) break;
                cairo_new_sub_path(cr);
                cairo_arc(cr, X(m, v->x), Y(m, v->y), v->radius * m->s, 0, 2 * M_PI);
            }
            if (drawn_f) {
                set_rgb(cr, fc, v->active ? fill * 0.8 + 0.04 : 0.04);
                cairo_fill_preserve(cr);
            }
            if (drawn_e) {
                set_rgb(cr, ec, v->active ? 0.9 : 0.45);
                cairo_set_line_width(cr, lw);
                if (!v->active) {
                    double d[2] = {5, 4};
                    cairo_set_dash(cr, d, 2, 0);
                }
                cairo_stroke(cr);
                cairo_set_dash(cr, NULL, 0, 0);
            }
            cairo_new_path(cr);
            if (v->label[0] && drawn_e) {
                double lx = v->x, ly = v->y;
                if (v->kind == KELP_VIEW_POLYGON && v->npts) {
                    lx = ly = 0;
                    for (size_t j = 0; j < v->npts; j++) lx += v->pts[j][0], ly += v->pts[j][1];
                    lx /= (double)v->npts;
                    ly /= (double)v->npts;
                }
                if (ok_coord(lx) && ok_coord(ly)) text(cr, X(m, lx), Y(m, ly) + 4, v->label, 11, false, label_c, A_CENTER, true);
            }
            break;
        case KELP_VIEW_RANGE_PULSE:
            if (pass != 0 || !o->show_pulses || !ok_coord(v->x) || !ok_coord(v->y)) break;
            drawn_f = art_color(s, pv, v->fill_color, 0x2ca02c, fc);
            drawn_e = art_color(s, pv, v->edge_color, 0x2ca02c, ec);
            cairo_new_sub_path(cr);
            cairo_arc(cr, X(m, v->x), Y(m, v->y), v->radius * m->s, 0, 2 * M_PI);
            if (drawn_f) {
                cairo_pattern_t *g = cairo_pattern_create_radial(X(m, v->x), Y(m, v->y), 0, X(m, v->x), Y(m, v->y),
                                                                 v->radius * m->s);
                cairo_pattern_add_color_stop_rgba(g, 0, fc[0], fc[1], fc[2], v->fill * 0.9);
                cairo_pattern_add_color_stop_rgba(g, 1, fc[0], fc[1], fc[2], 0.02);
                cairo_set_source(cr, g);
                cairo_fill_preserve(cr);
                cairo_pattern_destroy(g);
            }
            if (drawn_e) {
                set_rgb(cr, ec, 0.7);
                cairo_set_line_width(cr, 1.2);
                cairo_stroke(cr);
            }
            cairo_new_path(cr);
            break;
        case KELP_VIEW_COMMS_PULSE: {
            if (pass != 0 || !o->show_pulses || !ok_coord(v->x) || !ok_coord(v->y) || !ok_coord(v->tx) ||
                !ok_coord(v->ty))
                break;
            drawn_f = art_color(s, pv, v->fill_color, 0x9467bd, fc);
            if (!drawn_f) break;
            double dx = v->tx - v->x, dy = v->ty - v->y, d = hypot(dx, dy);
            if (d <= 0) break;
            double hw = (v->beam_width > 0 ? v->beam_width : 7) / 2.0;
            double nx = -dy / d * hw, ny = dx / d * hw;
            cairo_move_to(cr, X(m, v->x), Y(m, v->y));
            cairo_line_to(cr, X(m, v->tx + nx), Y(m, v->ty + ny));
            cairo_line_to(cr, X(m, v->tx - nx), Y(m, v->ty - ny));
            cairo_close_path(cr);
            set_rgb(cr, fc, v->fill * 0.7 + 0.05);
            cairo_fill(cr);
            break;
        }
        case KELP_VIEW_SEGLIST: {
            if (v->npts == 0) break;
            if (!art_color(s, pv, v->edge_color, 0x5b6b7f, ec)) break;
            if (pass == 0) { /* the path under the tracks */
                bool first = true;
                for (size_t j = 0; j < v->npts; j++) {
                    if (!ok_coord(v->pts[j][0]) || !ok_coord(v->pts[j][1])) continue;
                    if (first) cairo_move_to(cr, X(m, v->pts[j][0]), Y(m, v->pts[j][1]));
                    else cairo_line_to(cr, X(m, v->pts[j][0]), Y(m, v->pts[j][1]));
                    first = false;
                }
                double d[2] = {7, 5};
                cairo_set_dash(cr, d, 2, 0);
                set_rgb(cr, ec, v->active ? 0.8 : 0.55);
                cairo_set_line_width(cr, 1.4);
                cairo_stroke(cr);
                cairo_set_dash(cr, NULL, 0, 0);
            } else { /* its vertices over them */
                for (size_t j = 0; j < v->npts; j++) {
                    if (!ok_coord(v->pts[j][0]) || !ok_coord(v->pts[j][1])) continue;
                    cairo_rectangle(cr, X(m, v->pts[j][0]) - 3.5, Y(m, v->pts[j][1]) - 3.5, 7, 7);
                    cairo_set_source_rgba(cr, 1, 1, 1, 1);
                    cairo_fill_preserve(cr);
                    set_rgb(cr, ec, 1);
                    cairo_set_line_width(cr, 1.6);
                    cairo_stroke(cr);
                }
            }
            break;
        }
        case KELP_VIEW_MARKER: {
            if (pass != 1 || !ok_coord(v->x) || !ok_coord(v->y)) break;
            if (!art_color(s, pv, v->fill_color[0] ? v->fill_color : "orange", 0xff7f0e, fc)) break;
            double r = (v->width > 0 ? v->width * m->s / 2 : 5);
            if (r < 5) r = 5;
            if (r > 30) r = 30;
            shape(cr, v->type, X(m, v->x), Y(m, v->y), r);
            set_rgb(cr, fc, 0.95);
            cairo_fill_preserve(cr);
            cairo_set_source_rgba(cr, 0.15, 0.18, 0.22, 0.9);
            cairo_set_line_width(cr, 1.2);
            cairo_stroke(cr);
            if (v->label[0]) text(cr, X(m, v->x) + r + 4, Y(m, v->y) + 4, v->label, 11, false, label_c, A_LEFT, true);
            break;
        }
        case KELP_VIEW_POINT: {
            if (pass != 1 || !ok_coord(v->x) || !ok_coord(v->y)) break;
            if (!art_color(s, pv, v->vertex_color[0] ? v->vertex_color : v->edge_color, 0x34495e, fc)) break;
            double px = X(m, v->x), py = Y(m, v->y);
            double r = v->vertex_size > 0 ? v->vertex_size : 6.5;
            if (r > 14) r = 14;
            diamond(cr, px, py, r);
            if (v->active) {
                set_rgb(cr, fc, 0.95);
                cairo_fill_preserve(cr);
                cairo_set_source_rgba(cr, 1, 1, 1, 1);
            } else {
                cairo_set_source_rgba(cr, 1, 1, 1, 0.95);
                cairo_fill_preserve(cr);
                set_rgb(cr, fc, 0.9);
            }
            cairo_set_line_width(cr, 1.5);
            cairo_stroke(cr);
            break;
        }
        default:
            break;
        }
    }
}

/* point labels: one per distinct (position, label), so repeated postings do not pile up */
static void draw_point_labels(cairo_t *cr, const kelp_plot_scene *s, const view_map *m, placer *pl)
{
    static const double c[3] = {0.29, 0.35, 0.42};
    for (size_t i = 0; i < s->nviews; i++) {
        const kelp_view *v = &s->views[i].v;
        if (v->kind != KELP_VIEW_POINT || !ok_coord(v->x) || !ok_coord(v->y)) continue;
        bool dup = false;
        for (size_t j = 0; j < i && !dup; j++) {
            const kelp_view *w = &s->views[j].v;
            dup = w->kind == KELP_VIEW_POINT && w->x == v->x && w->y == v->y;
        }
        if (dup) continue;
        char buf[96];
        char xs[24], ys[24];
        fmt_num(xs, sizeof xs, v->x, 0.1);
        fmt_num(ys, sizeof ys, v->y, 0.1);
        snprintf(buf, sizeof buf, "(%s, %s)", xs, ys);
        double tx, ty;
        place(cr, pl, X(m, v->x), Y(m, v->y), buf, 10.5, false, &tx, &ty);
        text(cr, tx, ty, buf, 10.5, false, c, A_LEFT, true);
    }
}

/* ------------------------------------------------------------------ tracks */

static double tick_period(double dur)
{
    static const double steps[] = {1, 2, 5, 10, 15, 20, 30, 60, 120, 300, 600, 900, 1800, 3600, 7200};
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++)
        if (dur / steps[i] <= 24) return steps[i];
    return 7200;
}

static void draw_tracks(cairo_t *cr, const kelp_plot_scene *s, const view_map *m, double tick)
{
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (int layer = 0; layer < 2; layer++) {
        for (size_t i = 0; i < s->ntracks; i++) {
            const kelp_plot_track *t = &s->tracks[i];
            const double *c = palette[i % NPAL];
            bool first = true;
            for (size_t j = 0; j < t->n; j++) {
                if (!ok_coord(t->pts[j].x) || !ok_coord(t->pts[j].y)) continue;
                if (first) cairo_move_to(cr, X(m, t->pts[j].x), Y(m, t->pts[j].y));
                else cairo_line_to(cr, X(m, t->pts[j].x), Y(m, t->pts[j].y));
                first = false;
            }
            if (layer == 0) {
                cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
                cairo_set_line_width(cr, 6);
            } else {
                set_rgb(cr, c, 0.95);
                cairo_set_line_width(cr, 2.6);
            }
            cairo_stroke(cr);
        }
    }
    /* time ticks */
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        if (t->n < 2 || tick <= 0) continue;
        const double *c = palette[i % NPAL];
        double next = t->pts[0].t + tick;
        for (size_t j = 1; j < t->n; j++) {
            while (t->pts[j].t >= next) {
                const kelp_plot_pt *a = &t->pts[j - 1], *b = &t->pts[j];
                double f = b->t > a->t ? (next - a->t) / (b->t - a->t) : 1;
                double x = a->x + f * (b->x - a->x), y = a->y + f * (b->y - a->y);
                if (ok_coord(x) && ok_coord(y)) {
                    cairo_new_sub_path(cr);
                    cairo_arc(cr, X(m, x), Y(m, y), 2.6, 0, 2 * M_PI);
                    cairo_set_source_rgba(cr, 1, 1, 1, 1);
                    cairo_fill_preserve(cr);
                    set_rgb(cr, c, 1);
                    cairo_set_line_width(cr, 1.3);
                    cairo_stroke(cr);
                }
                next += tick;
            }
        }
    }
}

static void draw_track_starts(cairo_t *cr, const kelp_plot_scene *s, const view_map *m)
{
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        if (!t->n || !ok_coord(t->pts[0].x) || !ok_coord(t->pts[0].y)) continue;
        const double *c = palette[i % NPAL];
        cairo_new_sub_path(cr);
        cairo_arc(cr, X(m, t->pts[0].x), Y(m, t->pts[0].y), 6, 0, 2 * M_PI);
        cairo_set_source_rgba(cr, 1, 1, 1, 1);
        cairo_fill_preserve(cr);
        set_rgb(cr, c, 1);
        cairo_set_line_width(cr, 2.4);
        cairo_stroke(cr);
    }
}

/* reserve the glyphs and rings, then the vehicle names (before any other label) */
static void place_names(cairo_t *cr, const kelp_plot_scene *s, const view_map *m, placer *pl, double (*at)[2])
{
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        if (!t->n) continue;
        const kelp_plot_pt *a = &t->pts[0], *b = &t->pts[t->n - 1];
        if (ok_coord(a->x) && ok_coord(a->y)) placer_add(pl, X(m, a->x) - 7, Y(m, a->y) - 7, X(m, a->x) + 7, Y(m, a->y) + 7);
        if (ok_coord(b->x) && ok_coord(b->y))
            placer_add(pl, X(m, b->x) - 11, Y(m, b->y) - 11, X(m, b->x) + 11, Y(m, b->y) + 11);
    }
    for (size_t i = 0; i < s->ntracks && i < 64; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        if (!t->n || !ok_coord(t->pts[t->n - 1].x) || !ok_coord(t->pts[t->n - 1].y)) continue;
        place(cr, pl, X(m, t->pts[t->n - 1].x), Y(m, t->pts[t->n - 1].y), t->name, 15, true, &at[i][0], &at[i][1]);
    }
}

static void draw_track_ends(cairo_t *cr, const kelp_plot_scene *s, const view_map *m, double (*at)[2])
{
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        if (!t->n) continue;
        const double *c = palette[i % NPAL];
        const kelp_plot_pt *b = &t->pts[t->n - 1];
        if (!ok_coord(b->x) || !ok_coord(b->y)) continue;
        double hdg = b->hdg;
        if (!isfinite(hdg) && t->n >= 2) {
            const kelp_plot_pt *p = &t->pts[t->n - 2];
            hdg = atan2(b->x - p->x, b->y - p->y) * 180 / M_PI;
        }
        vehicle(cr, X(m, b->x), Y(m, b->y), hdg, 22, c);
        if (i < 64) text(cr, at[i][0], at[i][1], t->name, 15, true, c, A_LEFT, true);
    }
}

/* ------------------------------------------------------------------ legend */

static const char *kind_label(kelp_view_kind k)
{
    switch (k) {
    case KELP_VIEW_POINT: return "waypoints (VIEW_POINT)";
    case KELP_VIEW_CIRCLE: return "circles (VIEW_CIRCLE)";
    case KELP_VIEW_POLYGON: return "polygons (VIEW_POLYGON)";
    case KELP_VIEW_SEGLIST: return "paths (VIEW_SEGLIST)";
    case KELP_VIEW_MARKER: return "markers (VIEW_MARKER)";
    case KELP_VIEW_COMMS_PULSE: return "comms pulses";
    case KELP_VIEW_RANGE_PULSE: return "range pulses";
    default: return "?";
    }
}

static void legend_symbol(cairo_t *cr, kelp_view_kind k, double x, double y)
{
    double c[3] = {0.36, 0.42, 0.50};
    switch (k) {
    case KELP_VIEW_POINT:
        diamond(cr, x, y, 6);
        set_rgb(cr, c, 1);
        cairo_fill(cr);
        break;
    case KELP_VIEW_CIRCLE:
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, 7, 0, 2 * M_PI);
        set_rgb(cr, c, 0.15);
        cairo_fill_preserve(cr);
        set_rgb(cr, c, 1);
        cairo_set_line_width(cr, 1.4);
        cairo_stroke(cr);
        break;
    case KELP_VIEW_POLYGON:
        cairo_move_to(cr, x - 9, y + 6);
        cairo_line_to(cr, x - 4, y - 7);
        cairo_line_to(cr, x + 9, y - 4);
        cairo_line_to(cr, x + 6, y + 7);
        cairo_close_path(cr);
        set_rgb(cr, c, 0.15);
        cairo_fill_preserve(cr);
        set_rgb(cr, c, 1);
        cairo_set_line_width(cr, 1.4);
        cairo_stroke(cr);
        break;
    case KELP_VIEW_SEGLIST: {
        double d[2] = {4, 3};
        cairo_set_dash(cr, d, 2, 0);
        cairo_move_to(cr, x - 10, y + 4);
        cairo_line_to(cr, x + 10, y - 4);
        set_rgb(cr, c, 1);
        cairo_set_line_width(cr, 1.5);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
        break;
    }
    case KELP_VIEW_MARKER:
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, 5.5, 0, 2 * M_PI);
        cairo_set_source_rgb(cr, 1.0, 0.65, 0.0);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.15, 0.18, 0.22);
        cairo_set_line_width(cr, 1.1);
        cairo_stroke(cr);
        break;
    case KELP_VIEW_COMMS_PULSE:
        cairo_move_to(cr, x - 10, y);
        cairo_line_to(cr, x + 10, y - 5);
        cairo_line_to(cr, x + 10, y + 5);
        cairo_close_path(cr);
        cairo_set_source_rgba(cr, 0.58, 0.40, 0.74, 0.5);
        cairo_fill(cr);
        break;
    case KELP_VIEW_RANGE_PULSE:
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, 7, 0, 2 * M_PI);
        cairo_set_source_rgba(cr, 0.17, 0.63, 0.17, 0.35);
        cairo_fill_preserve(cr);
        cairo_set_source_rgba(cr, 0.17, 0.63, 0.17, 0.8);
        cairo_set_line_width(cr, 1.1);
        cairo_stroke(cr);
        break;
    default:
        break;
    }
    cairo_new_path(cr);
}

static void draw_legend(cairo_t *cr, const kelp_plot_scene *s, double x0, double y0, double w, double tick)
{
    static const double dark[3] = {0.13, 0.16, 0.20}, mid[3] = {0.38, 0.44, 0.51};
    unsigned long nk[KELP_VIEW_NKINDS] = {0};
    for (size_t i = 0; i < s->nviews; i++) nk[s->views[i].v.kind]++;
    int nkinds = 0;
    for (int k = 0; k < KELP_VIEW_NKINDS; k++) nkinds += nk[k] > 0;
    double h = 44 + (double)s->ntracks * 44 + 18 + (nkinds ? 34 + nkinds * 24 : 0) + 62;
    cairo_rectangle(cr, x0, y0, w, h);
    cairo_set_source_rgb(cr, 0.985, 0.988, 0.992);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.82, 0.85, 0.89);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    double y = y0 + 28;
    text(cr, x0 + 16, y, "Vehicles", 15, true, dark, A_LEFT, false);
    y += 14;
    if (!s->ntracks) {
        y += 16;
        text(cr, x0 + 16, y, "no vehicle positions in the log", 12, false, mid, A_LEFT, false);
        y += 14;
    }
    for (size_t i = 0; i < s->ntracks; i++) {
        const kelp_plot_track *t = &s->tracks[i];
        const double *c = palette[i % NPAL];
        y += 22;
        cairo_move_to(cr, x0 + 16, y - 5);
        cairo_line_to(cr, x0 + 44, y - 5);
        set_rgb(cr, c, 1);
        cairo_set_line_width(cr, 3);
        cairo_stroke(cr);
        vehicle(cr, x0 + 52, y - 5, 90, 14, c);
        text(cr, x0 + 66, y, t->name, 14, true, dark, A_LEFT, false);
        char buf[128];
        double dur = t->n ? t->pts[t->n - 1].t - t->pts[0].t : 0;
        snprintf(buf, sizeof buf, "%.0f m in %.0f s  ·  %zu fixes (%s)", t->dist, dur, t->n,
                 t->src == KELP_PLOT_SRC_REPORT ? "node reports" : "NAV_X/Y");
        y += 18;
        text(cr, x0 + 66, y, buf, 11, false, mid, A_LEFT, false);
        y += 4;
    }
    y += 18;
    if (nkinds) {
        y += 16;
        text(cr, x0 + 16, y, "Artifacts", 15, true, dark, A_LEFT, false);
        y += 6;
        for (int k = 0; k < KELP_VIEW_NKINDS; k++) {
            if (!nk[k]) continue;
            y += 24;
            legend_symbol(cr, (kelp_view_kind)k, x0 + 30, y - 4);
            char buf[96];
            snprintf(buf, sizeof buf, "%s  %lu", kind_label((kelp_view_kind)k), nk[k]);
            text(cr, x0 + 52, y, buf, 12, false, dark, A_LEFT, false);
        }
        y += 12;
    }
    /* how to read the tracks */
    y += 22;
    double c[3] = {0.36, 0.42, 0.50};
    cairo_new_sub_path(cr);
    cairo_arc(cr, x0 + 24, y - 4, 5, 0, 2 * M_PI);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_fill_preserve(cr);
    set_rgb(cr, c, 1);
    cairo_set_line_width(cr, 2);
    cairo_stroke(cr);
    text(cr, x0 + 36, y, "start", 11.5, false, mid, A_LEFT, false);
    vehicle(cr, x0 + 96, y - 4, 90, 14, c);
    text(cr, x0 + 108, y, "end (heading)", 11.5, false, mid, A_LEFT, false);
    y += 22;
    cairo_new_sub_path(cr);
    cairo_arc(cr, x0 + 24, y - 4, 2.6, 0, 2 * M_PI);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_fill_preserve(cr);
    set_rgb(cr, c, 1);
    cairo_set_line_width(cr, 1.3);
    cairo_stroke(cr);
    char buf[64];
    snprintf(buf, sizeof buf, "every %.0f s along a track", tick);
    text(cr, x0 + 36, y, buf, 11.5, false, mid, A_LEFT, false);
}

/* ------------------------------------------------------------------ the page */

/* every pair's closest approach: a red dashed line between the two positions, a ring on
 * each, and the distance and time (MOOS seconds from the start) beside it */
static void draw_closest(cairo_t *cr, const kelp_plot_scene *s, const view_map *m, placer *pl)
{
    static const double red[3] = {0.80, 0.10, 0.12};
    for (size_t i = 0; i < s->ntracks; i++)
        for (size_t j = i + 1; j < s->ntracks; j++) {
            kelp_plot_cpa c;
            if (kelp_plot_closest(&s->tracks[i], &s->tracks[j], &c) < 0 || !ok_coord(c.ax) || !ok_coord(c.bx)) continue;
            double x0 = X(m, c.ax), y0 = Y(m, c.ay), x1 = X(m, c.bx), y1 = Y(m, c.by);
            static const double dash[] = {4, 3};
            cairo_set_dash(cr, dash, 2, 0);
            cairo_move_to(cr, x0, y0);
            cairo_line_to(cr, x1, y1);
            set_rgb(cr, red, 0.9);
            cairo_set_line_width(cr, 1.6);
            cairo_stroke(cr);
            cairo_set_dash(cr, NULL, 0, 0);
            cairo_arc(cr, x0, y0, 4.5, 0, 2 * M_PI);
            cairo_new_sub_path(cr);
            cairo_arc(cr, x1, y1, 4.5, 0, 2 * M_PI);
            cairo_stroke(cr);
            char buf[800];
            snprintf(buf, sizeof buf, "%s-%s %.1f m @ %.0f s", s->tracks[i].name, s->tracks[j].name, c.d, c.t - s->t0);
            double tx, ty;
            place(cr, pl, (x0 + x1) / 2, (y0 + y1) / 2, buf, 11, true, &tx, &ty);
            text(cr, tx, ty, buf, 11, true, red, A_LEFT, true);
        }
}

static void draw(cairo_t *cr, const kelp_plot_scene *s, const kelp_plot_opts *o)
{
    const double W = o->width, H = o->height;
    static const double dark[3] = {0.13, 0.16, 0.20}, mid[3] = {0.38, 0.44, 0.51}, axis[3] = {0.27, 0.33, 0.40};
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);

    /* title */
    text(cr, 28, 40, o->title && o->title[0] ? o->title : "kelp mission plot", 22, true, dark, A_LEFT, false);
    if (o->subtitle && o->subtitle[0]) text(cr, 28, 64, o->subtitle, 13, false, mid, A_LEFT, false);

    view_map m;
    m.px0 = 92;
    m.py0 = 88;
    m.pw = W - LEGEND_W - 40 - m.px0;
    m.ph = H - 70 - m.py0;
    if (m.pw < 100) m.pw = 100;
    if (m.ph < 100) m.ph = 100;
    bbox b = scene_bounds(s, o->show_pulses);
    if (!b.any) b = (bbox){-50, -50, 50, 50, true};
    double dx = b.x1 - b.x0, dy = b.y1 - b.y0;
    double pad = 0.07 * (dx > dy ? dx : dy) + 8;
    b.x0 -= pad, b.x1 += pad, b.y0 -= pad, b.y1 += pad;
    dx = b.x1 - b.x0, dy = b.y1 - b.y0;
    if (dx < 40) b.x0 -= (40 - dx) / 2, b.x1 += (40 - dx) / 2, dx = 40;
    if (dy < 40) b.y0 -= (40 - dy) / 2, b.y1 += (40 - dy) / 2, dy = 40;
    m.s = fmin(m.pw / dx, m.ph / dy);
    m.cx = (b.x0 + b.x1) / 2;
    m.cy = (b.y0 + b.y1) / 2;
    m.ox = m.px0 + m.pw / 2;
    m.oy = m.py0 + m.ph / 2;
    /* the data window the whole plot area shows */
    double wx0 = m.cx - m.pw / 2 / m.s, wx1 = m.cx + m.pw / 2 / m.s;
    double wy0 = m.cy - m.ph / 2 / m.s, wy1 = m.cy + m.ph / 2 / m.s;

    /* water and grid */
    cairo_rectangle(cr, m.px0, m.py0, m.pw, m.ph);
    cairo_set_source_rgb(cr, 0.953, 0.965, 0.980);
    cairo_fill(cr);
    double step = nice_step(fmax(wx1 - wx0, wy1 - wy0), 9);
    double minor = step / 5;
    cairo_save(cr);
    cairo_rectangle(cr, m.px0, m.py0, m.pw, m.ph);
    cairo_clip(cr);
    if (minor * m.s >= 11) {
        cairo_set_source_rgb(cr, 0.905, 0.925, 0.950);
        cairo_set_line_width(cr, 0.6);
        for (long k = (long)ceil(wx0 / minor), k1 = (long)floor(wx1 / minor); k <= k1; k++) {
            double gx = (double)k * minor;
            cairo_move_to(cr, round(X(&m, gx)) + 0.5, m.py0);
            cairo_line_to(cr, round(X(&m, gx)) + 0.5, m.py0 + m.ph);
        }
        for (long k = (long)ceil(wy0 / minor), k1 = (long)floor(wy1 / minor); k <= k1; k++) {
            double gy = (double)k * minor;
            cairo_move_to(cr, m.px0, round(Y(&m, gy)) + 0.5);
            cairo_line_to(cr, m.px0 + m.pw, round(Y(&m, gy)) + 0.5);
        }
        cairo_stroke(cr);
    }
    cairo_set_source_rgb(cr, 0.815, 0.851, 0.894);
    cairo_set_line_width(cr, 1);
    for (long k = (long)ceil(wx0 / step), k1 = (long)floor(wx1 / step); k <= k1; k++) {
        double gx = (double)k * step;
        cairo_move_to(cr, round(X(&m, gx)) + 0.5, m.py0);
        cairo_line_to(cr, round(X(&m, gx)) + 0.5, m.py0 + m.ph);
    }
    for (long k = (long)ceil(wy0 / step), k1 = (long)floor(wy1 / step); k <= k1; k++) {
        double gy = (double)k * step;
        cairo_move_to(cr, m.px0, round(Y(&m, gy)) + 0.5);
        cairo_line_to(cr, m.px0 + m.pw, round(Y(&m, gy)) + 0.5);
    }
    cairo_stroke(cr);
    /* the datum axes */
    cairo_set_source_rgb(cr, 0.62, 0.69, 0.77);
    cairo_set_line_width(cr, 1.4);
    if (wx0 < 0 && wx1 > 0) {
        cairo_move_to(cr, round(X(&m, 0)) + 0.5, m.py0);
        cairo_line_to(cr, round(X(&m, 0)) + 0.5, m.py0 + m.ph);
    }
    if (wy0 < 0 && wy1 > 0) {
        cairo_move_to(cr, m.px0, round(Y(&m, 0)) + 0.5);
        cairo_line_to(cr, m.px0 + m.pw, round(Y(&m, 0)) + 0.5);
    }
    cairo_stroke(cr);

    /* content */
    double dur = 0;
    for (size_t i = 0; i < s->ntracks; i++)
        if (s->tracks[i].n > 1) dur = fmax(dur, s->tracks[i].pts[s->tracks[i].n - 1].t - s->tracks[i].pts[0].t);
    double tick = tick_period(dur > 0 ? dur : 60);
    draw_views(cr, s, &m, o, 0);
    draw_tracks(cr, s, &m, tick);
    draw_track_starts(cr, s, &m);
    draw_views(cr, s, &m, o, 1);
    static placer pl;
    pl.n = 0;
    double name_at[64][2] = {{0}};
    place_names(cr, s, &m, &pl, name_at);
    draw_point_labels(cr, s, &m, &pl);
    draw_track_ends(cr, s, &m, name_at);
    if (o->show_closest) draw_closest(cr, s, &m, &pl);
    if (!s->ntracks && !s->nviews)
        text(cr, m.ox, m.oy, "nothing to draw: no vehicle positions or VIEW_* postings", 16, false, mid, A_CENTER, true);

    /* north arrow and scale bar */
    {
        double ax = m.px0 + 30, ay = m.py0 + 22;
        cairo_move_to(cr, ax, ay);
        cairo_line_to(cr, ax + 8, ay + 24);
        cairo_line_to(cr, ax, ay + 18);
        cairo_line_to(cr, ax - 8, ay + 24);
        cairo_close_path(cr);
        set_rgb(cr, axis, 0.9);
        cairo_fill(cr);
        text(cr, ax, ay + 42, "N", 13, true, axis, A_CENTER, true);
        double sb = nice_step(m.pw / m.s, 5);
        double sx = m.px0 + 24, sy = m.py0 + m.ph - 24, sl = sb * m.s;
        cairo_rectangle(cr, sx - 6, sy - 22, sl + 12, 32);
        cairo_set_source_rgba(cr, 1, 1, 1, 0.75);
        cairo_fill(cr);
        cairo_move_to(cr, sx, sy - 5);
        cairo_line_to(cr, sx, sy);
        cairo_line_to(cr, sx + sl, sy);
        cairo_line_to(cr, sx + sl, sy - 5);
        set_rgb(cr, dark, 1);
        cairo_set_line_width(cr, 2);
        cairo_stroke(cr);
        char buf[32], n[24];
        fmt_num(n, sizeof n, sb, sb);
        snprintf(buf, sizeof buf, "%s m", n);
        text(cr, sx + sl / 2, sy - 8, buf, 11.5, true, dark, A_CENTER, false);
    }
    cairo_restore(cr);

    /* frame, tick labels, axis titles */
    cairo_rectangle(cr, m.px0 + 0.5, m.py0 + 0.5, m.pw - 1, m.ph - 1);
    cairo_set_source_rgb(cr, 0.54, 0.60, 0.67);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    char buf[32];
    for (long k = (long)ceil(wx0 / step), k1 = (long)floor(wx1 / step); k <= k1; k++) {
        double gx = (double)k * step;
        double px = X(&m, gx);
        if (px < m.px0 + 12 || px > m.px0 + m.pw - 12) continue;
        fmt_num(buf, sizeof buf, gx, step);
        cairo_move_to(cr, round(px) + 0.5, m.py0 + m.ph);
        cairo_line_to(cr, round(px) + 0.5, m.py0 + m.ph + 5);
        set_rgb(cr, axis, 1);
        cairo_stroke(cr);
        text(cr, px, m.py0 + m.ph + 20, buf, 12, false, axis, A_CENTER, false);
    }
    for (long k = (long)ceil(wy0 / step), k1 = (long)floor(wy1 / step); k <= k1; k++) {
        double gy = (double)k * step;
        double py = Y(&m, gy);
        if (py < m.py0 + 8 || py > m.py0 + m.ph - 8) continue;
        fmt_num(buf, sizeof buf, gy, step);
        cairo_move_to(cr, m.px0 - 5, round(py) + 0.5);
        cairo_line_to(cr, m.px0, round(py) + 0.5);
        set_rgb(cr, axis, 1);
        cairo_stroke(cr);
        text(cr, m.px0 - 9, py + 4, buf, 12, false, axis, A_RIGHT, false);
    }
    text(cr, m.px0 + m.pw / 2, m.py0 + m.ph + 44, "x  (metres east of the datum)", 13, false, axis, A_CENTER, false);
    cairo_save(cr);
    cairo_translate(cr, 24, m.py0 + m.ph / 2);
    cairo_rotate(cr, -M_PI / 2);
    text(cr, 0, 0, "y  (metres north of the datum)", 13, false, axis, A_CENTER, false);
    cairo_restore(cr);

    draw_legend(cr, s, W - LEGEND_W - 16, m.py0, LEGEND_W, tick);
}

void kelp_plot_release(void)
{
    /* cairo's and fontconfig's caches, so a leak checker sees only real leaks. FcFini is
     * looked up at run time: fontconfig comes in with libcairo, it is not linked directly. */
    cairo_debug_reset_static_data();
    void (*fc_fini)(void);
    void *sym = dlsym(RTLD_DEFAULT, "FcFini");
    memcpy(&fc_fini, &sym, sizeof fc_fini);
    if (fc_fini) fc_fini();
}

int kelp_plot_render(const kelp_plot_scene *s, const kelp_plot_opts *o, const char *path)
{
    size_t n = strlen(path);
    bool png = n >= 4 && strcasecmp(path + n - 4, ".png") == 0;
    cairo_surface_t *sf = png ? cairo_image_surface_create(CAIRO_FORMAT_ARGB32, o->width, o->height)
                              : cairo_svg_surface_create(path, o->width, o->height);
    if (cairo_surface_status(sf) != CAIRO_STATUS_SUCCESS) {
        fprintf(stderr, "kelp-plot: %s: %s\n", path, cairo_status_to_string(cairo_surface_status(sf)));
        cairo_surface_destroy(sf);
        return -1;
    }
    cairo_t *cr = cairo_create(sf);
    draw(cr, s, o);
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    if (st == CAIRO_STATUS_SUCCESS && png) st = cairo_surface_write_to_png(sf, path);
    cairo_surface_finish(sf);
    if (st == CAIRO_STATUS_SUCCESS) st = cairo_surface_status(sf);
    cairo_surface_destroy(sf);
    if (st != CAIRO_STATUS_SUCCESS) {
        fprintf(stderr, "kelp-plot: %s: %s\n", path, cairo_status_to_string(st));
        return -1;
    }
    return 0;
}
