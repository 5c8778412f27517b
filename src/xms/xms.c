/* kelp xms: the uXMS scope as a state machine (see include/kelp/xms.h). Behaviour follows
 * MOOS-IvP's uXMS (ivp/src/uXMS/XMS.cpp) and its table layout (lib_apputil ACTable). */
#include <string.h>
#include <kelp/util.h>
#include <kelp/xms.h>

#define XMS_COLS 5
#define XMS_HEADER_MAX 25 /* dashes under a header at most */

static void copy(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = 0;
}

static bool has_white(const char *s)
{
    for (; *s; s++)
        if (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r') return true;
    return false;
}

static bool ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), t = strlen(tail);
    return n >= t && strcmp(s + n - t, tail) == 0;
}

void kelp_xms_init(kelp_xms *x)
{
    memset(x, 0, sizeof *x);
    x->disp_virgins = true;
    x->disp_hist_var = true;
    x->wrap_len = 45;
    x->trunc_start = 20;
    x->history_len = 40;
    x->term_interval = 0.5; /* AppCasting's default terminal report interval */
    x->refresh = KELP_XMS_EVENTS;
    x->content = x->content_prev = KELP_XMS_SCOPING;
    x->update_requested = true;
    x->history_event = true;
    x->last_frame = -1e300;
}

static int find_var(const kelp_xms *x, const char *name, unsigned *at)
{
    unsigned lo = 0, hi = x->nvar;
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        int c = strcmp(x->var[mid].name, name);
        if (c == 0) {
            *at = mid;
            return 1;
        }
        if (c < 0) lo = mid + 1;
        else hi = mid;
    }
    *at = lo;
    return 0;
}

/* the content mode (its callers inside pass a known mode) */
static int set_content(kelp_xms *x, const char *mode, bool toggle)
{
    kelp_xms_content c;
    if (kelp_util_strieq(mode, "procs")) c = KELP_XMS_PROCS;
    else if (kelp_util_strieq(mode, "scoping")) c = KELP_XMS_SCOPING;
    else if (kelp_util_strieq(mode, "history")) c = KELP_XMS_HISTORY;
    else if (kelp_util_strieq(mode, "help")) c = KELP_XMS_HELP;
    else return KELP_ERR_PARSE;
    x->update_requested = true;
    if (c == x->content) {
        if (toggle) {
            x->content = x->content_prev;
            x->content_prev = c;
        }
        return 0;
    }
    x->content_prev = x->content;
    x->content = c;
    return 0;
}

int kelp_xms_set_content(kelp_xms *x, const char *mode, bool toggle)
{
    return set_content(x, mode, toggle);
}

int kelp_xms_set_refresh(kelp_xms *x, const char *mode)
{
    if (kelp_util_strieq(mode, "events")) x->refresh = KELP_XMS_EVENTS;
    else if (kelp_util_strieq(mode, "paused")) x->refresh = KELP_XMS_PAUSED;
    else if (kelp_util_strieq(mode, "streaming")) x->refresh = KELP_XMS_STREAMING;
    else return KELP_ERR_PARSE;
    return 0;
}

int kelp_xms_add_var(kelp_xms *x, const char *name, bool history)
{
    if (!name[0] || strstr(name, "uXMS") || has_white(name) || strlen(name) >= KELP_XMS_NAME) return 0;
    if (history && !x->history_var[0]) {
        copy(x->history_var, sizeof x->history_var, name);
        if (x->nvar == 0) (void)set_content(x, "history", false);
    }
    unsigned at;
    if (find_var(x, name, &at)) return 1;
    if (x->nvar >= KELP_XMS_MAX_VARS) {
        x->dropped++;
        return KELP_ERR_NOSPACE;
    }
    memmove(&x->var[at + 1], &x->var[at], (x->nvar - at) * sizeof x->var[0]);
    x->nvar++;
    kelp_xms_entry *e = &x->var[at];
    memset(e, 0, sizeof *e);
    copy(e->name, sizeof e->name, name);
    copy(e->value, sizeof e->value, "n/a");
    copy(e->source, sizeof e->source, " n/a");
    copy(e->time, sizeof e->time, " n/a");
    e->is_string = true;
    return 1;
}

