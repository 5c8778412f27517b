/* pContactMgrV20: the contact manager (seed 003; shared/spec/contactmgr.md): contacts from
 * NODE_REPORT, alerts by range and CPA range with flag macros, filters, retirement, summaries,
 * custom range reports, range rings. The logic is kelp_contactmgr in the core; this file reads the
 * block and wires the core to the bus. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <kelp/edge/app.h>
#include <kelp/contactmgr.h>

typedef struct cmgr_app {
    kelp_app *app;
    kelp_contactmgr *core;           /* about 1.3 MB: on the heap (reachable until exit) */
    kelp_field_sink sink, cfg_sink;
    char text[32768];          /* the terminal report */
    unsigned long events_shown; /* the core's events already in the AppCast */
} cmgr_app;

/* the core's new events into the AppCast's events */
static void forward_events(cmgr_app *a)
{
    for (; a->events_shown < a->core->events_made; a->events_shown++) {
        const char *e = kelp_contactmgr_event(a->core, a->events_shown);
        if (e) kelp_app_event(a->app, "%s", e);
    }
}

static void publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    cmgr_app *a = ctx;
    int rc = is_string ? kelp_app_notify_string(a->app, var, sval) : kelp_app_notify_double(a->app, var, dval);
    if (rc < 0) kelp_app_run_warning(a->app, "cannot publish %s", var);
}

static void warn(void *ctx, const char *msg)
{
    /* 24.8 files a bad alert component as a configuration warning, mail or not (its
     * handleConfigAlert); the request itself ("Unhandled Alert Request: ...") as a run warning */
    if (strncmp(msg, "unhandled alert config component: ", 34) == 0) {
        kelp_app_config_warning(((cmgr_app *)ctx)->app, "%s", msg);
        return;
    }
    kelp_app_run_warning(((cmgr_app *)ctx)->app, "%s", msg);
}

static void cfg_warn(void *ctx, const char *msg)
{
    kelp_app_config_warning(((cmgr_app *)ctx)->app, "%s", msg);
}

static int param(void *ctx, const char *key, const char *val, kelp_diag *d)
{
    cmgr_app *a = ctx;
    (void)d;
    return kelp_contactmgr_config(a->core, key, val, &a->cfg_sink);
}

static int startup(kelp_app *app, void *st)
{
    cmgr_app *a = st;
    a->app = app;
    a->sink = (kelp_field_sink){ a, publish, warn };
    a->cfg_sink = (kelp_field_sink){ a, publish, cfg_warn };
    a->core = malloc(sizeof *a->core);
    if (!a->core) return kelp_app_config_error(app, NULL, "out of memory");
    kelp_contactmgr_init(a->core, kelp_app_community(app));
    int rc = kelp_app_param_foreach(app, param, a);
    if (rc < 0) return rc;
    double lat0 = 0, lon0 = 0;
    bool hl = kelp_app_global_double(app, "LatOrigin", &lat0) == 1;
    bool hn = kelp_app_global_double(app, "LongOrigin", &lon0) == 1;
    kelp_contactmgr_config_done(a->core, hl, lat0, hn, lon0, &a->cfg_sink);
    const char *v;
    for (unsigned i = 0; (v = kelp_contactmgr_subscription(i)) != NULL; i++)
        if (kelp_app_register(app, v, 0) < 0) return kelp_app_config_error(app, NULL, "cannot register %s", v);
    const char *able[3] = { a->core->disable_var, a->core->enable_var, a->core->expunge_var };
    for (int i = 0; i < 3; i++)
        if (able[i][0] && kelp_app_register(app, able[i], 0) < 0)
            return kelp_app_config_error(app, NULL, "cannot register %s", able[i]);
    KELP_IGNORE(kelp_app_notify_double(app, "PCONTACTMGRV20_PID", (double)getpid()));
    a->events_shown = a->core->events_made;
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    cmgr_app *a = st;
    if (v->kind == KELP_VAR_BINARY) return;
    /* refused mail is warned through the sink and counted by the core */
    KELP_IGNORE(kelp_contactmgr_mail(a->core, v->name, v->kind == KELP_VAR_STRING, v->sval, v->dval, kelp_app_time(app),
                                     v->source, &a->sink));
    forward_events(a);
}

static int iterate(kelp_app *app, void *st, double now)
{
    cmgr_app *a = st;
    (void)app;
    kelp_contactmgr_iterate(a->core, now, &a->sink);
    forward_events(a);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    cmgr_app *a = st;
    if (!a->core) return;
    if (kelp_contactmgr_report_text(a->core, kelp_app_time(app), a->text, sizeof a->text) < 0) fputs("(report cut)\n", out);
    fputs(a->text, out);
}

