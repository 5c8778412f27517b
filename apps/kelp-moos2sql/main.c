/* kelp-moos2sql: the iMOOS2SQL role. Records status (node reports), contact (pContactMgrV20's
 * reports) and track (decoded acoustic status messages) postings into an SQLite database and
 * keeps a Google Earth KML of the fleet current, with a NetworkLink file that reloads it.
 *
 *   kelp-moos2sql MISSION.moos [NAME]          live, in a community (ProcessConfig = iMOOS2SQL)
 *   kelp-moos2sql [OPTIONS] --log=LOG          from an LCM log
 *
 * The classification, schema and KML are the core kelp_moos2sql (include/kelp/moos2sql.h); the
 * database is store.c. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/app.h>
#include <kelp/edge/lcmlog.h>
#include <kelp/util.h>
#include "store.h"

typedef struct m2s {
    kelp_moos2sql_cfg cfg;
    kelp_moos2sql_fleet fleet;
    m2s_store *store;
    double kml_last;
    unsigned long bad, ignored;
    unsigned long rows[3];      /* committed rows per kind, kept after the store closes */
    unsigned version;
    char last_bad[160];
} m2s;

/* one posting: classify, store, update the fleet; -1 when the database fails */
static int take(m2s *s, const kelp_var *v, char *err, size_t cap)
{
    kelp_moos2sql_record r;
    kelp_diag dg = { 0 };
    bool str = v->kind == KELP_VAR_STRING;
    if (v->kind == KELP_VAR_BINARY || !s->store) return 0;
    int rc = kelp_moos2sql_classify(&s->cfg, v->name, v->community, v->time, str, v->sval, str ? v->slen : 0, v->dval, &r, &dg);
    if (rc == 0) {
        s->ignored++;
        return 0;
    }
    if (rc < 0) {
        s->bad++;
        snprintf(s->last_bad, sizeof s->last_bad, "%s: %s", v->name, dg.code ? kelp_diag_text(&dg) : "unreadable");
        return 0;
    }
    (void)kelp_moos2sql_fleet_update(&s->fleet, &s->cfg, &r);
    return m2s_store_put(s->store, &r, err, cap);
}

/* the store's counts, kept for the last report after it closes */
static void counts(m2s *s)
{
    if (!s->store) return;
    for (int k = 0; k < 3; k++) s->rows[k] = m2s_store_rows(s->store, k + 1);
    s->version = m2s_store_version(s->store);
}

static void summary(m2s *s, FILE *out)
{
    counts(s);
    fprintf(out, "database schema version %u; rows: status %lu, contact %lu, track %lu; %lu unreadable", s->version,
            s->rows[0], s->rows[1], s->rows[2], s->bad);
    if (s->last_bad[0]) fprintf(out, " (last: %s)", s->last_bad);
    fprintf(out, "; %u vehicles in the KML\n", s->fleet.n);
}

/* ------------------------------------------------------------------ live */

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    return kelp_moos2sql_config(&((m2s *)ctx)->cfg, key, val, d);
}

static int startup(kelp_app *app, void *st)
{
    m2s *s = st;
    kelp_moos2sql_cfg_default(&s->cfg);
    kelp_moos2sql_fleet_init(&s->fleet);
    int rc = kelp_app_param_foreach(app, param, s);
    if (rc < 0) return rc;
    double lat, lon;
    if (kelp_app_global_double(app, "LatOrigin", &lat) == 1 && kelp_app_global_double(app, "LongOrigin", &lon) == 1)
        s->cfg.have_datum = kelp_geo_init(&s->cfg.datum, lat, lon) == 0;
    char err[512];
    s->store = m2s_store_open(s->cfg.database, s->cfg.commit_period, err, sizeof err);
    if (!s->store) return kelp_app_config_error(app, NULL, "%s", err);
    for (unsigned k = 0; k < 3; k++)
        for (unsigned i = 0; i < s->cfg.nvars[k]; i++)
            if (kelp_app_register(app, s->cfg.vars[k][i], 0) < 0)
                return kelp_app_config_error(app, NULL, "cannot register %s", s->cfg.vars[k][i]);
    s->kml_last = -1e300;
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    char err[512];
    if (take(st, v, err, sizeof err) < 0) kelp_app_run_warning(app, "%s", err);
}