/* calls fn for each trimmed, non-empty item of a comma-separated list */
static int each_item(const char *list, int (*fn)(kelp_xms *, const char *), kelp_xms *x)
{
    int rc = 0;
    const char *p = list;
    for (;;) {
        size_t n = strcspn(p, ",");
        const char *s = p, *e = p + n;
        while (s < e && (*s == ' ' || *s == '\t')) s++;
        while (e > s && (e[-1] == ' ' || e[-1] == '\t')) e--;
        if (e > s) {
            char item[KELP_XMS_NAME];
            size_t len = (size_t)(e - s);
            if (len >= sizeof item) rc = KELP_ERR_RANGE;
            else {
                memcpy(item, s, len);
                item[len] = 0;
                if (fn(x, item) <= 0) rc = KELP_ERR_PARSE;
            }
        }
        if (!p[n]) return rc;
        p += n + 1;
    }
}

static int add_plain(kelp_xms *x, const char *name) { return kelp_xms_add_var(x, name, false); }

int kelp_xms_add_vars(kelp_xms *x, const char *list) { return each_item(list, add_plain, x); }

static int add_source(kelp_xms *x, const char *src)
{
    char status[KELP_XMS_NAME];
    size_t n = strlen(src);
    if (n + 8 > sizeof status || has_white(src)) return KELP_ERR_PARSE;
    for (size_t i = 0; i < n; i++) status[i] = (char)(src[i] >= 'a' && src[i] <= 'z' ? src[i] - 32 : src[i]);
    memcpy(status + n, "_STATUS", 8);
    for (unsigned i = 0; i < x->nsources; i++)
        if (strcmp(x->sources[i], status) == 0) return 1;
    if (x->nsources >= KELP_XMS_MAX_SOURCES) return KELP_ERR_NOSPACE;
    copy(x->sources[x->nsources++], KELP_XMS_NAME, status);
    return 1;
}

int kelp_xms_add_sources(kelp_xms *x, const char *list)
{
    if (!strchr(list, ',') && !list[strspn(list, " \t")]) return KELP_ERR_PARSE;
    return each_item(list, add_source, x);
}

void kelp_xms_set_columns(kelp_xms *x, const char *list)
{
    const char *p = list;
    for (;;) {
        size_t n = strcspn(p, ",");
        while (n && *p == ' ') p++, n--;
        if (n >= 6 && kelp_util_strieq_n(p, 6, "source")) x->disp_source = true;
        else if (n >= 4 && kelp_util_strieq_n(p, 4, "time")) x->disp_time = true;
        else if (n >= 9 && kelp_util_strieq_n(p, 9, "community")) x->disp_community = true;
        if (!p[n]) return;
        p += n + 1;
    }
}

void kelp_xms_set_filter(kelp_xms *x, const char *prefix)
{
    if (has_white(prefix)) return;
    if (strcmp(x->filter, prefix) != 0) x->update_requested = true;
    copy(x->filter, sizeof x->filter, prefix);
    x->disp_all = prefix[0] != 0;
}

void kelp_xms_set_trunc(kelp_xms *x, unsigned n)
{
    x->trunc = n < 10 ? 10 : n > 1000 ? 1000 : n;
    x->trunc_start = x->trunc;
}

static int set_bool(bool *b, const char *val, kelp_diag *d)
{
    if (kelp_util_parse_bool(val, strlen(val), b) < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "expected true or false");
    }
    return 1;
}

