/* kelp moos2sql core: classify postings, keep the fleet, write KML (include/kelp/moos2sql.h). */
#include <math.h>
#include <stdarg.h>
#include <string.h>
#include <kelp/kv.h>
#include <kelp/moos2sql.h>
#include <kelp/util.h>

static const char *const default_vars[3][10] = {
    { "NODE_REPORT", "NODE_REPORT_LOCAL", NULL },
    { "CONTACTS_LIST", "CONTACTS_ALERTED", "CONTACTS_UNALERTED", "CONTACTS_RETIRED", "CONTACTS_RECAP",
      "CONTACTS_COUNT", "CONTACT_CLOSEST", "CONTACT_CLOSEST_RANGE", "CONTACT_RANGES", NULL },
    { "STATUS_REPORT", "STATUS_SUMMARY", "STATUS_REPORT_IN", NULL },
};

const char *const kelp_moos2sql_migrations[] = {
    /* 1: the three tables and their (name, time) indexes */
    "CREATE TABLE status (id INTEGER PRIMARY KEY, time REAL NOT NULL, name TEXT NOT NULL, community TEXT NOT NULL,"
    " var TEXT NOT NULL, type TEXT, mode TEXT, x REAL, y REAL, lat REAL, lon REAL, spd REAL, hdg REAL, depth REAL,"
    " report TEXT NOT NULL);"
    "CREATE INDEX status_name_time ON status (name, time);"
    "CREATE TABLE contact (id INTEGER PRIMARY KEY, time REAL NOT NULL, name TEXT NOT NULL, community TEXT NOT NULL,"
    " var TEXT NOT NULL, count INTEGER, value TEXT NOT NULL);"
    "CREATE INDEX contact_name_time ON contact (name, time);"
    "CREATE TABLE track (id INTEGER PRIMARY KEY, time REAL NOT NULL, name TEXT NOT NULL, community TEXT NOT NULL,"
    " var TEXT NOT NULL, x REAL, y REAL, lat REAL, lon REAL, hdg REAL, spd REAL, depth REAL, value TEXT NOT NULL);"
    "CREATE INDEX track_name_time ON track (name, time);",
    /* 2: a time index per table (queries over a time window across the fleet) */
    "CREATE INDEX status_time ON status (time);"
    "CREATE INDEX contact_time ON contact (time);"
    "CREATE INDEX track_time ON track (time);",
};
const unsigned kelp_moos2sql_nmigrations = sizeof kelp_moos2sql_migrations / sizeof kelp_moos2sql_migrations[0];

static void copyz(char *dst, size_t cap, const char *s, size_t n)
{
    if (n >= cap) n = cap - 1;
    memcpy(dst, s, n);
    dst[n] = 0;
}

static int find_var(const kelp_moos2sql_cfg *c, unsigned k, const char *var, size_t n)
{
    for (unsigned i = 0; i < c->nvars[k]; i++)
        if (strlen(c->vars[k][i]) == n && memcmp(c->vars[k][i], var, n) == 0) return (int)i;
    return -1;
}

static void drop_var(kelp_moos2sql_cfg *c, unsigned k, unsigned i)
{
    memmove(c->vars[k][i], c->vars[k][i + 1], (size_t)(c->nvars[k] - i - 1) * sizeof c->vars[k][0]);
    c->nvars[k]--;
}

/* add var to kind k, removing it from the others */
static int add_var(kelp_moos2sql_cfg *c, unsigned k, const char *var, size_t n)
{
    if (n == 0) return 0;
    if (n >= KELP_MAX_NAME) return KELP_ERR_RANGE;
    for (unsigned j = 0; j < 3; j++) {
        int i = find_var(c, j, var, n);
        if (i >= 0 && j == k) return 0;
        if (i >= 0) drop_var(c, j, (unsigned)i);
    }
    if (c->nvars[k] >= KELP_M2S_MAX_VARS) return KELP_ERR_NOSPACE;
    copyz(c->vars[k][c->nvars[k]++], KELP_MAX_NAME, var, n);
    return 0;
}

