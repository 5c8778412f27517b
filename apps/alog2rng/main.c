/* alog2rng (the Alog Toolbox's, seed 000 section 12.2): a table of range reports for Matlab
 * from a log -- a MOOS .alog or an LCM log of a kelp run.
 *
 *   alog2rng [--nav=false] [--nohdr] [--delim=tab|space|padded] [--report=table|flat]
 *            [--var=NAME] [--vname=NAME] [--verbose] LOGFILE
 *
 * Header "Time <id...> NAV_X NAV_Y NAV_HDG", columns tab-separated (--delim=space: one space;
 * --delim=padded: MOOS-IvP alog2rng's layout, a blank line, then the time padded to its
 * longest + 4, each range to the longest range + 4 and each NAV value to 11; --nohdr: no
 * header). --report=flat (MOOS-IvP's other report): "Time ID Range", a row per report. A row per burst of range
 * reports: the reports that share their time= field (a new burst also starts when an id comes
 * round again); the row's time (3 decimals, seconds since the log's start) is its first
 * report's, then the range of each id as the report wrote it (columns in first-seen order;
 * NaN for an id without a report in the burst), then the latest NAV_X, NAV_Y and NAV_HEADING
 * (or NAV_HDG) posted before the row, 3 decimals (--nav=false drops them). Reports are
 * BRS_RANGE_REPORT and CRS_RANGE_REPORT and their _<VNAME> forms (not _GT), or --var's; the id
 * is id= (beacons) or target= (contacts). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/alog.h>
#include <kelp/edge/cli.h>
#include <kelp/kv.h>
#include <kelp/util.h>

#define MAX_IDS 64
#define ID_LEN 32

enum { DELIM_TAB, DELIM_SPACE, DELIM_PADDED };

typedef struct table {
    const char *var, *vname;
    int delim;
    bool header, flat;
    size_t wtime, wrange, wid;   /* longest time, range and id texts (--delim=padded) */
    char id[MAX_IDS][ID_LEN];
    int nid;
    /* the burst being collected */
    char val[MAX_IDS][ID_LEN];
    bool have[MAX_IDS];
    char key[64];
    double t;
    bool open;
    double nav[3], row_nav[3];   /* latest values; their values when the row opened */
    bool nav_ok[3], row_nav_ok[3], with_nav;
    long rows;
} table;

static bool is_report(const table *tb, const char *var)
{
    if (tb->var) return strcmp(var, tb->var) == 0;
    size_t n = strlen(var);
    if (n >= 3 && strcmp(var + n - 3, "_GT") == 0) return false;
    return strncmp(var, "BRS_RANGE_REPORT", 16) == 0 || strncmp(var, "CRS_RANGE_REPORT", 16) == 0;
}

static int id_index(table *tb, const char *id, bool add)
{
    for (int i = 0; i < tb->nid; i++)
        if (strcmp(tb->id[i], id) == 0) return i;
    if (!add || tb->nid >= MAX_IDS) return -1;
    snprintf(tb->id[tb->nid], ID_LEN, "%s", id);
    if (strlen(tb->id[tb->nid]) > tb->wid) tb->wid = strlen(tb->id[tb->nid]);
    return tb->nid++;
}

/* one cell: the first without a separator before it; padded cells are left-aligned in width */
static void cell(const table *tb, bool first, const char *text, size_t width)
{
    if (tb->delim == DELIM_PADDED) printf("%-*s", (int)width, text);
    else printf("%s%s", first ? "" : tb->delim == DELIM_TAB ? "\t" : " ", text);
}

