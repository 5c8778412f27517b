/* kelp-mac: the uMAC role. Asks every app of a community for its AppCast (APPCAST_REQ, node=all,
 * app=all, renewed every 2 s) and shows what comes back: the list of apps with their
 * iteration and warning counts, or one app's cast, refreshed in place on a terminal.
 * Keys (on a terminal): 1-9 show that app of the list, n / p next / previous app, l the list,
 * h help, q quit. The core parses and renders casts (include/kelp/appcast.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>
#include <kelp/edge/app.h>
#include <kelp/appcast.h>

#define MAX_APPS 64

typedef struct cast {
    kelp_appcast ac;
    double heard;                /* MOOS time of the last cast */
    unsigned long casts;
} cast;

typedef struct mac {
    cast apps[MAX_APPS];         /* in (node, proc) order (the state is static: no heap) */
    int napps;
    int shown;                   /* -1: the list */
    char want_node[KELP_APPCAST_NAME], want_app[KELP_APPCAST_NAME];
    double next_req, now;
    unsigned long bad;
    bool raw;
    struct termios saved;
    bool help;
} mac;

static int cmp_cast(const cast *a, const cast *b)
{
    int c = strcmp(a->ac.node, b->ac.node);
    return c ? c : strcmp(a->ac.proc, b->ac.proc);
}

static void take(mac *m, const kelp_appcast *ac)
{
    int i = 0;
    while (i < m->napps && (strcmp(m->apps[i].ac.node, ac->node) != 0 || strcmp(m->apps[i].ac.proc, ac->proc) != 0)) i++;
    if (i == m->napps) {
        if (m->napps == MAX_APPS) return;
        m->napps++;
        m->apps[i].casts = 0;
    }
    m->apps[i].ac = *ac;
    m->apps[i].heard = m->now;
    m->apps[i].casts++;
    /* keep the list sorted (insertion: one entry moved) */
    while (i > 0 && cmp_cast(&m->apps[i], &m->apps[i - 1]) < 0) {
        cast t = m->apps[i];
        m->apps[i] = m->apps[i - 1];
        m->apps[i - 1] = t;
        if (m->shown == i) m->shown = i - 1;
        else if (m->shown == i - 1) m->shown = i;
        i--;
    }
}

static void on_key(kelp_app *app, void *st, int fd)
{
    mac *m = st;
    char c;
    if (read(fd, &c, 1) != 1) return;
    if (c >= '1' && c <= '9' && c - '1' < m->napps) m->shown = c - '1';
    else if (c == 'n' && m->napps) m->shown = (m->shown + 1) % m->napps;
    else if (c == 'p' && m->napps) m->shown = m->shown <= 0 ? m->napps - 1 : m->shown - 1;
    else if (c == 'l' || c == 'a') m->shown = -1;
    else if (c == 'h') m->help = !m->help;
    else if (c == 'q') kelp_app_quit(app);
}

static int startup(kelp_app *app, void *st)
{
    mac *m = st;
    m->shown = -1;
    snprintf(m->want_node, sizeof m->want_node, "all");
    snprintf(m->want_app, sizeof m->want_app, "all");
    const kelp_mission_node *n;
    if ((n = kelp_app_param(app, "node")) && kelp_mission_copy(n, m->want_node, sizeof m->want_node) < 0)
        return kelp_app_config_error(app, n, "node name too long");
    if ((n = kelp_app_param(app, "app")) && kelp_mission_copy(n, m->want_app, sizeof m->want_app) < 0)
        return kelp_app_config_error(app, n, "app name too long");
    if (kelp_app_register(app, "APPCAST", 0) < 0) return kelp_app_config_error(app, NULL, "cannot register APPCAST");
    if (isatty(0) && tcgetattr(0, &m->saved) == 0) {
        struct termios t = m->saved;
        t.c_lflag &= ~(tcflag_t)(ICANON | ECHO);
        t.c_cc[VMIN] = 1;
        t.c_cc[VTIME] = 0;
        m->raw = tcsetattr(0, TCSANOW, &t) == 0;
        if (kelp_app_watch_fd(app, 0, on_key) < 0) kelp_app_run_warning(app, "keys unavailable");
    }
    return 0;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    mac *m = st;
    static kelp_appcast ac;
    kelp_diag why;
    kelp_diag_clear(&why);
    if (v->kind != KELP_VAR_STRING) return;
    if (kelp_appcast_parse(v->sval, v->slen, &ac, &why) != KELP_OK) {
        m->bad++;
        kelp_app_run_warning(app, "an APPCAST from %s does not parse: %s", v->source, kelp_diag_text(&why));
        return;
    }
    if (!ac.node[0]) snprintf(ac.node, sizeof ac.node, "%s", v->community);
    take(m, &ac);
}