static const kelp_app_def def = {
    .name = "pContactMgrV20",
    .pid_var = "PCONTACTMGRV20_PID",
    .purpose = "The contact manager: alerts by range and CPA range about contacts, summaries, range reports.",
    .synopsis = "The contact manager deals with other known vehicles in its\n"
                "vicinity. It handles incoming reports perhaps received via a\n"
                "sensor application or over a communications link. Minimally\n"
                "it posts summary reports, but may also be configured to post\n"
                "alerts with user-configured content about the contacts.",
    .unhandled_prefix = "Unhandled config line: ", /* 24.8's reportUnhandledConfigWarning */
    .params = (const kelp_app_param_info[]){
        { "alert", "id=avd, on_flag=CONTACT_INFO=name=avd_$[VNAME] # contact=$[VNAME], alert_range=80, cpa_range=95",
          "an alert (repeat; lines with one id accumulate): id, alert_range, cpa_range, on_flag, off_flag, filters", NULL },
        { "ignore_name", "henry,gilda", "contacts not managed (also match_name, ignore_/match_type, _group)", NULL },
        { "match_name", "abe,cal", "only these contacts are managed", NULL },
        { "ignore_type", "usv,uuv", "types not managed", NULL },
        { "match_type", "ship", "only these types", NULL },
        { "ignore_group", "alpha", "groups not managed", NULL },
        { "match_group", "bravo,gamma", "only these groups", NULL },
        { "ignore_region", "pts={60,-40:60,-160:150,-160:150,-40}", "convex polygon whose contacts are ignored", NULL },
        { "match_region", "pts={60,70:60,160:150,160:150,70}", "convex polygon: only contacts inside one", NULL },
        { "strict_ignore", "true", "a contact without TYPE/GROUP fails ignore_type/_group (default true)", NULL },
        { "contact_max_age", "60", "s after its last report a contact is retired (default 60, as 24.8)", NULL },
        { "max_contact_age", "60", "the seed's other name", "contact_max_age" },
        { "max_retired_history", "5", "retired names kept, 1..50 (default 5)", NULL },
        { "max_retired_hist", "5", "the seed's other name", "max_retired_history" },
        { "max_contacts", "500", "contacts held; the farthest are retired beyond (default 500)", NULL },
        { "display_radii", "false", "a VIEW_CIRCLE alert_<ownship> at the largest cpa_range (default false)", NULL },
        { "display_radii_id", "avd", "accepted, unused (as 24.8)", NULL },
        { "alert_verbose", "false", "ALERT_VERBOSE postings (default false)", NULL },
        { "alert_range_color", "gray65", "the ring's colour; invisible or empty: posted inactive (default gray65)", NULL },
        { "cpa_range_color", "gray30", "accepted, unused (as 24.8)", NULL },
        { "decay", "15,30", "s: extrapolate at full speed to a, slowing to 0 at b (default 15,30)", NULL },
        { "recap_interval", "1", "s between CONTACTS_RECAP, or off (default 1)", NULL },
        { "contacts_recap_interval", "1", "the seed's other name", "recap_interval" },
        { "range_report_timeout", "10", "s a BCM_REPORT_REQUEST lives (default 10)", NULL },
        { "range_report_maxsize", "20", "custom reports beyond which a timed-out one is dropped each iteration (default 20)", NULL },
        { "contact_local_coords", "lazy_lat_lon", "lazy_lat_lon (24.8: X/Y from LAT/LON when absent), force_lat_lon or verbatim (default lazy_lat_lon)", NULL },
        { "post_closest_range", "false", "CONTACT_CLOSEST_RANGE (default false)", NULL },
        { "post_closest_relbng", "false", "CONTACT_CLOSEST_RELBNG (default false)", NULL },
        { "post_all_ranges", "false", "CONTACT_RANGES (default false)", NULL },
        { "reject_range", "2000", "m beyond which contacts are dropped, or off (default 2000)", NULL },
        { "ownship_group", "blue_team", "informational", NULL },
        { "ownship_type", "kayak", "informational", NULL },
        { "hold_alerts_for_helm", "false", "no alerts until IVPHELM_STATE=DRIVE (default false)", NULL },
        { "disable_var", "DISABLE_TARGET", "mail: contact=<name> or vsource=<src>: BHV_ABLE_FILTER, action=disable", NULL },
        { "enable_var", "REENABLE_TARGET", "the same, action=enable", NULL },
        { "expunge_var", "EXPUNGE_TARGET", "the same, action=expunge", NULL },
        { "able_flag", "MOOS_VAR = val", "posted at a contact's disable or enable", NULL },
        { "disable_flag", "MOOS_VAR = val", "posted at a contact's disable ($[RECENT_DISABLED] $[TOTAL_DISABLED] $[ALL_DISABLED])", NULL },
        { "enable_flag", "MOOS_VAR = val", "posted at a contact's enable ($[RECENT_ENABLED])", NULL },
        { "early_warning_time", "30", "s: warn a closing contact this long before the largest alert range (default off)", NULL },
        { "early_warning_radii", "true", "VIEW_CIRCLE xewarn_<contact> at each warning range (default false)", NULL },
        { "ewarn_radii_color", "yellow", "colour of those rings (default green)", NULL },
        { "early_warning_flag", "MOOS_VAR = val", "posted at an early warning ($[CONTACT] $[RNG] $[RNG_EXT] $[CPA] $[ROC] $[UTC])", NULL },
        { "cease_warning_flag", "MOOS_VAR = val", "posted when the warned contact opens beyond 1.05 x its warned range", NULL },
        { "retire_flag", "MOOS_VAR = val", "posted per retired or refused contact ($[CONTACT] $[UTC])", NULL },
        { "app_logging", "false", "accepted (record the bus with kelp-record)", NULL },
        { "default_alert_range_color", "gray65", "older name", "alert_range_color" },
        { "default_cpa_range_color", "gray30", "older name", "cpa_range_color" },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "NODE_REPORT", "NAME=alpha,TYPE=UUV,TIME=1252348077.59,X=51.71,Y=-35.50,SPD=2.0,HDG=118.8", "a contact" },
        { "NAV_X", "112.3", "ownship (also NAV_Y, NAV_HEADING, NAV_SPEED)" },
        { "NAV_Y", "-99.1", NULL },
        { "NAV_HEADING", "118.8", NULL },
        { "NAV_SPEED", "2.0", NULL },
        { "BCM_ALERT_REQUEST", "id=avd, on_flag=CONTACT_INFO=name=$[VNAME], alert_range=80, cpa_range=84",
          "an alert, as an alert line; id=avd, action=disable|enable" },
        { "BCM_REPORT_REQUEST", "var=CONTACTS_50, range=50", "names within range go to var (group=, type=, refresh=)" },
        { "BCM_DISPLAY_RADII", "true", "true, false, toggle or an alert id" },
        { "IVPHELM_STATE", "DRIVE", "with hold_alerts_for_helm" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<alert flags>", "CONTACT_INFO=name=avd_alpha # contact=alpha", "on_flag / off_flag postings" },
        { "CONTACTS_LIST", "delta,gus,henry", NULL },
        { "CONTACTS_ALERTED", "(delta,avd)(gus,avd)", NULL },
        { "CONTACTS_COUNT", "2", "alerted pairs" },
        { "CONTACTS_RETIRED", "bravo,foxtrot", "newest first" },
        { "CONTACTS_RECAP", "vname=delta,range=193.10,age=11.30 # vname=gus,range=48.20,age=0.70", NULL },
        { "CONTACT_CLOSEST", "gus", NULL },
        { "CONTACT_CLOSEST_TIME", "17514261063.3", NULL },
        { "CONTACT_CLOSEST_RANGE", "48", "if post_closest_range" },
        { "CONTACT_CLOSEST_RELBNG", "344", "if post_closest_relbng" },
        { "CONTACT_RANGES", "18.2,48.2,193.1", "if post_all_ranges" },
        { "<report var>", "vid_0027,vid_0197", "BCM_REPORT_REQUEST's var" },
        { "ALERT_VERBOSE", "new_contact=gus", "if alert_verbose" },
        { "BHV_ABLE_FILTER", "contact=henry,action=disable", "at disable_var/enable_var/expunge_var mail" },
        { "VIEW_CIRCLE", "x=-150.3,y=-117.5,radius=100,label=alert_ben,edge_color=gray65,time=17514261063.3,duration=3,vertex_size=0,edge_size=1", "if display_radii" },
        { "PCONTACTMGRV20_PID", "3988", NULL },
        { NULL, NULL, NULL } },
    .notes = "Globals used: Community (ownship), LatOrigin, LongOrigin.\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static cmgr_app a;
    return kelp_app_run(argc, argv, &def, &a);
}
