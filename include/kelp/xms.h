/* kelp xms (core): the uXMS scope as a state machine. Variables to show (named, from
 * DISPLAY_ALL, or from a SOURCE's <SRC>_STATUS Publishing list), their last value, source,
 * time and community, one variable's history, the uXMS key commands, and each frame as text
 * in uXMS's own column layout (a left-justified table, two spaces between columns, dashes
 * under the headers up to 25 wide, trailing blanks dropped), written into a caller buffer.
 * No allocation, no I/O, no clock: the app passes mail, keys and `now` (seconds).
 *
 * Frames (content modes): scoping (one row per variable, sorted by name), history (the
 * history variable's recent values, oldest first, repeats counted), procs (the processes
 * seen as sources, with their IDs for '-' hide and '+' add), help (the key list).
 * Refresh modes: events (a frame when a shown value changes or a key asks), paused (only on
 * request: space/u), streaming (every term interval). */
#ifndef KELP_XMS_H
#define KELP_XMS_H

#include <stdbool.h>
#include <stddef.h>
#include <kelp/config.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_XMS_MAX_VARS 512
#define KELP_XMS_MAX_SOURCES 16
#define KELP_XMS_HIST_CAP 100
#define KELP_XMS_NAME 64
#define KELP_XMS_VAL 512 /* value text kept per variable (longer values are cut) */
#define KELP_XMS_MAX_PROCS 36 /* sources given an ID: 0 (MOOSDB), 1 (pHelmIvP), a..z */

typedef enum kelp_xms_refresh { KELP_XMS_EVENTS = 0, KELP_XMS_PAUSED, KELP_XMS_STREAMING } kelp_xms_refresh;
typedef enum kelp_xms_content { KELP_XMS_SCOPING = 0, KELP_XMS_HISTORY, KELP_XMS_HELP, KELP_XMS_PROCS } kelp_xms_content;
/** What typed characters are going to: keys, the filter ('/'), the IDs of processes to hide
 *  ('-') or to add as sources ('+'); Enter ends. */
typedef enum kelp_xms_entry_mode { KELP_XMS_KEYS = 0, KELP_XMS_FILTER, KELP_XMS_EXCLUDE, KELP_XMS_INCLUDE } kelp_xms_entry_mode;

/** A process seen as the source of a scoped variable, with its one-character ID. */
typedef struct kelp_xms_proc {
    char name[KELP_XMS_NAME];
    char id;
    signed char mask; /**< -1 hidden ('-'), +1 added as a source ('+'), 0 */
    double last_mail; /**< seconds since start */
} kelp_xms_proc;

typedef struct kelp_xms_entry {
    char name[KELP_XMS_NAME];
    char value[KELP_XMS_VAL];       /**< as shown: "n/a" until written; doubles as %.6f compacted */
    char source[KELP_XMS_NAME];     /**< " n/a" until written (uXMS's placeholder) */
    char community[KELP_XMS_NAME];
    char time[24];                  /**< seconds since start, %.2f; " n/a" until written */
    bool is_string;
    bool subscribed;                /**< the app registered it (kelp_xms_next_subscription) */
} kelp_xms_entry;

typedef struct kelp_xms_hist {
    char value[KELP_XMS_VAL];       /**< quoted string or compacted number */
    char source[KELP_XMS_NAME];
    double time;
    unsigned count;
} kelp_xms_hist;

typedef struct kelp_xms {
    /* display options (mission parameters, command line, keys) */
    bool disp_source, disp_time, disp_community, disp_virgins, disp_hist_var;
    bool disp_all, disp_all_really, ignore_file_vars, wrap_data;
    unsigned wrap_len, trunc, trunc_start, history_len;
    double term_interval;           /**< streaming: seconds between frames */
    kelp_xms_refresh refresh;
    kelp_xms_content content, content_prev;
    char filter[KELP_XMS_NAME];     /**< shown: names starting with it (any case) */
    char history_var[KELP_XMS_NAME];
    char sources[KELP_XMS_MAX_SOURCES][KELP_XMS_NAME]; /**< <SRC>_STATUS names */
    unsigned nsources;
    /* variables, sorted by name (strcmp) */
    kelp_xms_entry var[KELP_XMS_MAX_VARS];
    unsigned nvar;
    /* history ring: hist[(hist_head + i) % CAP], i = 0 newest */
    kelp_xms_hist hist[KELP_XMS_HIST_CAP];
    unsigned hist_head, nhist;
    /* the startup list, restored by 'a' after 'A' */
    unsigned nvar_orig;
    char orig_names[KELP_XMS_MAX_VARS][KELP_XMS_NAME];
    bool saved_orig;
    /* frame scheduling */
    kelp_xms_proc proc[KELP_XMS_MAX_PROCS]; /**< sorted by ID */
    unsigned nproc, var_ids;
    kelp_xms_entry_mode entry_mode;
    char typed[KELP_XMS_NAME];      /**< IDs typed after '-' or '+' */
    bool update_requested, history_event;
    bool star_subscribed;           /**< "*" handed out (display-all) */
    double last_frame;
    unsigned long frames, dropped;  /**< frames drawn; variables not added (table full) */
    /* workspace of one call (keeps the stack under 1 KB) */
    kelp_xms_entry ws_entry;        /**< mail: the entry as it becomes */
    char ws_val[KELP_XMS_VAL], ws_cell[KELP_XMS_VAL + 24], ws_piece[KELP_XMS_VAL];
} kelp_xms;

