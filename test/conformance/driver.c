/* conform-driver: the scripted MOOS client of the recorded MOOS-IvP 24.8 runs, on kelp's bus.
 *
 *   conform-driver SCENARIO.scn MISSION.moos OUT.jsonl [OUT.meta.json]
 *
 * It joins the mission's community as the client "driver", waits `settle` real seconds (t0 is
 * the MOOS time then: join time + settle x warp, later on a loaded host until every app of the
 * mission's ANTLER block has posted, see main), plays the .scn script (at, every, appcast, vehicle; `@MOOSTIME` expanded) and records
 * every notification it receives as one JSON row, in the layout of the recordings (README of
 * ../shared/conformance/moos-ivp-24.8): t (the poster's time - t0), trx (our receive time -
 * t0), var, type, val, src, aux, community. Its own posts come back over the bus as they do
 * through a MOOSDB (src "driver"); a post the MOOSDB's type rule refuses comes back as
 * nothing. Rows are recorded from the moment it joins (the apps' start-up, negative t): the
 * recordings hold what their driver saw before t0 too, less what it dropped (their README), so
 * the comparator, not the recorder, decides what before t0 counts. The meta file counts every
 * notification received and every post made (a vehicle with nav=true makes six per update).
 * A bad script line is a file:line error and exit status 2. */
#include <fnmatch.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/lcmbus.h>
#include <kelp/util.h>
#include <kelp/edge/mission.h>

#define MAX_EVENTS 512
#define MAX_VEHICLES 32
#define MAX_PATTERNS 32
#define MAX_PTS 16
#define MAX_COUNTED 512

typedef struct event {
    double t0, t1, dt; /* dt 0: once at t0 */
    double next;
    int kind;          /* 's' string, 'd' double, 'a' appcast */
    char var[KELP_MAX_NAME];
    char val[KELP_MAX_SVAL + 1];
} event;

typedef struct vehicle {
    char name[KELP_MAX_NAME], var[KELP_MAX_NAME], type[32], group[32], mode[32];
    double x, y, hdg, spd, rate, t0, t1, len, depth;
    double px[MAX_PTS], py[MAX_PTS];
    int npts;
    bool nav, report, shortfmt;
    double next;
} vehicle;

typedef struct scenario {
    double warp, duration, settle;
    event ev[MAX_EVENTS];
    int nev;
    vehicle veh[MAX_VEHICLES];
    int nveh;
    char exclude[MAX_PATTERNS][KELP_MAX_NAME];
    int nexclude;
    char include[MAX_PATTERNS][KELP_MAX_NAME];
    int ninclude;
    char sub[MAX_PATTERNS][KELP_MAX_NAME];
    int nsub;
} scenario;

typedef struct recorder {
    FILE *out;
    const scenario *s;
    double t0, warp;
    bool started;
    unsigned long rows;
    char names[MAX_COUNTED][KELP_MAX_NAME];
    unsigned long counts[MAX_COUNTED];
    int nnames;
    char apps[MAX_PATTERNS][KELP_MAX_NAME]; /* the mission's launched apps (ANTLER Run lines) */
    bool heard[MAX_PATTERNS];               /* each has posted something: it is up */
    int napps;
    char phase_app[KELP_MAX_NAME]; /* KELP_CONF_PHASE: t0 at this app's recorded phase */
    double phase_period, phase, phase_up; /* its iteration period, phase and uptime at t0 */
    double phase_seen, phase_start;       /* its last status post's time (else -1), its start */
} recorder;

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* MOOS time as kelp's apps read it: wall clock times MOOSTimeWarp (src/app/app.c) */
static double g_epoch, g_warp = 1;
static double moos_now(void)
{
    return g_epoch + (wall() - g_epoch) * g_warp;
}

static int bad(const char *file, int line, const char *what)
{
    fprintf(stderr, "%s:%d: %s\n", file, line, what);
    return -1;
}

static int num(const char *s, double *out)
{
    return kelp_util_parse_double(s, strlen(s), out) < 0 ? -1 : 0;
}

/* a vehicle's keys: name=..,x=..,pts=x1,y1:x2,y2,... (pts holds commas, so it runs to the next
 * key=) */
