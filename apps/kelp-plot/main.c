/* kelp-plot: pictures of a mission.
 *
 *   kelp-plot [options] LOG [LOG...]          render lcm-logger logs to PNG and SVG
 *   kelp-plot MISSION.moos [NAME]             live: a shoreside viewer app (table + picture)
 *
 * Offline, every event of each log is decoded as a kelp variable (channels that do not decode
 * are counted and skipped); vehicle tracks come from NODE_REPORT / NODE_REPORT_LOCAL (or from
 * NAV_X/NAV_Y per community when a vehicle has no reports), and VIEW_* postings are drawn.
 * Live, it runs as an app in a community (ProcessConfig = kelp-plot or its alias), shows the
 * vehicles in a terminal table in its status report and writes the picture when it stops. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lcm/eventlog.h>
#include <kelp/edge/app.h>
#include <kelp/edge/plot.h>

/* "WxH" with both in range; 0 or -1 */
static int parse_size(const char *s, int *w, int *h)
{
    char *e;
    long a = strtol(s, &e, 10);
    if (e == s || *e != 'x') return -1;
    const char *s2 = e + 1;
    long b = strtol(s2, &e, 10);
    if (e == s2 || *e) return -1;
    if (a < 400 || b < 300 || a > 10000 || b > 10000) return -1;
    *w = (int)a;
    *h = (int)b;
    return 0;
}

enum { OPT_TITLE = 256, OPT_SIZE, OPT_NO_PULSES, OPT_CLOSEST };

static const kelp_cli cli = {
    .name = "kelp-plot",
    .purpose = "Pictures of a mission: renders lcm-logger logs (vehicle tracks from NODE_REPORT, NODE_REPORT_LOCAL\n"
               "or NAV_X/NAV_Y per community, with names; VIEW_POINT/POLYGON/SEGLIST/CIRCLE/MARKER/COMMS_PULSE/\n"
               "RANGE_PULSE; metre grid, legend) to PNG and SVG, or runs live as a shoreside viewer app.",
    .synopsis = "[OPTIONS] LOG [LOG...]\n"
                "[--alias=NAME] [--verbose] MISSION.moos [NAME]    (live viewer app; see --example, --interface)",
    .opts = (const kelp_cli_opt[]){
        { "output", required_argument, 'o', "OUT.png|OUT.svg", "write this picture (repeatable, up to 8)" },
        { "title", required_argument, OPT_TITLE, "T", "picture title" },
        { "size", required_argument, OPT_SIZE, "WxH", "picture size, 400 <= W, 300 <= H, both <= 10000" },
        { "no-pulses", no_argument, OPT_NO_PULSES, NULL, "do not draw comms and range pulses" },
        { "closest", no_argument, OPT_CLOSEST, NULL, "mark and print each pair of vehicles' closest approach" },
        { "quiet", no_argument, 'q', NULL, "print nothing but errors" },
        { NULL, 0, 0, NULL, NULL } },
    .more = "Without -o it writes LOG.png and LOG.svg next to the first log, and prints a per-vehicle summary\n"
            "(fixes, distance, duration, start, end). Exit 1 when a log cannot be read or holds nothing to draw.\n"
            "Live (a MISSION.moos argument, -e or -i): the MOOS options of every kelp app.\n",
};

/* ------------------------------------------------------------------ offline */

static int offline(int argc, char **argv)
{
    const char *outs[8];
    int nouts = 0;
    const char *logs[64];
    int nlogs = 0;
    kelp_plot_opts o = {1600, 1100, NULL, NULL, true, false};
    bool quiet = false;
    int c, status;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (c) {
        case KELP_CLI_EXIT:
            return status;
        case 'o':
            if (nouts < 8) outs[nouts++] = optarg;
            break;
        case OPT_TITLE:
            o.title = optarg;
            break;
        case OPT_SIZE: {
            int w, h;
            if (parse_size(optarg, &w, &h) < 0)
                return kelp_cli_error(&cli, "--size WxH with 400 <= W, 300 <= H, both <= 10000");
            o.width = w;
            o.height = h;
            break;
        }
        case OPT_NO_PULSES:
            o.show_pulses = false;
            break;
        case OPT_CLOSEST:
            o.show_closest = true;
            break;
        case 'q':
            quiet = true;
            break;
        }
    }
    for (int i = optind; i < argc && nlogs < 64; i++) logs[nlogs++] = argv[i];
    if (!nlogs) {
        kelp_cli_usage(&cli, stderr);
        return kelp_cli_error(&cli, "no log given");
    }
    kelp_plot_scene s;
    kelp_plot_scene_init(&s);
    unsigned long events = 0, undecoded = 0;
    int rc = 0;
    for (int i = 0; i < nlogs; i++)
        if (kelp_plot_scene_read_log(&s, logs[i], &events, &undecoded) < 0) rc = 1;
    kelp_plot_scene_finish(&s);
    char sub[512];
    const char *base = strrchr(logs[0], '/') ? strrchr(logs[0], '/') + 1 : logs[0];
    double dur = isfinite(s.t0) && s.t1 > s.t0 ? s.t1 - s.t0 : 0;
    snprintf(sub, sizeof sub, "%s%s  ·  %zu vehicle%s  ·  %.0f s of MOOS time  ·  %zu artifacts  ·  %lu log events", base,
             nlogs > 1 ? " (+ more logs)" : "", s.ntracks, s.ntracks == 1 ? "" : "s", dur, s.nviews, events);
    o.subtitle = sub;
    char defpng[1200], defsvg[1200];
    if (!nouts) {
        snprintf(defpng, sizeof defpng, "%s.png", logs[0]);
        snprintf(defsvg, sizeof defsvg, "%s.svg", logs[0]);
        outs[nouts++] = defpng;
        outs[nouts++] = defsvg;
    }
    for (int i = 0; i < nouts; i++) {
        if (kelp_plot_render(&s, &o, outs[i]) < 0) rc = 1;
        else if (!quiet) printf("kelp-plot: wrote %s\n", outs[i]);
    }
    if (!quiet) {
        printf("kelp-plot: %lu events, %lu not kelp variables (skipped)\n", events, undecoded);
        kelp_plot_print_summary(&s, stdout);
        if (o.show_closest) kelp_plot_print_closest(&s, stdout);
    }
    if (!s.ntracks && !s.nviews) {
        fprintf(stderr, "kelp-plot: nothing to draw (no vehicle positions, no VIEW_* postings)\n");
        rc = 1;
    }
    kelp_plot_scene_free(&s);
    kelp_plot_release();
    return rc;
}