int kelp_xms_config(kelp_xms *x, const char *key, const char *val, kelp_diag *d)
{
    bool b = false;
    if (kelp_util_strieq(key, "VAR")) {
        if (x->ignore_file_vars) return 1;
        (void)each_item(val, add_plain, x); /* taken: a bad name is skipped, as uXMS does */
        return 1;
    }
    if (kelp_util_strieq(key, "HISTORY_VAR")) {
        if (has_white(val) || kelp_xms_add_var(x, val, true) <= 0) return kelp_fail(d, KELP_ERR_PARSE, "not one variable name");
        return 1;
    }
    if (kelp_util_strieq(key, "SOURCE")) {
        if (kelp_xms_add_sources(x, val) < 0) return kelp_fail(d, KELP_ERR_PARSE, "expected comma-separated process names");
        return 1;
    }
    if (kelp_util_strieq(key, "REFRESH_MODE")) {
        if (kelp_xms_set_refresh(x, val) < 0) return kelp_fail(d, KELP_ERR_PARSE, "expected events, paused or streaming");
        return 1;
    }
    if (kelp_util_strieq(key, "CONTENT_MODE")) {
        if (set_content(x, val, false) < 0) return kelp_fail(d, KELP_ERR_PARSE, "expected scoping, history, procs or help");
        return 1;
    }
    if (kelp_util_strieq(key, "PAUSED")) { /* deprecated: REFRESH_MODE */
        if (set_bool(&b, val, d) < 0) return KELP_ERR_PARSE;
        x->refresh = b ? KELP_XMS_PAUSED : KELP_XMS_EVENTS;
        return 1;
    }
    if (kelp_util_strieq(key, "DISPLAY_SOURCE")) return set_bool(&x->disp_source, val, d);
    if (kelp_util_strieq(key, "DISPLAY_AUX_SOURCE")) return set_bool(&x->disp_source, val, d);
    if (kelp_util_strieq(key, "DISPLAY_TIME")) return set_bool(&x->disp_time, val, d);
    if (kelp_util_strieq(key, "DISPLAY_COMMUNITY")) return set_bool(&x->disp_community, val, d);
    if (kelp_util_strieq(key, "DISPLAY_VIRGINS")) return set_bool(&x->disp_virgins, val, d);
    if (kelp_util_strieq(key, "DISPLAY_HISTORY_VAR")) return set_bool(&x->disp_hist_var, val, d);
    if (kelp_util_strieq(key, "WRAP_DATA")) return set_bool(&x->wrap_data, val, d);
    if (kelp_util_strieq(key, "DISPLAY_ALL") || kelp_util_strieq(key, "DISPLAY_ALLL")) {
        if (set_bool(&b, val, d) < 0) return KELP_ERR_PARSE;
        if (!x->ignore_file_vars) {
            x->disp_all = b;
            if (kelp_util_strieq(key, "DISPLAY_ALLL")) x->disp_all_really = b;
        }
        return 1;
    }
    if (kelp_util_strieq(key, "TRUNC_DATA")) {
        if (set_bool(&b, val, d) < 0) return KELP_ERR_PARSE;
        if (b) x->trunc = x->trunc_start;
        return 1;
    }
    if (kelp_util_strieq(key, "WRAP_DATA_LEN") || kelp_util_strieq(key, "TERM_REPORT_INTERVAL")) {
        double num;
        if (kelp_util_parse_finite(val, strlen(val), &num) < 0 || num < 0)
            return kelp_fail(d, KELP_ERR_PARSE, "expected a number >= 0");
        if (kelp_util_strieq(key, "TERM_REPORT_INTERVAL")) x->term_interval = num > 10 ? 10 : num;
        else x->wrap_len = num < 10 ? 10 : num > 120 ? 120 : (unsigned)num;
        return 1;
    }
    if (kelp_util_strieq(key, "COLOR_MAP") || kelp_util_strieq(key, "COLORMAP")) return 1; /* no colours: accepted */
    return 0;
}

const char *kelp_xms_next_subscription(kelp_xms *x)
{
    if (x->disp_all && !x->star_subscribed) {
        x->star_subscribed = true;
        return "*";
    }
    for (unsigned i = 0; i < x->nvar; i++)
        if (!x->var[i].subscribed) {
            x->var[i].subscribed = true;
            return x->var[i].name;
        }
    return NULL;
}

/* the Publishing="A,B" list of a <SRC>_STATUS report joins the scope list */
static void add_published(kelp_xms *x, const char *status_var, const char *report)
{
    const char *p = strstr(report, "Publishing=");
    if (!p || (p != report && p[-1] != ',')) return;
    p += 11;
    size_t n = (*p == '"') ? strcspn(++p, "\"") : strcspn(p, ",");
    char list[KELP_XMS_VAL];
    if (n >= sizeof list) n = sizeof list - 1;
    memcpy(list, p, n);
    list[n] = 0;
    for (char *s = list, *e; *s; s = e + (*e != 0)) {
        e = s + strcspn(s, ",");
        char save = *e;
        *e = 0;
        while (*s == ' ') s++;
        if (*s && strcmp(s, status_var) != 0) (void)kelp_xms_add_var(x, s, false);
        *e = save;
    }
}