void kelp_moos2sql_cfg_default(kelp_moos2sql_cfg *c)
{
    memset(c, 0, sizeof *c);
    for (unsigned k = 0; k < 3; k++)
        for (unsigned i = 0; default_vars[k][i]; i++)
            (void)add_var(c, k, default_vars[k][i], strlen(default_vars[k][i]));
    copyz(c->database, sizeof c->database, "moos2sql.db", 11);
    copyz(c->kml, sizeof c->kml, "fleet.kml", 9);
    copyz(c->kml_link, sizeof c->kml_link, "fleet_link.kml", 14);
    c->kml_period = 2;
    c->commit_period = 0.25;
}

static int set_path(char *dst, const char *val, kelp_diag *d)
{
    size_t n = strlen(val);
    if (n >= KELP_M2S_PATH) {
        return kelp_fail(d, KELP_ERR_RANGE, "path too long");
    }
    copyz(dst, KELP_M2S_PATH, val, n);
    return 1;
}

int kelp_moos2sql_config(kelp_moos2sql_cfg *c, const char *key, const char *val, kelp_diag *d)
{
    static const char *const kinds[3] = { "STATUS_VAR", "CONTACT_VAR", "TRACK_VAR" };
    if (kelp_util_strieq(key, "DATABASE")) {
        if (!val[0]) {
            return kelp_fail(d, KELP_ERR_ARG, "a database path is required");
        }
        return set_path(c->database, val, d);
    }
    if (kelp_util_strieq(key, "KML_FILE")) return set_path(c->kml, val, d);
    if (kelp_util_strieq(key, "KML_LINK_FILE")) return set_path(c->kml_link, val, d);
    if (kelp_util_strieq(key, "KML_PERIOD") || kelp_util_strieq(key, "COMMIT_PERIOD")) {
        bool kml = kelp_util_strieq(key, "KML_PERIOD");
        double dv;
        if (kelp_util_parse_finite(val, strlen(val), &dv) < 0 || !(dv > 0) || (!kml && dv > 0.5)) {
            return kelp_fail(d, KELP_ERR_PARSE, kml ? "a number of seconds > 0" : "a number of seconds in (0, 0.5]");
        }
        *(kml ? &c->kml_period : &c->commit_period) = dv;
        return 1;
    }
    for (unsigned k = 0; k < 3; k++) {
        if (!kelp_util_strieq(key, kinds[k])) continue;
        for (const char *p = val; *p;) {
            size_t n = strcspn(p, ",");
            const char *s = p;
            size_t m = n;
            while (m && (*s == ' ' || *s == '\t')) s++, m--;
            while (m && (s[m - 1] == ' ' || s[m - 1] == '\t')) m--;
            int rc = add_var(c, k, s, m);
            if (rc < 0) {
                return kelp_fail(d, rc, rc == KELP_ERR_RANGE ? "variable name too long" : "too many variables");
            }
            p += n + (p[n] == ',');
        }
        return 1;
    }
    return 0;
}

kelp_moos2sql_kind kelp_moos2sql_kind_of(const kelp_moos2sql_cfg *c, const char *var)
{
    size_t n = strlen(var);
    for (unsigned k = 0; k < 3; k++)
        if (find_var(c, k, var, n) >= 0) return (kelp_moos2sql_kind)(k + 1);
    return KELP_M2S_NONE;
}

/* items in a contact report: names or ranges split at ',', recap entries at '#', pairs "(a,b)" */
static long count_items(const char *s, size_t n)
{
    size_t i = 0;
    while (i < n && (s[i] == ' ' || s[i] == '\t')) i++;
    if (i == n) return 0;
    long items = 0;
    if (s[i] == '(') {
        for (; i < n; i++) items += s[i] == '(';
        return items;
    }
    char sep = memchr(s, '#', n) ? '#' : ',';
    items = 1;
    for (; i < n; i++) items += s[i] == sep;
    return items;
}