static void emit(table *tb)
{
    if (!tb->open) return;
    char t[64];
    snprintf(t, sizeof t, "%.3f", tb->t);
    cell(tb, true, t, tb->wtime + 4);
    for (int i = 0; i < tb->nid; i++) cell(tb, false, tb->have[i] ? tb->val[i] : "NaN", tb->wrange + 4);
    for (int k = 0; tb->with_nav && k < 3; k++) {
        if (tb->row_nav_ok[k]) snprintf(t, sizeof t, "%.3f", tb->row_nav[k]);
        else snprintf(t, sizeof t, "NaN");
        cell(tb, false, t, 11);
    }
    printf("\n");
    tb->open = false;
    tb->rows++;
    memset(tb->have, 0, sizeof tb->have);
}

/* a report's id and range; false when it is not one of ours */
static bool report(const table *tb, const kelp_post *e, char *id, char *range, char *key)
{
    if (!e->is_string || !is_report(tb, e->var)) return false;
    char vn[64];
    if (tb->vname && (kelp_kv_get(e->sval, ',', "vname", vn, sizeof vn) != 1 || !kelp_util_strieq(vn, tb->vname))) return false;
    if (kelp_kv_get(e->sval, ',', "range", range, ID_LEN) != 1) return false;
    if (kelp_kv_get(e->sval, ',', "id", id, ID_LEN) != 1 && kelp_kv_get(e->sval, ',', "target", id, ID_LEN) != 1)
        snprintf(id, ID_LEN, "range");
    if (kelp_kv_get(e->sval, ',', "time", key, 64) != 1) key[0] = 0;
    return true;
}

/* pass 1 (print == false): the ids in first-seen order; pass 2: the rows */
static int pass(const char *path, table *tb, bool print)
{
    kelp_diag err = {0};
    kelp_alog_postlog *p = kelp_alog_postlog_open(path, NULL, &err);
    if (!p) return fprintf(stderr, "alog2rng: %s\n", kelp_diag_text(&err)), -1;
    kelp_post e;
    int rc;
    char id[ID_LEN], range[ID_LEN], key[64];
    while ((rc = kelp_alog_postlog_next(p, &e)) > 0) {
        static const char *const navs[] = { "NAV_X", "NAV_Y", "NAV_HEADING", "NAV_HDG" };
        for (int k = 0; k < 4; k++)
            if (!e.is_string && strcmp(e.var, navs[k]) == 0) tb->nav[k < 3 ? k : 2] = e.dval, tb->nav_ok[k < 3 ? k : 2] = true;
        if (!report(tb, &e, id, range, key)) continue;
        int i = id_index(tb, id, !print);
        if (!print) {
            char t[64];
            size_t tl = (size_t)snprintf(t, sizeof t, "%.3f", e.time - kelp_alog_postlog_start(p));
            if (tl > tb->wtime) tb->wtime = tl;
            if (strlen(range) > tb->wrange) tb->wrange = strlen(range);
            continue;
        }
        if (tb->flat) {
            char t[64];
            snprintf(t, sizeof t, "%.3f", e.time - kelp_alog_postlog_start(p));
            cell(tb, true, t, tb->wtime + 1);
            cell(tb, false, id, tb->wid + 1);
            cell(tb, false, range, tb->wrange);
            printf("\n");
            tb->rows++;
            continue;
        }
        if (i < 0) continue;
        if (tb->open && (tb->have[i] || strcmp(key, tb->key) != 0 || (!key[0] && fabs(e.time - kelp_alog_postlog_start(p) - tb->t) > 0.5)))
            emit(tb);
        if (!tb->open) {
            tb->open = true;
            tb->t = e.time - kelp_alog_postlog_start(p);
            memcpy(tb->row_nav, tb->nav, sizeof tb->nav);
            memcpy(tb->row_nav_ok, tb->nav_ok, sizeof tb->nav_ok);
            snprintf(tb->key, sizeof tb->key, "%s", key);
        }
        snprintf(tb->val[i], ID_LEN, "%s", range);
        tb->have[i] = true;
    }
    if (print) emit(tb);
    kelp_alog_postlog_close(p);
    if (rc < 0) return fprintf(stderr, "alog2rng: read error in %s\n", path), -1;
    return 0;
}

