/* kelp-moos2sql's SQLite store (store.h). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sqlite3.h>
#include "store.h"

struct m2s_store {
    sqlite3 *db;
    sqlite3_stmt *ins[3];
    double period, began;       /* monotonic s; began < 0: no transaction open */
    unsigned long pending[3], rows[3];
    unsigned version;
};

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int fail(sqlite3 *db, const char *what, char *err, size_t cap)
{
    snprintf(err, cap, "%s: %s", what, db ? sqlite3_errmsg(db) : "out of memory");
    return -1;
}

static int exec(sqlite3 *db, const char *sql, const char *what, char *err, size_t cap)
{
    return sqlite3_exec(db, sql, NULL, NULL, NULL) == SQLITE_OK ? 0 : fail(db, what, err, cap);
}

static int user_version(sqlite3 *db, unsigned *out)
{
    sqlite3_stmt *st;
    if (sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &st, NULL) != SQLITE_OK) return -1;
    int rc = sqlite3_step(st) == SQLITE_ROW ? 0 : -1;
    if (rc == 0) *out = (unsigned)sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
    return rc;
}

/* apply the migrations not yet applied, each in its own transaction with its version bump */
static int migrate(m2s_store *s, char *err, size_t cap)
{
    if (user_version(s->db, &s->version) < 0) return fail(s->db, "reading user_version", err, cap);
    if (s->version > kelp_moos2sql_nmigrations) {
        snprintf(err, cap, "the database's schema version %u is newer than this program's (%u)", s->version,
                 kelp_moos2sql_nmigrations);
        return -1;
    }
    for (unsigned v = s->version; v < kelp_moos2sql_nmigrations; v++) {
        char bump[64];
        snprintf(bump, sizeof bump, "PRAGMA user_version = %u;", v + 1);
        if (exec(s->db, "BEGIN IMMEDIATE", "begin migration", err, cap) < 0) return -1;
        if (exec(s->db, kelp_moos2sql_migrations[v], "migration", err, cap) < 0 ||
            exec(s->db, bump, "migration version", err, cap) < 0) {
            sqlite3_exec(s->db, "ROLLBACK", NULL, NULL, NULL);
            return -1;
        }
        if (exec(s->db, "COMMIT", "commit migration", err, cap) < 0) return -1;
        s->version = v + 1;
    }
    return 0;
}

m2s_store *m2s_store_open(const char *path, double commit_period, char *err, size_t cap)
{
    static const char *const ins[3] = {
        "INSERT INTO status (time, name, community, var, type, mode, x, y, lat, lon, spd, hdg, depth, report)"
        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)",
        "INSERT INTO contact (time, name, community, var, count, value) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
        "INSERT INTO track (time, name, community, var, x, y, lat, lon, hdg, spd, depth, value)"
        " VALUES (?1, ?2, ?3, ?4, ?7, ?8, ?9, ?10, ?12, ?11, ?13, ?14)",
    };
    m2s_store *s = calloc(1, sizeof *s);
    if (!s) return fail(NULL, path, err, cap), NULL;
    s->period = commit_period;
    s->began = -1;
    if (sqlite3_open_v2(path, &s->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, NULL) != SQLITE_OK) {
        fail(s->db, path, err, cap);
        goto bad;
    }
    sqlite3_busy_timeout(s->db, 5000); /* a reader's checkpoint or another writer: wait */
    if (exec(s->db, "PRAGMA journal_mode=WAL", "WAL mode", err, cap) < 0 ||
        exec(s->db, "PRAGMA synchronous=NORMAL", "synchronous", err, cap) < 0 || migrate(s, err, cap) < 0)
        goto bad;
    for (int k = 0; k < 3; k++)
        if (sqlite3_prepare_v2(s->db, ins[k], -1, &s->ins[k], NULL) != SQLITE_OK) {
            fail(s->db, "preparing insert", err, cap);
            goto bad;
        }
    return s;
bad:
    m2s_store_close(s);
    return NULL;
}

static void bind_num(sqlite3_stmt *st, int i, bool have, double v)
{
    if (have && isfinite(v)) sqlite3_bind_double(st, i, v);
    else sqlite3_bind_null(st, i);
}