/* ------------------------------------------------------------------ live */

typedef struct live {
    kelp_plot_scene s;
    char image[512], svg[512], title[128], table[512];
    double table_period, table_last;
    bool pulses;
    unsigned long mail;
} live;

static int live_startup(kelp_app *app, void *st)
{
    live *l = st;
    kelp_plot_scene_init(&l->s);
    l->pulses = true;
    if (kelp_app_param_str(app, "IMAGE", l->image, sizeof l->image) < 0) return -1;
    if (kelp_app_param_str(app, "SVG", l->svg, sizeof l->svg) < 0) return -1;
    if (kelp_app_param_str(app, "TITLE", l->title, sizeof l->title) < 0) return -1;
    if (kelp_app_param_bool(app, "SHOW_PULSES", &l->pulses) < 0) return -1;
    if (kelp_app_param_str(app, "TABLE_FILE", l->table, sizeof l->table) < 0) return -1;
    l->table_period = 5;
    const kelp_mission_node *n = kelp_app_param(app, "TABLE_PERIOD");
    if (n && (kelp_mission_double(n, &l->table_period) < 0 || !(l->table_period > 0)))
        return kelp_app_config_error(app, n, "TABLE_PERIOD must be a number of seconds > 0");
    l->table_last = -INFINITY;
    const char *vars[] = {"NODE_REPORT", "NODE_REPORT_LOCAL", "VIEW_*", "NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (kelp_app_register(app, vars[i], 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", vars[i]);
    return 0;
}

static void live_mail(kelp_app *app, void *st, const kelp_var *v)
{
    live *l = st;
    (void)app;
    l->mail++;
    if (!(v->flags & KELP_VAR_FLAG_SYNC)) kelp_plot_scene_add_var(&l->s, v);
}

static void vehicle_table(live *l, double now, FILE *out)
{
    fprintf(out, "%-10s %-6s %9s %9s %6s %7s %6s %-22s %7s %8s %6s\n", "Vehicle", "Type", "X", "Y", "Spd", "Hdg",
            "Dep", "Mode", "Reports", "Dist(m)", "Age(s)");
    fprintf(out, "%-10s %-6s %9s %9s %6s %7s %6s %-22s %7s %8s %6s\n", "-------", "----", "-", "-", "---", "---", "---",
            "----", "-------", "-------", "------");
    size_t shown = 0;
    for (size_t i = 0; i < l->s.ntracks; i++) {
        const kelp_plot_track *t = &l->s.tracks[i];
        if (!t->n) continue;
        if (t->src == KELP_PLOT_SRC_NAV && kelp_plot_scene_track(&l->s, t->name) != t) continue; /* has reports */
        const kelp_plot_pt *p = &t->pts[t->n - 1];
        double d = 0;
        for (size_t j = 1; j < t->n; j++) d += hypot(t->pts[j].x - t->pts[j - 1].x, t->pts[j].y - t->pts[j - 1].y);
        const kelp_nodereport *r = &t->last;
        bool rep = t->src == KELP_PLOT_SRC_REPORT;
        fprintf(out, "%-10.10s %-6.6s %9.1f %9.1f %6.2f %7.1f %6.1f %-22.22s %7lu %8.0f %6.1f\n", t->name,
                rep && (r->fields & KELP_NR_TYPE) ? r->type : "-", p->x, p->y, isfinite(p->spd) ? p->spd : 0,
                isfinite(p->hdg) ? p->hdg : 0, rep && (r->fields & KELP_NR_DEPTH) ? r->depth : 0,
                rep && (r->fields & KELP_NR_MODE) ? r->mode : "-", t->reports, d, now - p->t);
        shown++;
    }
    if (!shown) fprintf(out, "(no vehicles yet: waiting for NODE_REPORT)\n");
    fprintf(out, "Artifacts: %zu; rejected reports %lu, VIEW_* %lu%s%s\n", l->s.nviews, l->s.bad_reports,
            l->s.bad_views, l->s.last_bad[0] ? "; last: " : "", l->s.last_bad);
}