/* a process seen as a source: IDs 0 (MOOSDB...), 1 (pHelmIvP), then a, b, ... in order seen */
static kelp_xms_proc *proc_seen(kelp_xms *x, const char *src)
{
    for (unsigned i = 0; i < x->nproc; i++)
        if (strcmp(x->proc[i].name, src) == 0) return &x->proc[i];
    char id;
    if (strncmp(src, "MOOSDB", 6) == 0) id = '0';
    else if (strcmp(src, "pHelmIvP") == 0) id = '1';
    else if (x->var_ids < 26) id = (char)('a' + x->var_ids++);
    else return NULL;
    if (x->nproc >= KELP_XMS_MAX_PROCS) return NULL;
    unsigned at = 0;
    while (at < x->nproc && x->proc[at].id < id) at++;
    memmove(&x->proc[at + 1], &x->proc[at], (x->nproc - at) * sizeof x->proc[0]);
    x->nproc++;
    kelp_xms_proc *p = &x->proc[at];
    memset(p, 0, sizeof *p);
    copy(p->name, sizeof p->name, src);
    p->id = id;
    return p;
}

static bool proc_hidden(const kelp_xms *x, const char *src)
{
    for (unsigned i = 0; i < x->nproc; i++)
        if (x->proc[i].mask < 0 && strcmp(x->proc[i].name, src) == 0) return true;
    return false;
}

static void history_add(kelp_xms *x, const char *value, const char *source, double time)
{
    if (x->nhist) {
        kelp_xms_hist *h = &x->hist[x->hist_head];
        if (strcmp(h->value, value) == 0 && strcmp(h->source, source) == 0) {
            h->count++;
            h->time = time;
            return;
        }
    }
    x->hist_head = (x->hist_head + KELP_XMS_HIST_CAP - 1) % KELP_XMS_HIST_CAP;
    kelp_xms_hist *h = &x->hist[x->hist_head];
    copy(h->value, sizeof h->value, value);
    copy(h->source, sizeof h->source, source);
    h->time = time;
    h->count = 1;
    if (x->nhist < KELP_XMS_HIST_CAP) x->nhist++;
}

int kelp_xms_mail(kelp_xms *x, const char *name, bool is_string, const char *sval, double dval,
                  const char *source, const char *community, double time)
{
    for (unsigned i = 0; i < x->nsources; i++)
        if (is_string && strcmp(x->sources[i], name) == 0) add_published(x, name, sval);
    if (x->disp_all &&
        (x->disp_all_really || (!ends_with(name, "_STATUS") && strcmp(name, "APPCAST") != 0 &&
                                strcmp(name, "DB_RWSUMMARY") != 0 && strcmp(name, "DB_VARSUMMARY") != 0)))
        (void)kelp_xms_add_var(x, name, false);
    unsigned at;
    if (!find_var(x, name, &at)) return 0;
    kelp_xms_proc *pr = proc_seen(x, source);
    if (pr) pr->last_mail = time;
    kelp_xms_entry *n = &x->ws_entry;
    *n = x->var[at];
    char num[40];
    if (!is_string && kelp_util_fmt_fixed(num, sizeof num, dval, 6, true) < 0)
        (void)kelp_util_snprintf(num, sizeof num, "%g", dval);
    copy(n->value, sizeof n->value, is_string ? sval : num);
    n->is_string = is_string;
    copy(n->source, sizeof n->source, source);
    copy(n->community, sizeof n->community, community);
    if (kelp_util_fmt_fixed(n->time, sizeof n->time, time, 2, false) < 0) copy(n->time, sizeof n->time, "n/a");
    if (strcmp(name, x->history_var) == 0) {
        char *hv = x->ws_val;
        if (is_string) (void)kelp_util_snprintf(hv, sizeof x->ws_val, "\"%s\"", sval);
        else copy(hv, sizeof x->ws_val, num);
        history_add(x, hv, source, time);
        x->history_event = true;
    }
    bool changed = memcmp(n, &x->var[at], sizeof *n) != 0;
    x->var[at] = *n;
    if (changed && x->refresh == KELP_XMS_EVENTS) x->update_requested = true;
    return changed;
}

static void restore_orig(kelp_xms *x)
{
    unsigned w = 0;
    for (unsigned i = 0; i < x->nvar; i++) {
        bool keep = false;
        for (unsigned k = 0; k < x->nvar_orig && !keep; k++) keep = strcmp(x->orig_names[k], x->var[i].name) == 0;
        if (keep) x->var[w++] = x->var[i];
    }
    x->nvar = w;
}