/* track: the fields of a key=value status message */
static int read_track(const char *s, kelp_moos2sql_record *out, kelp_diag *d)
{
    static const struct { const char *key; uint32_t bit; } keys[] = {
        { "nav_x", KELP_NR_X }, { "x", KELP_NR_X }, { "nav_y", KELP_NR_Y }, { "y", KELP_NR_Y },
        { "nav_lat", KELP_NR_LAT }, { "lat", KELP_NR_LAT }, { "nav_long", KELP_NR_LON }, { "nav_lon", KELP_NR_LON },
        { "lon", KELP_NR_LON }, { "long", KELP_NR_LON }, { "heading", KELP_NR_HDG }, { "hdg", KELP_NR_HDG },
        { "nav_heading", KELP_NR_HDG }, { "speed", KELP_NR_SPD }, { "spd", KELP_NR_SPD },
        { "nav_speed", KELP_NR_SPD }, { "depth", KELP_NR_DEPTH }, { "dep", KELP_NR_DEPTH },
        { "nav_depth", KELP_NR_DEPTH },
    };
    kelp_nodereport *r = &out->nr;
    size_t pos = 0, kl, vl;
    const char *k, *v;
    int rc;
    while ((rc = kelp_kv_next(s, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        if (!out->name[0] && (kelp_util_strieq_n(k, kl, "name") || kelp_util_strieq_n(k, kl, "vname") ||
                              kelp_util_strieq_n(k, kl, "node"))) {
            if (vl >= sizeof out->name) {
                return kelp_fail(d, KELP_ERR_RANGE, "vehicle name too long");
            }
            copyz(out->name, sizeof out->name, v, vl);
            continue;
        }
        for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
            if (!kelp_util_strieq_n(k, kl, keys[i].key)) continue;
            double dv;
            if ((r->fields & keys[i].bit) || kelp_util_parse_finite(v, vl, &dv) < 0) break; /* first wins; text ignored */
            double *dst = keys[i].bit == KELP_NR_X     ? &r->x
                          : keys[i].bit == KELP_NR_Y   ? &r->y
                          : keys[i].bit == KELP_NR_LAT ? &r->lat
                          : keys[i].bit == KELP_NR_LON ? &r->lon
                          : keys[i].bit == KELP_NR_HDG ? &r->hdg
                          : keys[i].bit == KELP_NR_SPD ? &r->spd
                                                        : &r->depth;
            *dst = dv;
            r->fields |= keys[i].bit;
            break;
        }
    }
    if (rc < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "not a key=value list");
    }
    return 0;
}

int kelp_moos2sql_classify(const kelp_moos2sql_cfg *c, const char *var, const char *community, double time, bool is_string,
                      const char *sval, size_t slen, double dval, kelp_moos2sql_record *out, kelp_diag *d)
{
    kelp_moos2sql_kind kind = kelp_moos2sql_kind_of(c, var);
    if (kind == KELP_M2S_NONE) return 0;
    memset(out, 0, sizeof *out);
    kelp_nodereport_init(&out->nr);
    out->kind = kind;
    out->var = var;
    out->community = community ? community : "";
    out->time = time;
    out->is_number = !is_string;
    out->dval = is_string ? 0 : dval;
    out->value = is_string ? sval : "";
    out->value_len = is_string ? slen : 0;
    if (is_string && (memchr(sval, 0, slen) || sval[slen] != 0)) {
        return kelp_fail(d, KELP_ERR_PARSE, "a NUL byte in the text, or the text not terminated at its length");
    }
    if (kind == KELP_M2S_CONTACT) {
        copyz(out->name, sizeof out->name, out->community, strlen(out->community));
        out->count = is_string ? count_items(sval, slen) : (isfinite(dval) && fabs(dval) < 1e15 ? (long)dval : 0);
        return 1;
    }
    if (!is_string) {
        return kelp_fail(d, KELP_ERR_PARSE, kind == KELP_M2S_STATUS ? "a node report must be a string" : "a status message must be a string");
    }
    if (kind == KELP_M2S_STATUS) {
        int rc = kelp_nodereport_parse(sval, slen, &out->nr, d);
        if (rc < 0) return rc;
        copyz(out->name, sizeof out->name, out->nr.name, strlen(out->nr.name));
        return 1;
    }
    int rc = read_track(sval, out, d);
    return rc < 0 ? rc : 1;
}