int m2s_store_put(m2s_store *s, const kelp_moos2sql_record *r, char *err, size_t cap)
{
    if (r->kind < KELP_M2S_STATUS || r->kind > KELP_M2S_TRACK) return 0;
    int k = (int)r->kind - 1;
    if (s->began < 0) {
        if (exec(s->db, "BEGIN IMMEDIATE", "begin", err, cap) < 0) return -1;
        s->began = mono();
    }
    sqlite3_stmt *st = s->ins[k];
    const kelp_nodereport *n = &r->nr;
    sqlite3_reset(st);
    sqlite3_clear_bindings(st);
    sqlite3_bind_double(st, 1, r->time);
    sqlite3_bind_text(st, 2, r->name, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 3, r->community, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 4, r->var, -1, SQLITE_STATIC);
    int vlen = r->value_len > INT_MAX ? INT_MAX : (int)r->value_len;
    if (r->kind == KELP_M2S_CONTACT) {
        sqlite3_bind_int64(st, 5, r->count);
        if (r->is_number) {
            char num[64];
            snprintf(num, sizeof num, "%.17g", r->dval);
            sqlite3_bind_text(st, 6, num, -1, SQLITE_TRANSIENT);
        } else {
            sqlite3_bind_text(st, 6, r->value, vlen, SQLITE_STATIC);
        }
    } else {
        if (r->kind == KELP_M2S_STATUS) {
            if (n->fields & KELP_NR_TYPE) sqlite3_bind_text(st, 5, n->type, -1, SQLITE_STATIC);
            if (n->fields & KELP_NR_MODE) sqlite3_bind_text(st, 6, n->mode, -1, SQLITE_STATIC);
        }
        bind_num(st, 7, n->fields & KELP_NR_X, n->x);
        bind_num(st, 8, n->fields & KELP_NR_Y, n->y);
        bind_num(st, 9, n->fields & KELP_NR_LAT, n->lat);
        bind_num(st, 10, n->fields & KELP_NR_LON, n->lon);
        bind_num(st, 11, n->fields & KELP_NR_SPD, n->spd);
        bind_num(st, 12, n->fields & KELP_NR_HDG, n->hdg);
        bind_num(st, 13, n->fields & KELP_NR_DEPTH, n->depth);
        sqlite3_bind_text(st, 14, r->value, vlen, SQLITE_STATIC);
    }
    if (sqlite3_step(st) != SQLITE_DONE) return fail(s->db, "insert", err, cap);
    s->pending[k]++;
    return m2s_store_tick(s, 0, err, cap);
}

int m2s_store_tick(m2s_store *s, int force, char *err, size_t cap)
{
    if (s->began < 0 || (!force && mono() - s->began < s->period)) return 0;
    if (exec(s->db, "COMMIT", "commit", err, cap) < 0) return -1;
    s->began = -1;
    for (int k = 0; k < 3; k++) s->rows[k] += s->pending[k], s->pending[k] = 0;
    return 0;
}

unsigned long m2s_store_rows(const m2s_store *s, int kind)
{
    return kind >= 1 && kind <= 3 ? s->rows[kind - 1] : 0;
}

unsigned m2s_store_version(const m2s_store *s)
{
    return s->version;
}

void m2s_store_close(m2s_store *s)
{
    if (!s) return;
    if (s->db) {
        char err[256];
        (void)m2s_store_tick(s, 1, err, sizeof err);
    }
    for (int k = 0; k < 3; k++) sqlite3_finalize(s->ins[k]);
    sqlite3_close(s->db);
    free(s);
}

int m2s_write_file(const char *path, const char *text, size_t len)
{
    char tmp[KELP_M2S_PATH + 8];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) return -1;
    int ok = fwrite(text, 1, len, f) == len;
    ok = (fclose(f) == 0) && ok;
    if (!ok || rename(tmp, path) != 0) {
        unlink(tmp);
        return -1;
    }
    return 0;
}

/* the link's href: the KML's name when both files share a directory, else its absolute path */
static void link_href(const char *kml, const char *link, char *out, size_t cap)
{
    const char *kb = strrchr(kml, '/'), *lb = strrchr(link, '/');
    size_t kd = kb ? (size_t)(kb - kml) : 0, ld = lb ? (size_t)(lb - link) : 0;
    if (kd == ld && strncmp(kml, link, kd) == 0) {
        snprintf(out, cap, "%s", kb ? kb + 1 : kml);
        return;
    }
    char abs[PATH_MAX];
    snprintf(out, cap, "%s", realpath(kml, abs) ? abs : kml);
}

int m2s_write_kml(kelp_moos2sql_fleet *f, const char *kml, const char *link, double refresh, char *err, size_t cap)
{
    size_t bufcap = 4096 + (size_t)KELP_M2S_MAX_VEHICLES * 1536;
    char *buf = malloc(bufcap);
    if (!buf) return snprintf(err, cap, "out of memory"), -1;
    int rc = 0;
    int n = kelp_moos2sql_kml(f, "kelp fleet", buf, bufcap);
    if (n < 0 || m2s_write_file(kml, buf, (size_t)n) < 0) {
        snprintf(err, cap, "cannot write %s", kml);
        rc = -1;
    } else if (link[0]) {
        char href[PATH_MAX];
        link_href(kml, link, href, sizeof href);
        n = kelp_moos2sql_kml_link("kelp fleet", href, refresh, buf, bufcap);
        if (n < 0 || m2s_write_file(link, buf, (size_t)n) < 0) {
            snprintf(err, cap, "cannot write %s", link);
            rc = -1;
        }
    }
    free(buf);
    return rc;
}