int main(int argc, char **argv)
{
    const kelp_cli cli = {
        .name = "alog2rng",
        .purpose = "A table of range reports (time, a range per beacon or contact, NAV_X NAV_Y NAV_HDG) from an\n"
                   ".alog or an LCM log, for Matlab.",
        .synopsis = "[--nav=false] [--var=NAME] [--vname=NAME] LOGFILE",
        .opts = (const kelp_cli_opt[]){
            { "nav", required_argument, 'n', "BOOL", "false: no NAV_X NAV_Y NAV_HDG columns (default true)" },
            { "var", required_argument, 'r', "NAME", "the report variable (default BRS_/CRS_RANGE_REPORT[_<V>])" },
            { "vname", required_argument, 'V', "NAME", "only reports with vname=NAME" },
            { "nohdr", no_argument, 'H', NULL, "no header line" },
            { "delim", required_argument, 'd', "D", "tab (default), space, or padded (MOOS-IvP's aligned columns)" },
            { "report", required_argument, 'R', "R", "table (default), or flat: Time ID Range, a row per report" },
            { "verbose", no_argument, 1000, NULL, "the counts on stderr" },
            { NULL, 0, 0, NULL, NULL } },
    };
    static table tb;
    tb.with_nav = true;
    tb.header = true;
    bool verbose = false;
    int c, status;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (c) {
        case KELP_CLI_EXIT: return status;
        case 'n':
            if (kelp_util_parse_bool(optarg, strlen(optarg), &tb.with_nav) < 0) return kelp_cli_error(&cli, "--nav takes true or false");
            break;
        case 'r': tb.var = optarg; break;
        case 'V': tb.vname = optarg; break;
        case 'H': tb.header = false; break;
        case 'd':
            if (kelp_util_strieq(optarg, "tab")) tb.delim = DELIM_TAB;
            else if (kelp_util_strieq(optarg, "space")) tb.delim = DELIM_SPACE;
            else if (kelp_util_strieq(optarg, "padded")) tb.delim = DELIM_PADDED;
            else return kelp_cli_error(&cli, "--delim takes tab, space or padded");
            break;
        case 'R':
            if (kelp_util_strieq(optarg, "table")) tb.flat = false;
            else if (kelp_util_strieq(optarg, "flat") || kelp_util_strieq(optarg, "default")) tb.flat = true;
            else return kelp_cli_error(&cli, "--report takes table or flat");
            break;
        case 1000: verbose = true; break;
        default: break;
        }
    }
    if (argc - optind != 1) return kelp_cli_error(&cli, "one log file expected");
    if (pass(argv[optind], &tb, false) < 0) return 1;
    if (tb.header && tb.delim == DELIM_PADDED) printf("\n");
    if (tb.header && tb.flat) {
        cell(&tb, true, "Time", tb.wtime + 1);
        cell(&tb, false, "ID", tb.wid + 1);
        cell(&tb, false, "Range", tb.wrange);
        printf("\n");
    } else if (tb.header) {
        cell(&tb, true, "Time", tb.wtime + 4);
        for (int i = 0; i < tb.nid; i++) cell(&tb, false, tb.id[i], tb.wrange + 4);
        if (tb.with_nav) {
            cell(&tb, false, "NAV_X", 11);
            cell(&tb, false, "NAV_Y", 11);
            cell(&tb, false, "NAV_HDG", 0);
        }
        printf("\n");
    }
    memset(tb.nav_ok, 0, sizeof tb.nav_ok);
    if (pass(argv[optind], &tb, true) < 0) return 1;
    if (tb.nid == MAX_IDS) fprintf(stderr, "alog2rng: more than %d ids: the rest are left out\n", MAX_IDS);
    if (verbose) fprintf(stderr, "alog2rng: %s: %d ids, %ld rows\n", argv[optind], tb.nid, tb.rows);
    return tb.rows ? 0 : 1;
}
