/* kelp helm: private helpers shared by the helm sources. */
#ifndef KELP_HELM_INT_H
#define KELP_HELM_INT_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/helm.h>

/** Copy s[0..n) into dst (cap bytes). false if it does not fit (dst then untouched). */
bool hx_copy(char *dst, size_t cap, const char *s, size_t n);
/** Trim blanks: advance *s and shrink *n. */
void hx_trim(const char **s, size_t *n);
bool hx_is_space(char c);
char hx_lower(char c);
/** Case-insensitive equality of two C strings. */
bool hx_ieq(const char *a, const char *b);
/** Strict number parse of s[0..n) (trimmed first). */
bool hx_number(const char *s, size_t n, double *out);
/** FNV-1a 64 over bytes, chained from h. */
uint64_t hx_hash(uint64_t h, const void *p, size_t n);
static inline void hx_ignore(int rc)
{
    (void)rc;
}
#define HX_HASH_INIT UINT64_C(0xcbf29ce484222325)
/** Parse "VAR = value" (split at the first '='): var must be a word without blanks. The value
 *  is typed as MOOS "auto" (quoted -> string without quotes, number -> double, else string). */
bool hx_pair(const char *s, kelp_helm_pair *out);
/** Type a value string into a pair (var untouched). */
bool hx_pair_value(const char *v, size_t n, kelp_helm_pair *out);
/** A valid MOOS variable name: non-empty, fits, no blanks. */
bool hx_varname(const char *s, size_t n);
/** Numbers as text without stdio (newlib's snprintf would pull in malloc on firmware):
 *  hx_fmt_double: up to 6 decimals, trailing zeros dropped ("-0" -> "0"; >= 1e12 as m.mmmmmme+N);
 *  hx_fmt_fixed: exactly dec decimals (rounded as printf rounds: kelp_util_fmt_fixed). */
void hx_fmt_double(char *buf, size_t cap, double v);
void hx_fmt_fixed(char *buf, size_t cap, double v, unsigned dec);
/** At most dec decimals, trailing zeros and a bare '.' dropped ("2.50" -> "2.5", "3.0" -> "3"). */
void hx_fmt_x(char *buf, size_t cap, double v, unsigned dec);
void hx_fmt_ulong(char *buf, size_t cap, unsigned long v);
/** Concatenate NULL-terminated string arguments into buf (truncating); returns the length. */
size_t hx_cat(char *buf, size_t cap, ...);
#define HX_END ((const char *)0)

/* Record a configuration failure in h->diag (first wins): the code, the .bhv line and the
 * message made of the string arguments up to HX_END. Returns code. */
int helm_fail(kelp_helm *h, int line, int code, ...);

/* helm internals used by bhv.c */
/* the variable a behaviour's posting goes to (its post_mapping; "silent": none) */
const char *helm_bhv_var(const kelp_bhv *b, const char *var);
void helm_queue_post(kelp_helm *h, const kelp_bhv *b, const char *var, bool is_str, const char *sval, double dval,
                     const char *key);
int helm_need_var(kelp_helm *h, const char *name, size_t n);
void helm_post_flags(kelp_bhv *b, kelp_bhv_flag_kind kind);
/* IvPBehavior::expandMacros over a flag's text: $[..] and $(..) forms of OWNSHIP, BHVNAME,
 * BHVTYPE, PWT, UTC, CONTACT, and a contact behaviour's own (helm_avoid_macro); unknown
 * macros stay as written. *solo: the text was one macro only. */
void helm_expand_macros(const kelp_bhv *b, const char *in, char *out, size_t cap, bool *solo);
/* BHV_AvoidCollision's macros (CONTACT, OSX..OSV, CNX..CNV, CN_NAME, CN_VTYPE, CN_GROUP,
 * CN_RANGE, RANGE): the value of macro m (ml bytes) into val; false when not one of them */
bool helm_avoid_macro(const kelp_bhv *b, const char *m, size_t ml, char *val, size_t cap);
/* BHV_Waypoint's own macros (24.8's BHV_Waypoint::expandMacros): POINTS, SPEED, NX, NY, PX, PY,
 * NI, PI, CYCLES, WPTS_HIT, ... */
bool helm_wpt_macro(const kelp_bhv *b, const char *m, size_t ml, char *val, size_t cap);
/* a condition's variable registered with the helm (kelp_helm_cond_check's callback; user: the kelp_bhv) */
void bhv_cond_var(const char *var, size_t len, void *user);
/* BHV_Waypoint's lead_condition (called from bhv_general_param) */
int helm_wpt_lead_condition(kelp_bhv *b, const char *v);
/* a flag's string value posted as IvPBehavior::postFlag: macros expanded, a lone macro that
 * expands to a number posted as a number */