static int parse_vehicle(char *spec, vehicle *v)
{
    memset(v, 0, sizeof *v);
    v->rate = 1;
    v->t1 = INFINITY;
    v->len = 4;
    v->report = true;
    snprintf(v->var, sizeof v->var, "NODE_REPORT");
    snprintf(v->type, sizeof v->type, "kayak");
    char *p = spec;
    while (*p) {
        char *eq = strchr(p, '=');
        if (!eq) return -1;
        *eq = 0;
        char *key = p, *val = eq + 1, *end = val;
        /* the value ends at the comma before the next "word=" */
        for (;;) {
            char *c = strchr(end, ',');
            if (!c) { end = val + strlen(val); break; }
            char *q = c + 1;
            while (*q && *q != '=' && *q != ',') q++;
            if (*q == '=') { end = c; break; }
            end = c + 1;
        }
        char save = *end;
        *end = 0;
        double d = 0;
        bool isnum = num(val, &d) == 0;
        if (strcmp(key, "name") == 0) snprintf(v->name, sizeof v->name, "%s", val);
        else if (strcmp(key, "var") == 0) snprintf(v->var, sizeof v->var, "%s", val);
        else if (strcmp(key, "type") == 0) snprintf(v->type, sizeof v->type, "%s", val);
        else if (strcmp(key, "group") == 0) snprintf(v->group, sizeof v->group, "%s", val);
        else if (strcmp(key, "mode") == 0) snprintf(v->mode, sizeof v->mode, "%s", val);
        else if (strcmp(key, "nav") == 0) v->nav = strcmp(val, "true") == 0;
        else if (strcmp(key, "report") == 0) v->report = strcmp(val, "false") != 0;
        else if (strcmp(key, "fmt") == 0) v->shortfmt = strcmp(val, "short") == 0;
        else if (strcmp(key, "pts") == 0) {
            char *tok = val;
            while (tok && *tok) {
                if (v->npts == MAX_PTS) return -1;
                char *colon = strchr(tok, ':');
                if (colon) *colon = 0;
                if (sscanf(tok, "%lf,%lf", &v->px[v->npts], &v->py[v->npts]) != 2) return -1;
                v->npts++;
                tok = colon ? colon + 1 : NULL;
            }
        } else if (!isnum) return -1;
        else if (strcmp(key, "x") == 0) v->x = d;
        else if (strcmp(key, "y") == 0) v->y = d;
        else if (strcmp(key, "hdg") == 0) v->hdg = d;
        else if (strcmp(key, "spd") == 0) v->spd = d;
        else if (strcmp(key, "rate") == 0) v->rate = d;
        else if (strcmp(key, "t0") == 0) v->t0 = d;
        else if (strcmp(key, "t1") == 0) v->t1 = d;
        else if (strcmp(key, "len") == 0) v->len = d;
        else if (strcmp(key, "depth") == 0) v->depth = d;
        else return -1;
        if (!save) break;
        p = end + 1;
    }
    if (!v->name[0] || !(v->rate > 0)) return -1;
    v->next = v->t0;
    return 0;
}