/** Defaults as uXMS: no source/time/community columns, virgins shown, events refresh,
 *  scoping content, history length 40, no truncation, term interval 0.5 s. */
void kelp_xms_init(kelp_xms *x);
/** One ProcessConfig parameter (VAR, HISTORY_VAR, SOURCE, DISPLAY_*, PAUSED, REFRESH_MODE,
 *  CONTENT_MODE, TRUNC_DATA, WRAP_DATA, WRAP_DATA_LEN, COLOR_MAP, TERM_REPORT_INTERVAL):
 *  1 taken, 0 not an xms parameter, KELP_ERR_PARSE bad value (reason in d). */
KELP_MUST_CHECK int kelp_xms_config(kelp_xms *x, const char *key, const char *val, kelp_diag *d);
/** Add a variable to the scope list (history: also the history variable, if none yet).
 *  Names containing "uXMS" or white space are refused (0); 1 added or present; KELP_ERR_NOSPACE table full. */
KELP_MUST_CHECK int kelp_xms_add_var(kelp_xms *x, const char *name, bool history);
/** Add a comma-separated list of variables. @return 0, or KELP_ERR_PARSE / KELP_ERR_RANGE when
 *  one was refused or too long (the others are added). */
KELP_MUST_CHECK int kelp_xms_add_vars(kelp_xms *x, const char *list);
/** Add sources (comma-separated): their <SRC>_STATUS Publishing lists join the scope list.
 *  @return 0, or <0 (KELP_ERR_PARSE, KELP_ERR_NOSPACE) when one was refused. */
KELP_MUST_CHECK int kelp_xms_add_sources(kelp_xms *x, const char *list);
/** REFRESH_MODE events, paused or streaming. @return 0 or KELP_ERR_PARSE. */
KELP_MUST_CHECK int kelp_xms_set_refresh(kelp_xms *x, const char *mode);
/** CONTENT_MODE scoping, history, procs or help (toggle: again goes back). @return 0 or KELP_ERR_PARSE. */
KELP_MUST_CHECK int kelp_xms_set_content(kelp_xms *x, const char *mode, bool toggle);
/** --show=source,time,community */
void kelp_xms_set_columns(kelp_xms *x, const char *list);
/** --filter=PREFIX (also turns on display-all, as uXMS) */
void kelp_xms_set_filter(kelp_xms *x, const char *prefix);
/** --trunc=N (clipped to 10..1000) */
void kelp_xms_set_trunc(kelp_xms *x, unsigned n);

/** Names the app must subscribe to: call until NULL (each is returned once; "*" once
 *  display-all is on). */
const char *kelp_xms_next_subscription(kelp_xms *x);
/** One message; time is seconds since the scope's start. Returns 1 if it changed what is shown. */
int kelp_xms_mail(kelp_xms *x, const char *name, bool is_string, const char *sval, double dval,
                  const char *source, const char *community, double time);
/** One key (uXMS's commands; 'q' is the app's, unless x->entry_mode). Returns 1 if a frame
 *  should be drawn now. After '+' and Enter, new sources' <SRC>_STATUS may need registering:
 *  the app registers x->sources[] it has not yet. */
int kelp_xms_key(kelp_xms *x, int c);
/** Is a frame due at now: one is wanted (refresh and content mode, pending changes) and the
 *  term interval has passed since the last (AppCasting limits every terminal report so)? */
bool kelp_xms_due(const kelp_xms *x, kelp_time now);
/** Write the current frame (NUL-terminated, lines end in '\n') and note it drawn (clears the
 *  pending request). @return its length (cut at cap-1). */
size_t kelp_xms_render(kelp_xms *x, kelp_time now, char *buf, size_t cap);
/** The same text, changing nothing (the app's AppCast report body). */
size_t kelp_xms_format(kelp_xms *x, kelp_time now, char *buf, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