/* Enter after '-' (hide) or '+' (add as a source) and process IDs; '?' clears that mask */
static void apply_masks(kelp_xms *x, int sign)
{
    if (!x->typed[0]) return;
    if (strchr(x->typed, '?'))
        for (unsigned i = 0; i < x->nproc; i++)
            if (x->proc[i].mask == sign) x->proc[i].mask = 0;
    for (const char *t = x->typed; *t; t++)
        for (unsigned i = 0; i < x->nproc; i++) {
            if (x->proc[i].id != *t) continue;
            x->proc[i].mask = (signed char)sign;
            if (sign > 0) (void)add_source(x, x->proc[i].name);
        }
}

static int typed_key(kelp_xms *x, int c)
{
    bool filter = x->entry_mode == KELP_XMS_FILTER;
    char *buf = filter ? x->filter : x->typed;
    size_t n = strlen(buf);
    if (c == '\n' || c == '\r' || (filter && c == ' ' && n)) {
        if (x->entry_mode == KELP_XMS_EXCLUDE) {
            apply_masks(x, -1);
            x->content = KELP_XMS_SCOPING;
        } else if (x->entry_mode == KELP_XMS_INCLUDE) {
            apply_masks(x, 1);
        }
        x->entry_mode = KELP_XMS_KEYS;
    } else if ((c == 127 || c == 8) && n) {
        buf[n - 1] = 0;
    } else if (c > ' ' && c < 127 && n + 1 < KELP_XMS_NAME) {
        buf[n] = (char)c;
        buf[n + 1] = 0;
    }
    x->update_requested = true;
    return 1;
}

int kelp_xms_key(kelp_xms *x, int c)
{
    if (x->entry_mode != KELP_XMS_KEYS) return typed_key(x, c);
    switch (c) {
    case 's': case 'S': case 'x': case 'X': x->disp_source = !x->disp_source; break;
    case 't': case 'T': x->disp_time = !x->disp_time; break;
    case 'c': case 'C': x->disp_community = !x->disp_community; break;
    case 'v': case 'V': x->disp_virgins = !x->disp_virgins; break;
    case 'w': case 'W': x->wrap_data = !x->wrap_data; break;
    case 'd': case 'D': (void)set_content(x, "scoping", true); break;
    case 'h': case 'H': (void)set_content(x, "help", true); break;
    case 'z': case 'Z':
        if (!x->history_var[0]) return 0;
        (void)set_content(x, "history", true);
        break;
    case 'j': case 'J':
        x->disp_hist_var = !x->disp_hist_var;
        if (x->content != KELP_XMS_HISTORY) return 0;
        break;
    case 'r': case 'R': x->refresh = KELP_XMS_STREAMING; return 0;
    case 'e': case 'E': x->refresh = KELP_XMS_EVENTS; break;
    case ' ': x->refresh = KELP_XMS_PAUSED; break;
    case 'u': case 'U': break;
    case '<': x->history_len = x->history_len >= 10 ? x->history_len - 5 : 5; break;
    case '>': x->history_len = x->history_len + 5 > KELP_XMS_HIST_CAP ? KELP_XMS_HIST_CAP : x->history_len + 5; break;
    case '}':
        x->trunc = (unsigned)(x->trunc * 1.2);
        x->trunc_start = x->trunc;
        break;
    case '{':
        x->trunc = (unsigned)(x->trunc * 0.8);
        if (x->trunc > 0 && x->trunc < 15) x->trunc = 15;
        x->trunc_start = x->trunc;
        break;
    case '`':
        if (x->trunc == 0) x->trunc = x->trunc_start;
        else {
            x->trunc_start = x->trunc;
            x->trunc = 0;
        }
        break;
    case 'p': case 'P': (void)set_content(x, "procs", true); break;
    case '-':
    case '+':
        if (c == '-') x->refresh = KELP_XMS_PAUSED;
        x->entry_mode = c == '-' ? KELP_XMS_EXCLUDE : KELP_XMS_INCLUDE;
        x->typed[0] = 0;
        break;
    case '/':
        x->refresh = KELP_XMS_PAUSED;
        x->entry_mode = KELP_XMS_FILTER;
        x->filter[0] = 0;
        break;
    case '?': x->filter[0] = 0; break;
    case 'A':
        if (!x->disp_all) {
            x->nvar_orig = x->nvar;
            for (unsigned i = 0; i < x->nvar; i++) copy(x->orig_names[i], KELP_XMS_NAME, x->var[i].name);
            x->saved_orig = true;
        }
        x->disp_all = true;
        break;
    case 'a':
        if (!x->disp_all) return 0;
        x->disp_all = false;
        if (x->saved_orig) restore_orig(x);
        break;
    default: return 0;
    }
    x->update_requested = true;
    return 1;
}