static int parse_scn(const char *path, scenario *s)
{
    FILE *f = fopen(path, "r");
    if (!f) return bad(path, 0, "cannot open");
    char line[KELP_MAX_SVAL + 256];
    int ln = 0, rc = 0;
    s->warp = 1;
    while (rc == 0 && fgets(line, sizeof line, f)) {
        ln++;
        line[strcspn(line, "\r\n")] = 0;
        char *p = line;
        while (*p == ' ' || *p == '\t') p++;
        if (!*p || *p == '#') continue;
        char word[32], a[64], b[64], c[64], kind[8], var[KELP_MAX_NAME];
        int used = 0;
        double d1, d2, d3;
        if (sscanf(p, "%31s%n", word, &used) != 1) continue;
        char *rest = p + used;
        while (*rest == ' ' || *rest == '\t') rest++;
        if (strcmp(word, "warp") == 0 || strcmp(word, "duration") == 0 || strcmp(word, "settle") == 0) {
            if (num(rest, &d1) < 0) rc = bad(path, ln, "expected a number");
            else if (word[0] == 'w') s->warp = d1;
            else if (word[0] == 'd') s->duration = d1;
            else s->settle = d1;
        } else if (strcmp(word, "exclude") == 0 || strcmp(word, "include_only") == 0 || strcmp(word, "sub") == 0) {
            int *n = word[0] == 'e' ? &s->nexclude : word[0] == 'i' ? &s->ninclude : &s->nsub;
            char(*arr)[KELP_MAX_NAME] = word[0] == 'e' ? s->exclude : word[0] == 'i' ? s->include : s->sub;
            if (*n == MAX_PATTERNS || strlen(rest) >= KELP_MAX_NAME || !*rest) rc = bad(path, ln, "bad pattern");
            else snprintf(arr[(*n)++], KELP_MAX_NAME, "%s", rest);
        } else if (strcmp(word, "vehicle") == 0) {
            if (s->nveh == MAX_VEHICLES || parse_vehicle(rest, &s->veh[s->nveh]) < 0) rc = bad(path, ln, "bad vehicle");
            else s->nveh++;
        } else if (strcmp(word, "at") == 0 || strcmp(word, "every") == 0 || strcmp(word, "appcast") == 0) {
            if (s->nev == MAX_EVENTS) { rc = bad(path, ln, "too many events"); break; }
            event *e = &s->ev[s->nev];
            memset(e, 0, sizeof *e);
            int n2 = 0;
            if (word[0] == 'a' && word[1] == 'p') {
                int k = sscanf(rest, "%63s %63s", a, b);
                if (k < 1 || num(a, &e->t0) < 0) { rc = bad(path, ln, "appcast T [APP]"); break; }
                e->kind = 'a';
                snprintf(e->var, sizeof e->var, "APPCAST_REQ");
                snprintf(e->val, sizeof e->val, "node=all,app=%s,duration=1,key=driver,thresh=any", k == 2 ? b : "all");
            } else {
                if (word[0] == 'a') {
                    if (sscanf(rest, "%63s %7s %63s %n", a, kind, var, &n2) < 3 || num(a, &d1) < 0) {
                        rc = bad(path, ln, "at T str|dbl VAR VALUE");
                        break;
                    }
                    e->t0 = d1;
                } else {
                    if (sscanf(rest, "%63s %63s %63s %7s %63s %n", a, b, c, kind, var, &n2) < 5 || num(a, &d1) < 0 ||
                        num(b, &d2) < 0 || num(c, &d3) < 0 || !(d3 > 0)) {
                        rc = bad(path, ln, "every T0 T1 DT str|dbl VAR VALUE");
                        break;
                    }
                    e->t0 = d1, e->t1 = d2, e->dt = d3;
                }
                const char *val = rest + n2;
                if (strlen(var) >= sizeof e->var || strlen(val) >= sizeof e->val) { rc = bad(path, ln, "too long"); break; }
                e->kind = strcmp(kind, "str") == 0 ? 's' : strcmp(kind, "dbl") == 0 ? 'd' : 0;
                if (!e->kind) { rc = bad(path, ln, "type is str or dbl"); break; }
                snprintf(e->var, sizeof e->var, "%s", var);
                snprintf(e->val, sizeof e->val, "%s", val);
                size_t l = strlen(e->val);
                while (l && (e->val[l - 1] == ' ' || e->val[l - 1] == '\t')) e->val[--l] = 0;
                if (e->kind == 'd' && num(e->val, &d1) < 0) { rc = bad(path, ln, "dbl value is not a number"); break; }
            }
            e->next = e->t0;
            s->nev++;
        } else {
            rc = bad(path, ln, "unknown directive");
        }
    }
    fclose(f);
    return rc;
}

/* s[0..n) as a JSON string (kelp_util_json_quote: plain ASCII, whatever the bytes) */
static void json_str(FILE *f, const char *s, size_t n)
{
    static char buf[6 * KELP_MAX_SVAL + 3];
    size_t need = kelp_util_json_quote(buf, sizeof buf, s, n);
    fwrite(buf, 1, need < sizeof buf ? need : sizeof buf - 1, f);
}

static bool recorded(const scenario *s, const char *name)
{
    for (int i = 0; i < s->nexclude; i++)
        if (fnmatch(s->exclude[i], name, 0) == 0) return false;
    if (s->ninclude == 0) return true;
    for (int i = 0; i < s->ninclude; i++)
        if (fnmatch(s->include[i], name, 0) == 0) return true;
    return false;
}