/* ------------------------------------------------------------------ the fleet */

void kelp_moos2sql_fleet_init(kelp_moos2sql_fleet *f)
{
    memset(f, 0, sizeof *f);
}

int kelp_moos2sql_fleet_update(kelp_moos2sql_fleet *f, const kelp_moos2sql_cfg *c, const kelp_moos2sql_record *r)
{
    if ((r->kind != KELP_M2S_STATUS && r->kind != KELP_M2S_TRACK) || !r->name[0]) return 0;
    const kelp_nodereport *n = &r->nr;
    double lat, lon;
    if ((n->fields & (KELP_NR_LAT | KELP_NR_LON)) == (KELP_NR_LAT | KELP_NR_LON)) {
        lat = n->lat;
        lon = n->lon;
    } else if ((n->fields & (KELP_NR_X | KELP_NR_Y)) == (KELP_NR_X | KELP_NR_Y) && c->have_datum) {
        if (kelp_geo_to_latlon(&c->datum, n->x, n->y, &lat, &lon) < 0) return 0;
    } else {
        return 0;
    }
    if (!isfinite(lat) || !isfinite(lon) || fabs(lat) > 90 || fabs(lon) > 180) return 0;
    unsigned i = 0;
    while (i < f->n && strcmp(f->v[i].name, r->name) != 0) i++;
    if (i == f->n) {
        if (f->n == KELP_M2S_MAX_VEHICLES) {
            f->dropped++;
            return 0;
        }
        /* keep name order: insert */
        i = 0;
        while (i < f->n && strcmp(f->v[i].name, r->name) < 0) i++;
        memmove(&f->v[i + 1], &f->v[i], (f->n - i) * sizeof f->v[0]);
        f->n++;
        memset(&f->v[i], 0, sizeof f->v[i]);
        copyz(f->v[i].name, sizeof f->v[i].name, r->name, strlen(r->name));
    }
    kelp_moos2sql_vehicle *v = &f->v[i];
    v->time = (n->fields & KELP_NR_TIME) ? n->time : r->time;
    v->lat = lat;
    v->lon = lon;
    v->hdg = (n->fields & KELP_NR_HDG) ? n->hdg : NAN;
    v->spd = (n->fields & KELP_NR_SPD) ? n->spd : NAN;
    v->depth = (n->fields & KELP_NR_DEPTH) ? n->depth : NAN;
    if (n->fields & KELP_NR_TYPE) copyz(v->type, sizeof v->type, n->type, strlen(n->type));
    if (n->fields & KELP_NR_MODE) copyz(v->mode, sizeof v->mode, n->mode, strlen(n->mode));
    v->reports++;
    f->changed = true;
    return 1;
}

/* ------------------------------------------------------------------ KML */

int kelp_moos2sql_xml_escape(char *buf, size_t cap, size_t *len, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        unsigned char ch = (unsigned char)s[i];
        const char *rep = ch == '&' ? "&amp;" : ch == '<' ? "&lt;" : ch == '>' ? "&gt;" : ch == '"' ? "&quot;"
                                                                            : ch == '\'' ? "&apos;" : NULL;
        if (!rep && ch < 0x20 && ch != '\t' && ch != '\n') continue;
        if (!rep && ch == 0x7f) continue;
        size_t m = rep ? strlen(rep) : 1;
        if (*len + m >= cap) return KELP_ERR_NOSPACE;
        if (rep) memcpy(buf + *len, rep, m);
        else buf[*len] = (char)ch;
        *len += m;
    }
    buf[*len] = 0;
    return 0;
}

/* a text being written; full once anything did not fit (then nothing more is added) */
typedef struct wbuf {
    char *buf;
    size_t cap, len;
    bool full;
} wbuf;