bool kelp_xms_due(const kelp_xms *x, kelp_time now)
{
    bool want;
    if (x->content == KELP_XMS_HISTORY)
        want = x->refresh == KELP_XMS_STREAMING || x->update_requested ||
               (x->refresh == KELP_XMS_EVENTS && x->history_event);
    else want = x->update_requested || (x->refresh == KELP_XMS_STREAMING && x->content != KELP_XMS_HELP);
    return want && now - x->last_frame >= x->term_interval;
}

/* ---- the table (ACTable: left-justified, two spaces between columns, trailing blanks
 * dropped; the last column of the scoping table is not padded) ---- */
typedef struct tab {
    unsigned ncol, width[XMS_COLS];
    unsigned dash_max; /* dashes under a header at most (0: the column's width) */
    bool pad_last, measure;
    char *buf;
    size_t cap, len;
    kelp_xms *ws;      /* the workspace's owner */
} tab;

static void put(tab *t, const char *s, size_t n)
{
    if (t->len + 1 < t->cap) {
        size_t room = t->cap - 1 - t->len;
        memcpy(t->buf + t->len, s, n < room ? n : room);
    }
    t->len += n;
}

static void row(tab *t, const char *const *cell)
{
    if (t->measure) {
        for (unsigned j = 0; j < t->ncol; j++) {
            size_t n = strlen(cell[j]);
            if (n > t->width[j]) t->width[j] = (unsigned)n;
        }
        return;
    }
    size_t start = t->len;
    for (unsigned j = 0; j < t->ncol; j++) {
        size_t n = strlen(cell[j]);
        put(t, cell[j], n);
        bool last = j + 1 == t->ncol;
        if (!last || t->pad_last)
            for (; n < t->width[j]; n++) put(t, " ", 1);
        if (!last) put(t, "  ", 2);
    }
    while (t->len > start && t->len < t->cap && t->buf[t->len - 1] == ' ') t->len--;
    put(t, "\n", 1);
}

static void dashes(tab *t)
{
    if (t->measure) {
        for (unsigned j = 0; j < t->ncol; j++)
            if (t->width[j] < 2) t->width[j] = 2; /* ACTable counts the separator cell "{}" */
        return;
    }
    char d[XMS_COLS][KELP_XMS_NAME + 1];
    const char *cell[XMS_COLS];
    for (unsigned j = 0; j < t->ncol; j++) {
        unsigned w = t->dash_max && t->width[j] > t->dash_max ? t->dash_max : t->width[j];
        if (w > KELP_XMS_NAME) w = KELP_XMS_NAME;
        memset(d[j], '-', w);
        d[j][w] = 0;
        cell[j] = d[j];
    }
    row(t, cell);
}

/* truncString(s, n, "middle"): first part, "..", last part, n characters in all */
static const char *trunc_middle(const char *s, size_t n, char *out, size_t cap)
{
    size_t len = strlen(s);
    if (n >= len || n + 1 > cap) return s;
    if (n < 4) {
        memcpy(out, s, n);
        out[n] = 0;
        return out;
    }
    size_t back = n / 2 - 1, front = n - n / 2 - 1;
    memcpy(out, s, front);
    memcpy(out + front, "..", 2);
    memcpy(out + front + 2, s + len - back, back);
    out[n] = 0;
    return out;
}

static const char *mode_name(kelp_xms_refresh r)
{
    return r == KELP_XMS_PAUSED ? "PAUSED" : r == KELP_XMS_STREAMING ? "STREAMING" : "EVENTS";
}

static bool shown(const kelp_xms *x, const kelp_xms_entry *e)
{
    if (!x->disp_virgins && strcmp(e->value, "n/a") == 0) return false;
    if (proc_hidden(x, e->source)) return false;
    size_t fl = strlen(x->filter);
    return !fl || (strlen(e->name) >= fl && kelp_util_strieq_n(e->name, fl, x->filter));
}