static void on_var(const kelp_var *v, void *user)
{
    recorder *r = user;
    for (int i = 0; i < r->napps; i++)
        if (strcmp(r->apps[i], v->source) == 0) r->heard[i] = true;
    size_t vl = strlen(v->name);
    if (r->phase_app[0] && strcmp(v->source, r->phase_app) == 0 && vl > 7 && strcmp(v->name + vl - 7, "_STATUS") == 0 &&
        v->kind == KELP_VAR_STRING) {
        const char *u = strstr(v->sval, "Uptime=");
        double up = 0;
        if (u && kelp_util_parse_double(u + 7, strcspn(u + 7, ","), &up) == 0) {
            r->phase_seen = v->time;
            r->phase_start = v->time - up;
        }
    }
    if (!r->started || !recorded(r->s, v->name)) return;
    /* absolute times here: t0 is final only once every app is up (rebase() makes them relative) */
    fprintf(r->out, "{\"t\":%.4f,\"trx\":%.4f,\"var\":", v->time, moos_now());
    json_str(r->out, v->name, strlen(v->name));
    if (v->kind == KELP_VAR_DOUBLE) fprintf(r->out, ",\"type\":\"double\",\"val\":%.17g", v->dval);
    else {
        fprintf(r->out, ",\"type\":\"%s\",\"val\":", v->kind == KELP_VAR_STRING ? "string" : "binary");
        json_str(r->out, v->sval, v->slen);
    }
    fputs(",\"src\":", r->out);
    json_str(r->out, v->source, strlen(v->source));
    fputs(",\"aux\":", r->out);
    json_str(r->out, v->source_aux, strlen(v->source_aux));
    fputs(",\"community\":", r->out);
    json_str(r->out, v->community, strlen(v->community));
    fputs("}\n", r->out);
    r->rows++;
    int i = 0;
    while (i < r->nnames && strcmp(r->names[i], v->name) != 0) i++;
    if (i == r->nnames && r->nnames < MAX_COUNTED) snprintf(r->names[r->nnames++], KELP_MAX_NAME, "%s", v->name);
    if (i < MAX_COUNTED) r->counts[i]++;
}

/* the apps the mission launches: "Run = prog [@ config] [~ name]" of ProcessConfig = ANTLER,
 * less the MOOSDB (kelp has none) */
static void read_apps(const kelp_mission *m, recorder *r)
{
    int b = kelp_mission_block(m, "ProcessConfig", "ANTLER");
    if (b < 0) return;
    for (int k = kelp_mission_next(m, b, -1, "Run"); k >= 0 && r->napps < MAX_PATTERNS;
         k = kelp_mission_next(m, b, k, "Run")) {
        char line[256], name[KELP_MAX_NAME];
        if (kelp_mission_copy(&m->nodes[k], line, sizeof line) < 0) continue;
        const char *tilde = strchr(line, '~');
        const char *from = tilde ? tilde + 1 : line;
        if (sscanf(from, " %63[^ @~\t]", name) != 1 || strcmp(name, "MOOSDB") == 0) continue;
        snprintf(r->apps[r->napps++], KELP_MAX_NAME, "%s", name);
    }
}

static int apps_up(const recorder *r)
{
    int n = 0;
    for (int i = 0; i < r->napps; i++) n += r->heard[i];
    return n;
}

/* the rows were written with absolute times: rewrite them relative to t0 */
static int rebase(const char *tmp, const char *out, double t0)
{
    FILE *in = fopen(tmp, "r"), *o = fopen(out, "w");
    if (!in || !o) {
        if (in) fclose(in);
        if (o) fclose(o);
        return bad(in ? out : tmp, 0, "cannot open");
    }
    static char line[8 * KELP_MAX_SVAL + 512];
    int rc = 0;
    while (fgets(line, sizeof line, in)) {
        double t, trx;
        int used = 0;
        if (sscanf(line, "{\"t\":%lf,\"trx\":%lf%n", &t, &trx, &used) != 2 || used == 0) { rc = -1; break; }
        fprintf(o, "{\"t\":%.4f,\"trx\":%.4f%s", t - t0, trx - t0, line + used);
    }
    fclose(in);
    if (fclose(o) != 0) rc = -1;
    remove(tmp);
    return rc < 0 ? bad(out, 0, "cannot rewrite the rows") : 0;
}