static void live_report(kelp_app *app, void *st, FILE *out)
{
    vehicle_table(st, kelp_app_time(app), out);
}

/* the table also goes to TABLE_FILE (replaced atomically) every TABLE_PERIOD s of MOOS time */
static void write_table(kelp_app *app, live *l, double now)
{
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s.tmp", l->table);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        kelp_app_run_warning(app, "cannot write %s", tmp);
        return;
    }
    fprintf(f, "Shoreside (%s) at MOOS time +%.0f s\n", kelp_app_community(app), now - kelp_app_start_time(app));
    vehicle_table(l, now, f);
    if (fclose(f) != 0 || rename(tmp, l->table) != 0) kelp_app_run_warning(app, "cannot write %s", l->table);
}

static int live_iterate(kelp_app *app, void *st, double now)
{
    live *l = st;
    if (l->table[0] && now - l->table_last >= l->table_period) {
        write_table(app, l, now);
        l->table_last = now;
    }
    return 0;
}

static void live_shutdown(kelp_app *app, void *st)
{
    live *l = st;
    kelp_plot_scene_finish(&l->s);
    char sub[256];
    double dur = isfinite(l->s.t0) && l->s.t1 > l->s.t0 ? l->s.t1 - l->s.t0 : 0;
    snprintf(sub, sizeof sub, "community %s (live)  ·  %zu vehicle%s  ·  %.0f s of MOOS time  ·  %zu artifacts",
             kelp_app_community(app), l->s.ntracks, l->s.ntracks == 1 ? "" : "s", dur, l->s.nviews);
    kelp_plot_opts o = {1600, 1100, l->title[0] ? l->title : NULL, sub, l->pulses, false};
    const char *outs[2] = {l->image, l->svg};
    for (int i = 0; i < 2; i++)
        if (outs[i][0]) {
            if (kelp_plot_render(&l->s, &o, outs[i]) == 0) kelp_app_event(app, "wrote %s", outs[i]);
            else kelp_app_run_warning(app, "cannot write %s", outs[i]);
        }
    if (l->table[0]) write_table(app, l, kelp_app_time(app));
    kelp_plot_print_summary(&l->s, stdout);
    kelp_plot_release(); /* the scene stays: the runner prints a last report after this */
}

static const kelp_app_def live_def = {
    .name = "kelp-plot",
    .purpose = "Live shoreside viewer: a table of the vehicles (NODE_REPORT) and a picture of the mission on exit.",
    .params = (const kelp_app_param_info[]){
        { "IMAGE", "mission.png", "PNG written when the app stops (optional)", NULL },
        { "SVG", "mission.svg", "SVG written when the app stops (optional)", NULL },
        { "TITLE", "Fleet demo", "picture title (optional)", NULL },
        { "SHOW_PULSES", "true", "draw comms and range pulses", NULL },
        { "TABLE_FILE", "vehicles.txt", "the vehicle table, rewritten every TABLE_PERIOD (optional)", NULL },
        { "TABLE_PERIOD", "5", "seconds of MOOS time", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2.0,HDG=118.8", NULL },
        { "NODE_REPORT_LOCAL", "(as NODE_REPORT)", NULL },
        { "VIEW_*", "x=10,y=20,label=alpha", "VIEW_POINT, VIEW_SEGLIST, VIEW_POLYGON, VIEW_RANGE_PULSE, ..." },
        { "NAV_X", "112.3", "also NAV_Y, NAV_HEADING, NAV_SPEED" },
        { NULL, NULL, NULL } },
    .startup = live_startup,
    .on_mail = live_mail,
    .iterate = live_iterate,
    .report = live_report,
    .shutdown = live_shutdown,
};

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        size_t n = strlen(argv[i]);
        if (argv[i][0] != '-' && n > 5 && strcmp(argv[i] + n - 5, ".moos") == 0) {
            static live l;
            return kelp_app_run(argc, argv, &live_def, &l);
        }
        if (!strcmp(argv[i], "--example") || !strcmp(argv[i], "--interface") || !strcmp(argv[i], "-e") ||
            !strcmp(argv[i], "-i") || !strncmp(argv[i], "--alias", 7)) {
            static live l;
            return kelp_app_run(argc, argv, &live_def, &l);
        }
    }
    return offline(argc, argv);
}