static void scoping_rows(const kelp_xms *x, tab *t)
{
    char value_hdr[64];
    (void)kelp_util_snprintf(value_hdr, sizeof value_hdr, "VarValue (SCOPING:%s)", mode_name(x->refresh));
    const char *hdr[XMS_COLS] = { "VarName", x->disp_source ? "(S)ource" : "(S)", x->disp_time ? "(T)ime" : "(T)",
                                  x->disp_community ? "(C)ommunity" : "(C)", value_hdr };
    row(t, hdr);
    dashes(t);
    unsigned trunc = x->trunc;
    if (trunc) trunc += (x->disp_community ? 0 : 8) + (x->disp_time ? 0 : 5) + (x->disp_source ? 0 : 10);
    for (unsigned i = 0; i < x->nvar; i++) {
        const kelp_xms_entry *e = &x->var[i];
        if (!shown(x, e)) continue;
        char *val = t->ws->ws_val, *cell = t->ws->ws_cell, src[20], com[20];
        const size_t val_cap = sizeof t->ws->ws_val, cell_cap = sizeof t->ws->ws_cell;
        copy(val, val_cap, e->value);
        if (strcmp(e->name, "APPCAST") == 0) val[strcspn(val, "!")] = 0;
        if (!e->is_string || strcmp(val, "n/a") == 0) copy(cell, cell_cap, val);
        else if (trunc && strlen(val) > trunc)
            (void)kelp_util_snprintf(cell, cell_cap, "\"%.*s...\"", (int)trunc, val);
        else (void)kelp_util_snprintf(cell, cell_cap, "\"%s\"", val);
        const char *c[XMS_COLS] = { e->name, x->disp_source ? trunc_middle(e->source, 16, src, sizeof src) : "",
                                    x->disp_time ? e->time : "",
                                    x->disp_community ? trunc_middle(e->community, 14, com, sizeof com) : "", cell };
        size_t vlen = strlen(val);
        if (!x->wrap_data || vlen <= x->wrap_len) {
            row(t, c);
            continue;
        }
        for (size_t off = 0; off < vlen; off += x->wrap_len) { /* wrapped: the raw value in pieces */
            char *piece = t->ws->ws_piece;
            size_t n = vlen - off < x->wrap_len ? vlen - off : x->wrap_len;
            memcpy(piece, val + off, n);
            piece[n] = 0;
            const char *w[XMS_COLS] = { off ? "" : c[0], off ? "" : c[1], off ? "" : c[2], off ? "" : c[3], piece };
            row(t, w);
        }
    }
}

static void history_rows(const kelp_xms *x, tab *t)
{
    char value_hdr[64];
    (void)kelp_util_snprintf(value_hdr, sizeof value_hdr, "VarValue (HISTORY:%s)", mode_name(x->refresh));
    const char *hdr[4] = { x->disp_hist_var ? "(J)VarName" : "(J)", x->disp_source ? "(S)ource" : "(S)",
                           x->disp_time ? "(T)ime" : "(T)", value_hdr };
    row(t, hdr);
    dashes(t);
    unsigned n = x->nhist < x->history_len ? x->nhist : x->history_len;
    for (unsigned k = n; k-- > 0;) { /* oldest first */
        const kelp_xms_hist *h = &x->hist[(x->hist_head + k) % KELP_XMS_HIST_CAP];
        char tm[24], *cell = t->ws->ws_cell; /* workspace: no value-sized buffer on the stack */
        const size_t cell_cap = sizeof t->ws->ws_cell;
        if (kelp_util_fmt_fixed(tm, sizeof tm, h->time, 2, false) < 0) copy(tm, sizeof tm, "n/a");
        if (x->trunc && strlen(h->value) > x->trunc)
            (void)kelp_util_snprintf(cell, cell_cap, "(%u) %.*s...", h->count, (int)x->trunc, h->value);
        else (void)kelp_util_snprintf(cell, cell_cap, "(%u) %s", h->count, h->value);
        const char *c[4] = { x->disp_hist_var ? x->history_var : "", x->disp_source ? h->source : "",
                             x->disp_time ? tm : "", cell };
        row(t, c);
    }
}

/* the processes report: the mode right-justified in 78 columns, the process-watch line (kelp
 * has no uProcessWatch summary), then ID, name, age of its last mail, client age */
static void procs_rows(const kelp_xms *x, tab *t, kelp_time now)
{
    const char *hdr[4] = { "ID", "Process Name", "Mail", "Client" };
    row(t, hdr);
    dashes(t);
    for (unsigned i = 0; i < x->nproc; i++) {
        const kelp_xms_proc *p = &x->proc[i];
        char id[4] = { p->mask < 0 ? '-' : p->mask > 0 ? '+' : p->id, p->mask ? p->id : 0, 0, 0 };
        char age[24] = "-";
        if (p->last_mail > 0 && kelp_util_fmt_fixed(age, sizeof age, now - p->last_mail, 2, false) < 0) copy(age, sizeof age, "-");
        const char *c[4] = { id, p->name, age, "-" };
        row(t, c);
    }
}

