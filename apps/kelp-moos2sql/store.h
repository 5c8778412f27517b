/* kelp-moos2sql's SQLite store and file writers (edge; only this program links SQLite). */
#ifndef KELP_MOOS2SQL_STORE_H
#define KELP_MOOS2SQL_STORE_H
#include <stddef.h>
#include <kelp/moos2sql.h>

typedef struct m2s_store m2s_store;

/** Open (create) the database: WAL journal, synchronous=NORMAL (a committed transaction
 *  survives the process being killed), migrations applied up to kelp_moos2sql_nmigrations.
 *  commit_period: seconds a transaction stays open at most. NULL with err on failure. */
m2s_store *m2s_store_open(const char *path, double commit_period, char *err, size_t cap);
/** Insert one record (inside the open transaction, begun if none). 0 or -1 with err. */
int m2s_store_put(m2s_store *s, const kelp_moos2sql_record *r, char *err, size_t cap);
/** Commit the open transaction when it is commit_period old (force: now). 0 or -1. */
int m2s_store_tick(m2s_store *s, int force, char *err, size_t cap);
/** Rows inserted and committed, per kind (index kind - 1). */
unsigned long m2s_store_rows(const m2s_store *s, int kind);
unsigned m2s_store_version(const m2s_store *s);
/** Commit and close. */
void m2s_store_close(m2s_store *s);

/** Replace path with text atomically (path.tmp, then rename). 0 or -1. */
int m2s_write_file(const char *path, const char *text, size_t len);
/** The fleet's KML to kml and, when link is not "", the NetworkLink file pointing at it.
 *  0 or -1 with err. */
int m2s_write_kml(kelp_moos2sql_fleet *f, const char *kml, const char *link, double refresh, char *err, size_t cap);
#endif