/* a number as the vehicle reports write it: two decimals, trailing zeros and dot removed */
static const char *n2(char *buf, double v)
{
    if (kelp_util_fmt_fixed(buf, 32, v, 2, true) < 0) snprintf(buf, 32, "0");
    return buf;
}

static void vehicle_at(const vehicle *v, double t, double *x, double *y, double *hdg, double *spd)
{
    double dt = t - v->t0;
    if (v->npts < 2) {
        double h = v->hdg * M_PI / 180.0;
        *x = v->x + sin(h) * v->spd * dt;
        *y = v->y + cos(h) * v->spd * dt;
        *hdg = v->hdg, *spd = v->spd;
        return;
    }
    double go = v->spd * dt;
    for (int i = 0; i + 1 < v->npts; i++) {
        double dx = v->px[i + 1] - v->px[i], dy = v->py[i + 1] - v->py[i], l = hypot(dx, dy);
        double h = atan2(dx, dy) * 180.0 / M_PI;
        if (h < 0) h += 360.0;
        if (go < l || i + 2 == v->npts) { /* on a vertex: the next leg, as recorded */
            double f = l > 0 ? (go < l ? go : l) / l : 0;
            *x = v->px[i] + dx * f, *y = v->py[i] + dy * f, *hdg = h;
            *spd = go < l ? v->spd : 0;
            return;
        }
        go -= l;
    }
}

/* one update of a vehicle; adds the notifications made to *posts */
static int post_vehicle(kelp_bus *bus, const vehicle *v, double t, double sched, double now, unsigned long *posts)
{
    double x = 0, y = 0, h = 0, sp = 0;
    vehicle_at(v, t, &x, &y, &h, &sp);
    int rc = 0;
    if (v->nav) {
        rc |= kelp_bus_notify_double(bus, "NAV_X", x, now);
        rc |= kelp_bus_notify_double(bus, "NAV_Y", y, now);
        rc |= kelp_bus_notify_double(bus, "NAV_HEADING", h, now);
        rc |= kelp_bus_notify_double(bus, "NAV_SPEED", sp, now);
        rc |= kelp_bus_notify_double(bus, "NAV_DEPTH", v->depth, now);
        *posts += 5;
    }
    if (!v->report) return rc;
    (*posts)++;
    char b[6][32], rep[512];
    int o = snprintf(rep, sizeof rep, "NAME=%s,X=%s,Y=%s,SPD=%s,HDG=%s,DEP=%s", v->name, n2(b[0], x), n2(b[1], y),
                     n2(b[2], sp), n2(b[3], h), n2(b[4], v->depth));
    if (!v->shortfmt) {
        o += snprintf(rep + o, sizeof rep - (size_t)o, ",TYPE=%s", v->type);
        if (v->group[0]) o += snprintf(rep + o, sizeof rep - (size_t)o, ",GROUP=%s", v->group);
        if (v->mode[0]) o += snprintf(rep + o, sizeof rep - (size_t)o, ",MODE=%s", v->mode);
        o += snprintf(rep + o, sizeof rep - (size_t)o, ",LENGTH=%s", n2(b[5], v->len));
    }
    /* TIME: the scheduled MOOS time. The recordings' driver posted within 0.5 ms of its
     * schedule; a loaded host's lateness stamped in would move the apps' speeds (pathcheck's
     * avg_spd from two TIMEs 0.25 s apart) by what the rig, not the app, did */
    snprintf(rep + o, sizeof rep - (size_t)o, ",TIME=%.3f", sched);
    return rc | kelp_bus_notify_string(bus, v->var, rep, now);
}