static int iterate(kelp_app *app, void *st, double now)
{
    m2s *s = st;
    char err[512];
    if (s->store && m2s_store_tick(s->store, 1, err, sizeof err) < 0) kelp_app_run_warning(app, "%s", err);
    if (s->cfg.kml[0] && now - s->kml_last >= s->cfg.kml_period) {
        if (m2s_write_kml(&s->fleet, s->cfg.kml, s->cfg.kml_link, s->cfg.kml_period, err, sizeof err) < 0)
            kelp_app_run_warning(app, "%s", err);
        s->kml_last = now;
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    (void)app;
    summary(st, out);
}

static void shutdown_(kelp_app *app, void *st)
{
    m2s *s = st;
    char err[512];
    if (s->cfg.kml[0] && m2s_write_kml(&s->fleet, s->cfg.kml, s->cfg.kml_link, s->cfg.kml_period, err, sizeof err) < 0)
        kelp_app_run_warning(app, "%s", err);
    if (s->store) {
        if (m2s_store_tick(s->store, 1, err, sizeof err) < 0) kelp_app_run_warning(app, "%s", err);
        counts(s);
        m2s_store_close(s->store);
        s->store = NULL;
    }
}

static const kelp_app_def live_def = {
    .name = "kelp-moos2sql",
    .moos_name = "iMOOS2SQL",
    .purpose = "Record node reports, contact reports and decoded acoustic status messages into SQLite; keep a KML of the fleet.",
    .synopsis = "The iMOOS2SQL role (Goby 1.1's topside recorder): every status (NODE_REPORT), contact\n"
                "(pContactMgrV20's CONTACTS_* / CONTACT_*) and track (pAcommsHandler's decoded status messages)\n"
                "posting becomes a row of an SQLite database (WAL; committed at least every COMMIT_PERIOD s,\n"
                "so a killed process loses nothing committed), and a Google Earth KML with a Placemark per\n"
                "vehicle is rewritten every KML_PERIOD s, with a NetworkLink file that reloads it.\n"
                "Schema: include/kelp/moos2sql.h (PRAGMA user_version = migrations applied).",
    .params = (const kelp_app_param_info[]){
        { "DATABASE", "moos2sql.db", "the SQLite database (created, migrated to the current schema)", NULL },
        { "KML_FILE", "fleet.kml", "the fleet's KML, rewritten every KML_PERIOD (empty: none)", NULL },
        { "KML_LINK_FILE", "fleet_link.kml", "the NetworkLink file a display opens (empty: none)", NULL },
        { "KML_PERIOD", "2", "seconds between KML rewrites, also the link's refreshInterval", NULL },
        { "COMMIT_PERIOD", "0.25", "seconds a transaction stays open at most, in (0, 0.5]", NULL },
        { "STATUS_VAR", "NODE_REPORT", "more node report variables (repeatable, comma lists)", NULL },
        { "CONTACT_VAR", "CONTACTS_LIST", "more contact report variables (repeatable, comma lists)", NULL },
        { "TRACK_VAR", "STATUS_REPORT", "more decoded status message variables (repeatable, comma lists)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,LAT=43.824981,LON=-70.329755",
          "also NODE_REPORT_LOCAL and each STATUS_VAR: status rows" },
        { "CONTACTS_LIST", "delta,gus", "also CONTACTS_ALERTED, _UNALERTED, _RETIRED, _RECAP, _COUNT, CONTACT_CLOSEST,\n"
                                        "                  CONTACT_CLOSEST_RANGE, CONTACT_RANGES and each CONTACT_VAR: contact rows" },
        { "STATUS_REPORT", "name=alder,nav_x=12.5,nav_y=-40,heading=90,speed=1.5",
          "also STATUS_SUMMARY, STATUS_REPORT_IN and each TRACK_VAR: track rows" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){ { NULL, NULL, NULL } },
    .notes = "Globals used: LatOrigin, LongOrigin (x/y-only positions in the KML).\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_,
};

/* ------------------------------------------------------------------ from a log */

enum { OPT_LOG = 256, OPT_DB, OPT_KML, OPT_LINK, OPT_DATUM };

static const kelp_cli cli = {
    .name = "kelp-moos2sql",
    .purpose = "Record node reports, contact reports and decoded acoustic status messages into SQLite and write\n"
               "a Google Earth KML of the fleet, live (an app: see --example, --interface) or from an LCM log.",
    .synopsis = "[OPTIONS] --log=LOG\n[--alias=NAME] [--verbose] MISSION.moos [NAME]    (live app; see --example, --interface)",
    .opts = (const kelp_cli_opt[]){
        { "log", required_argument, OPT_LOG, "LOG", "read this LCM log (kelp-record, lcm-logger)" },
        { "db", required_argument, OPT_DB, "FILE", "the database (default moos2sql.db)" },
        { "kml", required_argument, OPT_KML, "FILE", "the fleet's KML (default fleet.kml; \"\" none)" },
        { "link", required_argument, OPT_LINK, "FILE", "the NetworkLink file (default fleet_link.kml; \"\" none)" },
        { "datum", required_argument, OPT_DATUM, "LAT,LON", "datum for x/y-only positions" },
        { NULL, 0, 0, NULL, NULL } },
    .more = "Prints the rows written per table. Exit 1 when the log or the database cannot be used.\n",
};

static int from_log(int argc, char **argv)
{
    static m2s s;
    kelp_moos2sql_cfg_default(&s.cfg);
    kelp_moos2sql_fleet_init(&s.fleet);
    const char *log = NULL;
    kelp_diag dg = { 0 };
    int c, status;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        if (c == KELP_CLI_EXIT) return status;
        const char *key = c == OPT_DB ? "DATABASE" : c == OPT_KML ? "KML_FILE" : c == OPT_LINK ? "KML_LINK_FILE" : NULL;
        if (c == OPT_LOG) log = optarg;
        if (key && kelp_moos2sql_config(&s.cfg, key, optarg, &dg) < 0) return kelp_cli_error(&cli, "%s: %s", key, kelp_diag_text(&dg));
        if (c == OPT_DATUM) {
            double lat, lon;
            char *comma = strchr(optarg, ',');
            if (!comma || kelp_util_parse_finite(optarg, (size_t)(comma - optarg), &lat) < 0 ||
                kelp_util_parse_finite(comma + 1, strlen(comma + 1), &lon) < 0 || kelp_geo_init(&s.cfg.datum, lat, lon) < 0)
                return kelp_cli_error(&cli, "--datum LAT,LON");
            s.cfg.have_datum = true;
        }
    }
    if (optind < argc) return kelp_cli_error(&cli, "unexpected argument '%s'", argv[optind]);
    if (!log) {
        kelp_cli_usage(&cli, stderr);
        return kelp_cli_error(&cli, "no log given (--log=LOG), and no mission file");
    }
    char err[512];
    kelp_diag lerr = {0};
    kelp_lcmlog_reader *r = kelp_lcmlog_open(log, 0, &lerr);
    if (!r) return fprintf(stderr, "kelp-moos2sql: %s\n", kelp_diag_text(&lerr)), 1;
    s.store = m2s_store_open(s.cfg.database, 0.5, err, sizeof err);
    if (!s.store) {
        kelp_lcmlog_close(r);
        return fprintf(stderr, "kelp-moos2sql: %s\n", err), 1;
    }
    kelp_var *v = malloc(sizeof *v);
    kelp_lcmlog_event ev;
    const char *channel;
    int rr = 1, rc = 0;
    while (v && rc == 0 && (rr = kelp_lcmlog_next(r, &ev, &channel)) > 0)
        /* bus writes only: a sync reply (a retained value replayed on a late registrant's channel) is not one */
        if (kelp_var_decode(ev.data, ev.data_len, v) == 0 && strcmp(channel, v->name) == 0) rc = take(&s, v, err, sizeof err);
    if (rc == 0 && rr < 0) rc = -1, snprintf(err, sizeof err, "read error in %s", log);
    if (!v) rc = -1, snprintf(err, sizeof err, "out of memory");
    free(v);
    kelp_lcmlog_close(r);
    if (rc == 0) rc = m2s_store_tick(s.store, 1, err, sizeof err);
    if (rc == 0 && s.cfg.kml[0]) rc = m2s_write_kml(&s.fleet, s.cfg.kml, s.cfg.kml_link, s.cfg.kml_period, err, sizeof err);
    if (rc < 0) fprintf(stderr, "kelp-moos2sql: %s\n", err);
    summary(&s, stdout);
    m2s_store_close(s.store);
    return rc < 0 ? 1 : 0;
}

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        size_t n = strlen(argv[i]);
        if ((argv[i][0] != '-' && n > 5 && strcmp(argv[i] + n - 5, ".moos") == 0) || !strcmp(argv[i], "--example") ||
            !strcmp(argv[i], "--interface") || !strcmp(argv[i], "-e") || !strcmp(argv[i], "-i") ||
            !strncmp(argv[i], "--alias", 7)) {
            static m2s s;
            return kelp_app_run(argc, argv, &live_def, &s);
        }
    }
    return from_log(argc, argv);
}