static int iterate(kelp_app *app, void *st, double now)
{
    mac *m = st;
    m->now = now;
    if (now >= m->next_req) {
        char req[256];
        snprintf(req, sizeof req, "node=%s,app=%s,duration=3,key=kelp-mac_%ld,thresh=any", m->want_node, m->want_app,
                 (long)getpid());
        if (kelp_app_notify_string(app, "APPCAST_REQ", req) < 0) kelp_app_run_warning(app, "cannot post APPCAST_REQ");
        m->next_req = now + 2.0;
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    mac *m = st;
    (void)app;
    if (m->help) fprintf(out, "keys: 1-9 show an app, n/p next/previous, l the list, h help, q quit\n");
    if (m->shown >= 0 && m->shown < m->napps) {
        static char buf[3 * KELP_APPCAST_MSG];
        size_t len;
        const cast *c = &m->apps[m->shown];
        int rc = kelp_appcast_render(&c->ac, buf, sizeof buf, &len);
        fputs(buf, out);
        if (rc != KELP_OK) fputs("\n(cut)\n", out);
        fprintf(out, "(%lu casts, last %.1f s ago; l: the list)\n", c->casts, m->now - c->heard);
        return;
    }
    fprintf(out, "%-3s %-14s %-22s %8s %6s %6s %10s\n", "#", "node", "app", "iter", "cfg", "run", "heard (s)");
    for (int i = 0; i < m->napps; i++) {
        const cast *c = &m->apps[i];
        fprintf(out, "%-3d %-14s %-22s %8lu %6u %6lu %10.1f\n", i + 1, c->ac.node, c->ac.proc, c->ac.iter, c->ac.ncfg,
                c->ac.run_total, m->now - c->heard);
    }
    if (!m->napps) fprintf(out, "(no AppCast yet)\n");
    if (m->bad) fprintf(out, "%lu APPCAST postings did not parse\n", m->bad);
}

static void shutdown_mac(kelp_app *app, void *st)
{
    mac *m = st;
    (void)app;
    if (m->raw) tcsetattr(0, TCSANOW, &m->saved);
}

static const kelp_app_def def = {
    .name = "kelp-mac",
    .moos_name = "uMAC",
    .purpose = "AppCast monitor: the apps of a community with their warnings, or one app's cast, live.",
    .params = (const kelp_app_param_info[]){
        { "node", "all", "the community whose apps to ask (default all)", NULL },
        { "app", "all", "the app to ask (default all)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "APPCAST", "proc=pHostInfo!@#iter=48!@#node=alpha!@#...", "every app's cast" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "APPCAST_REQ", "node=all,app=all,duration=3,key=kelp-mac_1234,thresh=any", "every 2 s" },
        { NULL, NULL, NULL } },
    .notes = "Keys on a terminal: 1-9 show that app, n / p next / previous, l the list, h help, q quit.\n",
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
    .shutdown = shutdown_mac,
};

int main(int argc, char **argv)
{
    static mac m;
    return kelp_app_run(argc, argv, &def, &m);
}