static void put(wbuf *w, const char *fmt, ...) KELP_PRINTF(2, 3);
static void put(wbuf *w, const char *fmt, ...)
{
    if (w->full) return;
    va_list ap;
    va_start(ap, fmt);
    int n = kelp_util_vsnprintf(w->buf + w->len, w->cap - w->len, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= w->cap - w->len) w->full = true;
    else w->len += (size_t)n;
}

static void put_text(wbuf *w, const char *s)
{
    if (!w->full && kelp_moos2sql_xml_escape(w->buf, w->cap, &w->len, s, strlen(s)) < 0) w->full = true;
}

/* ISO 8601 UTC of a time in seconds since 1970 (MOOS time) */
static void iso_time(double t, char *out, size_t cap)
{
    if (!isfinite(t) || t < 0 || t > 253402300799.0) t = 0;
    int64_t s = (int64_t)floor(t);
    int64_t days = kelp_util_floor_div(s, 86400), sec = s - days * 86400;
    int64_t y;
    unsigned mo, d;
    kelp_util_civil_from_days(days, &y, &mo, &d);
    (void)kelp_util_snprintf(out, cap, "%04lld-%02u-%02uT%02u:%02u:%02uZ", (long long)y, mo, d, (unsigned)(sec / 3600),
                        (unsigned)(sec / 60 % 60), (unsigned)(sec % 60));
}

static wbuf start(char *buf, size_t cap, const char *title, const char *elem)
{
    wbuf w = { buf, cap, 0, cap == 0 };
    if (cap) buf[0] = 0;
    put(&w, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n<%s>\n<name>",
        elem);
    put_text(&w, title ? title : "kelp fleet");
    put(&w, "</name>\n");
    return w;
}

int kelp_moos2sql_kml(kelp_moos2sql_fleet *f, const char *title, char *buf, size_t cap)
{
    wbuf w = start(buf, cap, title, "Document");
    for (unsigned i = 0; i < f->n; i++) {
        const kelp_moos2sql_vehicle *v = &f->v[i];
        char when[40];
        iso_time(v->time, when, sizeof when);
        put(&w, "<Placemark id=\"v%u\">\n<name>", i);
        put_text(&w, v->name);
        put(&w, "</name>\n<description>");
        if (v->type[0]) put(&w, "type "), put_text(&w, v->type), put(&w, "; ");
        if (v->mode[0]) put(&w, "mode "), put_text(&w, v->mode), put(&w, "; ");
        if (isfinite(v->spd)) put(&w, "speed %.2f m/s; ", v->spd);
        if (isfinite(v->depth)) put(&w, "depth %.2f m; ", v->depth);
        put(&w, "time %.2f; %lu reports</description>\n<TimeStamp><when>%s</when></TimeStamp>\n", v->time, v->reports,
            when);
        if (isfinite(v->hdg)) put(&w, "<Style><IconStyle><heading>%.2f</heading></IconStyle></Style>\n", v->hdg);
        put(&w, "<Point><coordinates>%.7f,%.7f,0</coordinates></Point>\n</Placemark>\n", v->lon, v->lat);
    }
    put(&w, "</Document>\n</kml>\n");
    if (w.full) return KELP_ERR_NOSPACE;
    f->changed = false;
    return (int)w.len;
}

int kelp_moos2sql_kml_link(const char *title, const char *href, double refresh, char *buf, size_t cap)
{
    if (!isfinite(refresh) || refresh <= 0) refresh = 2;
    wbuf w = start(buf, cap, title, "NetworkLink");
    put(&w, "<refreshVisibility>0</refreshVisibility>\n<Link>\n<href>");
    put_text(&w, href);
    put(&w, "</href>\n<refreshMode>onInterval</refreshMode>\n<refreshInterval>%g</refreshInterval>\n</Link>\n"
            "</NetworkLink>\n</kml>\n", refresh);
    return w.full ? KELP_ERR_NOSPACE : (int)w.len;
}