static const char *const help_lines[] = {
    "KeyStroke    Function         (HELP)",
    "---------    ---------------------------",
    "    s        Show or hide the source column",
    "    t        Show or hide the time column",
    "    c        Show or hide the community column",
    "    v        Show or hide variables never written",
    "    d        Content: scoping (the variable table)",
    "    h        Content: this help; h again goes back",
    "    z        Content: history of the history variable",
    "    p        Content: processes seen, with their IDs",
    "    -        Hide variables from processes (type IDs, Enter)",
    "    +        Add processes as sources (type IDs, Enter)",
    "    j        Show or hide the history variable's name",
    "  > or <     Longer or shorter history",
    "  } or {     Longer or shorter cut of long values",
    "    `        Cut long values on or off",
    "    /        Type a filter (name prefix), then Enter",
    "    ?        Clear the filter",
    "    a        Back to the variables shown at start",
    "    A        Show every variable on the bus",
    "   u/SPC     Refresh: draw once, then pause",
    "    r        Refresh: streaming",
    "    e        Refresh: on events (a value changed)",
    "    w        Wrap long values",
};

size_t kelp_xms_format(kelp_xms *x, kelp_time now, char *buf, size_t cap)
{
    tab t = { .buf = buf, .cap = cap, .dash_max = XMS_HEADER_MAX, .ws = x };
    if (cap) buf[0] = 0;
    if (x->content == KELP_XMS_HELP) {
        for (size_t i = 0; i < sizeof help_lines / sizeof help_lines[0]; i++) {
            put(&t, help_lines[i], strlen(help_lines[i]));
            put(&t, "\n", 1);
        }
    } else if (x->content == KELP_XMS_PROCS || x->entry_mode == KELP_XMS_EXCLUDE || x->entry_mode == KELP_XMS_INCLUDE) {
        char mode[40], line[160];
        (void)kelp_util_snprintf(mode, sizeof mode, "(PROCESSES:%s)", mode_name(x->refresh));
        int n = kelp_util_snprintf(line, sizeof line, "%78s\nuProcessWatch(0): not running\n", mode);
        put(&t, line, (size_t)n);
        t.ncol = 4;
        t.pad_last = true;
        t.dash_max = 0;
        for (int pass = 0; pass < 2; pass++) {
            t.measure = pass == 0;
            procs_rows(x, &t, now);
        }
        if (x->entry_mode == KELP_XMS_EXCLUDE || x->entry_mode == KELP_XMS_INCLUDE) {
            n = kelp_util_snprintf(line, sizeof line, "\n%s process > %s\n",
                              x->entry_mode == KELP_XMS_EXCLUDE ? "Exclude a" : "Include a", x->typed);
            put(&t, line, (size_t)n);
        }
    } else {
        t.ncol = x->content == KELP_XMS_HISTORY ? 4 : 5;
        t.pad_last = x->content == KELP_XMS_HISTORY;
        for (int pass = 0; pass < 2; pass++) {
            t.measure = pass == 0;
            if (x->content == KELP_XMS_HISTORY) history_rows(x, &t);
            else scoping_rows(x, &t);
        }
        if (x->content == KELP_XMS_SCOPING) {
            bool typing = x->entry_mode == KELP_XMS_FILTER;
            if (x->filter[0] || typing) {
                put(&t, "  -- filter: ", 13);
                put(&t, x->filter, strlen(x->filter));
                put(&t, typing ? "_ -- \n" : " -- \n", typing ? 6 : 5);
            }
            if (x->disp_all) put(&t, "  -- displaying all variables --\n", 33);
        }
    }
    if (cap) buf[t.len < cap ? t.len : cap - 1] = 0;
    return t.len < cap ? t.len : (cap ? cap - 1 : 0);
}

size_t kelp_xms_render(kelp_xms *x, kelp_time now, char *buf, size_t cap)
{
    size_t n = kelp_xms_format(x, now, buf, cap);
    x->update_requested = false;
    x->history_event = false;
    x->last_frame = now;
    x->frames++;
    return n;
}