void helm_post_flag_string(kelp_bhv *b, const char *var, const char *sval, const char *key);
int bhv_general_param(kelp_bhv *b, const char *param, const char *value);
/* "true" or "false" (any case) into *out; false for anything else (*out unchanged) */
bool bhv_parse_true_false(const char *v, bool *out);
void helm_sink(kelp_helm *h, const char *var, bool is_str, const char *s, double d, const char *aux);
/* IVPHELM_LIFE_EVENT as 24.8 writes it: "iter=0[,time=<helm s since the first iteration>],
 * bname=.., btype=.., event=..[, seed=..],iter=<helm iteration>" */
void helm_life_event(kelp_helm *h, const char *bname, const char *btype, const char *event, const char *seed);
/* one '#'-separated update piece "param = value" of s[0..pn), trimmed */
bool helm_update_piece(const char *piece, size_t pn, char *param, size_t pcap, char *val, size_t vcap);
/* templates and spawning (spawn.c) */
int helm_templates_extract(kelp_helm *h);
void helm_spawn(kelp_helm *h);
void helm_reap(kelp_helm *h);
void helm_ledger_update(kelp_helm *h);
/* does an update's name=val piece name b (exactly, or base + val for a spawned behaviour)? */
bool helm_name_matches(const kelp_bhv *b, const char *val);
void bhv_defaults(kelp_bhv *b);

/* shared by the waypoint-like behaviours: coupled course x speed ZAIC function (seed Listing 13):
 * speed peak at speed (peakwidth spw, basewidth sbw, summitdelta ssd), course peak at course
 * (peakwidth 0, basewidth 180, summitdelta 0, wrap), coupled 50/50 and normalised to [0,100]. */
int bhv_course_speed_zaic(kelp_bhv *b, const kelp_helm_work *w, double course, double speed, double spw, double sbw,
                          double ssd, kelp_ivp_func *out);
/* hierarchical modes (modes.c): load the "set VAR = VAL { ... } ELSE" block at node bi; evaluate
 * all entries (post gets each changed value); IVPHELM_MODESET text */
int helm_mode_load(kelp_helm *h, const kelp_mission *m, size_t bi);
void helm_mode_eval(kelp_helm *h, void (*post)(kelp_helm *h, const char *var, const char *val));
void helm_mode_describe(const kelp_helm *h, char *buf, size_t cap);
/* the same with the course function's share of the coupling (MOOS-IvP crs_spd_zaic_ratio) */
/* the speed variable's points when the domain has course and speed and tmp holds more (the
 * speed function goes first in tmp): 0, KELP_ERR_NOTFOUND or KELP_ERR_NOSPACE */
int bhv_cs_speed_points(const kelp_bhv *b, const kelp_helm_work *w, size_t *ns);
int bhv_course_speed_zaic_ratio(kelp_bhv *b, const kelp_helm_work *w, double course, double speed, double spw,
                                double sbw, double ssd, double course_pct, kelp_ivp_func *out);
/* the course peak (peakwidth 0, basewidth 180, wrap) coupled with spd, a function over speed
 * whose pieces take the first `used` of w->tmp: the course's share course_pct, into w->out */
int bhv_course_couple(kelp_bhv *b, const kelp_helm_work *w, double course, const kelp_ivp_func *spd, size_t used,
                      double course_pct, kelp_ivp_func *out);
/** A one-variable ZAIC_PEAK over var into w->out. */
int bhv_zaic1(kelp_bhv *b, const kelp_helm_work *w, const char *var, double summit, double pw, double bw, double sd,
              bool wrap, kelp_ivp_func *out);

/* IvPBehavior::updatePlatformInfo: ownship's X, Y and heading (in [0,360)) from the buffer; a
 * BHV_ERROR (which halts the helm) and false when one is missing */
bool bhv_platform_info(kelp_bhv *b, double *osx, double *osy, double *osh);
/* snapToStep as MOOS-IvP rounds: v to the nearest multiple of step, a tie away from zero */
double bhv_snap_step(double v, double step);
/* projectPoint: (*x, *y) moved dist along compass bearing deg (exactly along an axis at 0, 90,
 * 180 and 270 degrees) */
void bhv_project(double deg, double dist, double *x, double *y);

/* Set a behaviour's domain to the helm domain's sub-domain over `vars` (e.g. "course,speed");
 * when the helm domain lacks them the domain is left empty, which configuration refuses. */
void bhv_use_subdomain(kelp_bhv *b, const char *vars);
/* visual_hints: MOOS-IvP's defaults; "key=value, ..." (unknown or bad hints are ignored, as
 * MOOS-IvP does; a malformed list is KELP_ERR_PARSE) */
void bhv_hints_default(kelp_bhv_hints *h);
int bhv_set_hints(kelp_bhv_hints *h, const char *v);
/* post_suffix into suffix[cap] with its leading '_' (added when missing); "" clears */
int bhv_set_suffix(char *suffix, size_t cap, const char *v);

#endif