/* the value with every @MOOSTIME replaced by the MOOS time (%.3f) */
static void expand(const char *in, char *out, size_t cap, double now)
{
    size_t o = 0;
    while (*in && o + 1 < cap) {
        if (strncmp(in, "@MOOSTIME", 9) == 0) {
            int n = snprintf(out + o, cap - o, "%.3f", now);
            if (n > 0) o += (size_t)n < cap - o ? (size_t)n : cap - o - 1;
            in += 9;
        } else {
            out[o++] = *in++;
        }
    }
    out[o] = 0;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: conform-driver SCENARIO.scn MISSION.moos OUT.jsonl [OUT.meta.json]\n");
        return 2;
    }
    static scenario s;
    if (parse_scn(argv[1], &s) < 0) return 2;
    static kelp_mission_file mf;
    if (kelp_mission_load(&mf, argv[2]) < 0) {
        fprintf(stderr, "%s\n", mf.error);
        return 2;
    }
    char community[KELP_MAX_NAME] = "kelp", url[512];
    int gi = kelp_mission_next(&mf.m, -1, -1, "Community");
    if (gi >= 0 && kelp_mission_copy(&mf.m.nodes[gi], community, sizeof community) < 0) return 2;
    const char *env_url = getenv("KELP_LCM_URL");
    if (env_url) snprintf(url, sizeof url, "%s", env_url);
    else if (kelp_lcmbus_mission_url(&mf.m, url, sizeof url, &gi) < 0) return bad(argv[2], gi, "bad LCM_URL or ServerPort"), 2;
    const char *ep = getenv("KELP_WARP_EPOCH");
    if (ep && kelp_util_parse_double(ep, strlen(ep), &g_epoch) < 0) g_epoch = 0;
    g_warp = s.warp > 0 ? s.warp : 1;
    static recorder r;
    r.s = &s;
    read_apps(&mf.m, &r);
    r.t0 = moos_now() + s.settle * g_warp;
    r.started = true;
    r.phase_seen = -1;
    const char *ph = getenv("KELP_CONF_PHASE");
    if (ph && sscanf(ph, "%63s %lf %lf %lf", r.phase_app, &r.phase_period, &r.phase, &r.phase_up) != 4)
        r.phase_app[0] = 0;
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s.abs", argv[3]);
    r.out = fopen(tmp, "w");
    if (!r.out) return bad(tmp, 0, "cannot write"), 2;
    kelp_diag err = {0};
    kelp_lcmbus *lb = kelp_lcmbus_open(url, "driver", community, on_var, &r, &err);
    if (!lb) {
        fprintf(stderr, "conform-driver: %s\n", kelp_diag_text(&err));
        return 1;
    }
    kelp_bus *bus = kelp_lcmbus_bus(lb);
    if (s.nsub == 0) snprintf(s.sub[s.nsub++], KELP_MAX_NAME, "*");
    for (int i = 0; i < s.nsub; i++)
        if (kelp_bus_register(bus, s.sub[i], 0, moos_now()) < 0) return bad(argv[1], 0, "cannot register"), 1;
    /* joined: tell the runner (it starts the apps only then, so their start-up posts are heard
     * on a loaded host too, as the recordings' driver heard them) */
    const char *jf = getenv("KELP_CONF_JOINED");
    if (jf && *jf) {
        FILE *j = fopen(jf, "w");
        if (j) fclose(j);
    }
    /* settle: `settle` real seconds from joining, as recorded. On a loaded host an app may not
     * be up by then (the recordings' apps were started before their driver): t0 then waits
     * until every launched app has posted, plus one second for its first iterations, at most
     * READY_MAX_S. Wake in time for t0, the vehicles' first reports are stamped with it. */
    const double READY_MAX_S = 30;
    double joined = wall();
    bool all_up = r.napps == 0;
    for (double left; (left = (r.t0 - moos_now()) / g_warp) > 0 || !all_up;) {
        if (!all_up && apps_up(&r) == r.napps) {
            all_up = true;
            double ready_t0 = moos_now() + 1.0 * g_warp;
            if (ready_t0 > r.t0) r.t0 = ready_t0;
            continue;
        }
        if (!all_up && wall() - joined > READY_MAX_S) {
            fprintf(stderr, "conform-driver: %d of %d apps heard after %.0f s; starting\n", apps_up(&r), r.napps,
                    READY_MAX_S);
            all_up = true;
            continue;
        }
        int ms = left < 0.02 && left > 0 ? (int)(left * 1000.0) : 20;
        KELP_IGNORE(kelp_lcmbus_handle(lb, ms, moos_now()));
    }
    /* phase: t0 such that the app's iterations fall where the recorded app's did (a report's
     * arrival before or after an iteration replays as recorded) and, of those times, the one
     * nearest the app's recorded uptime at t0 (what counts from its start), not yet past. The
     * app's status is posted at an iteration: its time fixes kelp's app's phase. */
    if (r.phase_app[0] && r.phase_seen > 0 && r.phase_period > 0) {
        double base = r.phase_seen - r.phase, want = r.phase_start + r.phase_up;
        double soon = moos_now() + 0.05 * g_warp;
        double k = floor((want - base) / r.phase_period + 0.5);
        r.t0 = base + k * r.phase_period;
        while (r.t0 < soon) r.t0 += r.phase_period;
        fprintf(stderr, "conform-driver: t0 at %s's recorded phase %.3f of %.3f s, up %.2f s (recorded %.2f)\n",
                r.phase_app, r.phase, r.phase_period, r.t0 - r.phase_start, r.phase_up);
    }
    fprintf(stderr, "conform-driver: %d apps up, t0 %.2f s after joining\n", r.napps, wall() - joined);
    unsigned long posts = 0;
    for (;;) {
        double t = moos_now() - r.t0;
        if (t >= s.duration) break;
        double next = s.duration;
        for (int i = 0; i < s.nev; i++) {
            event *e = &s.ev[i];
            while (e->next <= t && e->next >= 0) {
                double now = moos_now();
                char val[KELP_MAX_SVAL + 1];
                expand(e->val, val, sizeof val, now);
                int rc;
                if (e->kind == 'd') {
                    double d = 0;
                    KELP_IGNORE(num(val, &d));
                    rc = kelp_bus_notify_double(bus, e->var, d, now);
                } else {
                    rc = kelp_bus_notify_string(bus, e->var, val, now);
                }
                if (rc < 0) fprintf(stderr, "conform-driver: post %s: %s\n", e->var, kelp_err_str(rc));
                posts++;
                e->next = e->dt > 0 && e->next + e->dt < e->t1 ? e->next + e->dt : -1;
            }
            if (e->next >= 0 && e->next < next) next = e->next;
        }
        for (int i = 0; i < s.nveh; i++) {
            vehicle *v = &s.veh[i];
            while (v->next <= t && v->next < v->t1) {
                double now = moos_now();
                if (post_vehicle(bus, v, v->next, now, now, &posts) < 0) fprintf(stderr, "conform-driver: post failed\n");
                v->next += 1.0 / v->rate;
            }
            if (v->next < v->t1 && v->next < next) next = v->next;
        }
        double wait_real = (next - (moos_now() - r.t0)) / g_warp;
        int ms = wait_real > 0 ? (int)(wait_real * 1000.0) : 0;
        if (ms > 50) ms = 50;
        KELP_IGNORE(kelp_lcmbus_handle(lb, ms, moos_now()));
    }
    /* late echoes of the last posts */
    double until = wall() + 0.2;
    while (wall() < until) KELP_IGNORE(kelp_lcmbus_handle(lb, 20, moos_now()));
    r.started = false;
    fclose(r.out);
    if (rebase(tmp, argv[3], r.t0) < 0) return 2;
    if (argc > 4) {
        FILE *m = fopen(argv[4], "w");
        if (!m) return bad(argv[4], 0, "cannot write"), 2;
        fputs("{\"scenario\":", m);
        json_str(m, argv[1], strlen(argv[1]));
        fprintf(m, ",\"t0_moostime\":%.4f,\"warp\":%g,\"duration\":%g,\"rows\":%lu,\"driver_posts\":%lu,"
                   "\"type_refused\":%llu,\"counts\":{",
                r.t0, g_warp, s.duration, r.rows, posts,
                (unsigned long long)kelp_bus_get_stats(bus)->type_refused);
        for (int i = 0; i < r.nnames; i++) {
            if (i) fputc(',', m);
            json_str(m, r.names[i], strlen(r.names[i]));
            fprintf(m, ":%lu", r.counts[i]);
        }
        fprintf(m, "}}\n");
        fclose(m);
    }
    kelp_lcmbus_close(lb);
    kelp_mission_free(&mf);
    return 0;
}
