/* kelp helm: the IvP helm, its behaviour framework and the built-in behaviours.
 *
 * Follows the IvP helm of MOOS-IvP (Benjamin et al., MIT-CSAIL-TR-2009-037, chapters 4 and 5).
 * Functions are built and solved with kelp's IvP
 * library (include/kelp/ivp.h).
 *
 * Core and allocation-free: the caller places a kelp_helm (it is large: size it with the
 * KELP_HELM_* limits of config.h) and passes piece/work storage in a kelp_helm_mem. Time is
 * an argument (MOOS time, seconds); "buffer time" is seconds since kelp_helm_start().
 *
 * One helm iteration (kelp_helm_iterate), as pHelmIvP's Iterate:
 *   1. buffer time is set once; mail received since the last iteration is stamped with it;
 *   2. per behaviour, in file order: checkUpdates (UPDATES strings), duration reset check,
 *      isComplete (completed behaviours are skipped), isRunnable (run conditions, then the
 *      duration clock, then the domain, then NOSTARVE), then onIdleState or onRunState with
 *      the idle/run/active/inactive flags posted on state transitions;
 *   3. the active behaviours' functions are solved (argmax of the weighted sum);
 *   4. behaviour postings are applied to the buffer and, through the duplicate filter,
 *      sent to the sink; then DESIRED_<VAR> (course -> DESIRED_HEADING), or zeros on
 *      all-stop, and the helm summary variables;
 *   5. the per-iteration value vectors are cleared.
 *
 * Not thread-safe; one thread owns a helm.
 */
#ifndef KELP_HELM_H
#define KELP_HELM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <kelp/config.h>
#include <kelp/cpa.h>
#include <kelp/err.h>
#include <kelp/ivp.h>
#include <kelp/mission.h>
#include <kelp/util.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ information buffer */

typedef struct kelp_helm_ibvar {
    char name[KELP_MAX_NAME];
    bool is_str;
    bool pending;              /**< arrived by mail; stamped at the next iteration start */
    double dval;
    double time;               /**< buffer time of the last write */
    char sval[KELP_HELM_MAX_SVAL];
} kelp_helm_ibvar;

typedef struct kelp_helm_ibdelta {
    uint16_t var;
    bool is_str;
    double dval;
    uint32_t soff;             /**< offset of the string in pool */
} kelp_helm_ibdelta;

/** The information buffer (InfoBuffer): latest value and write time of each variable the
 *  behaviours need, plus every value received since the last iteration. */
typedef struct kelp_helm_ib {
    double curr_time;          /**< buffer time, set once per iteration */
    unsigned nvar;
    kelp_helm_ibvar var[KELP_HELM_MAX_VARS];
    unsigned ndelta;
    kelp_helm_ibdelta delta[KELP_HELM_MAX_DELTAS];
    size_t npool;
    char pool[KELP_HELM_DELTA_POOL];
    unsigned long dropped;     /**< writes refused: buffer full or string too long */
} kelp_helm_ib;

void kelp_helm_ib_init(kelp_helm_ib *ib);
/** Write a value at buffer time t (also appended to the iteration's vectors when delta).
 *  KELP_ERR_NOSPACE when the buffer is full, KELP_ERR_RANGE for a too long string. */
KELP_MUST_CHECK int kelp_helm_ib_set_double(kelp_helm_ib *ib, const char *name, double v, double t, bool delta);
KELP_MUST_CHECK int kelp_helm_ib_set_string(kelp_helm_ib *ib, const char *name, const char *v, double t, bool delta);
/** Latest double (a numeric string counts, as getBufferDoubleVal). false if unknown. */
bool kelp_helm_ib_double(const kelp_helm_ib *ib, const char *name, double *out);
/** Latest value as a string (a double is formatted with %g precision 10). false if unknown. */
bool kelp_helm_ib_string(const kelp_helm_ib *ib, const char *name, char *buf, size_t cap);
/** Buffer time of the variable's last write; -1 if unknown (getBufferTimeVal). */
double kelp_helm_ib_time(const kelp_helm_ib *ib, const char *name);
/** Values received since the last iteration for name, oldest first: the k-th (from 0).
 *  Returns false past the end. *sval is NULL for a double. */
bool kelp_helm_ib_delta(const kelp_helm_ib *ib, const char *name, unsigned k, double *dval, const char **sval);
/** Number of values of name received since the last iteration. */
unsigned kelp_helm_ib_ndeltas(const kelp_helm_ib *ib, const char *name);
/** Forget the per-iteration values. */
void kelp_helm_ib_clear_deltas(kelp_helm_ib *ib);
/** Index of name, or -1. */
int kelp_helm_ib_find(const kelp_helm_ib *ib, const char *name);

/* ------------------------------------------------------------------ run conditions */

/** Check the syntax of a run condition. Grammar (the IvPBuild guide, MIT-CSAIL-TR-2009-037:
 *  "VAR = value", "(K <= 4)"; the rest is kelp's reading of what it leaves open):
 *    expr     := term { ("or" | "||") term }
 *    term     := factor { ("and" | "&&") factor }
 *    factor   := ("not" | "!") factor | "(" expr ")" | relation
 *    relation := operand op operand,  op := = | == | != | < | <= | > | >=
 *    operand  := "quoted string" | number | word | $(VAR)
 *  In a relation with two words the LEFT one is the variable and the right one a literal
 *  (DEPLOY = true); with one word and a number/string, the word is the variable ((4 > K));
 *  $(VAR) always names a variable. An unknown variable makes the relation false. Numbers
 *  compare numerically (a numeric string value counts); strings compare exactly, except that
 *  = and != between a value and the literal true/false ignore case. <,<=,>,>= on strings
 *  compare lexically. A bare word (no op) is not allowed.
 *  @param on_var called for each variable named (may be NULL). @return 0 or KELP_ERR_PARSE. */
KELP_MUST_CHECK int kelp_helm_cond_check(const char *cond, void (*on_var)(const char *var, size_t len, void *user),
                                         void *user);
/** Evaluate a condition against the buffer: 1 true, 0 false, KELP_ERR_PARSE. */
KELP_MUST_CHECK int kelp_helm_cond_eval(const char *cond, const kelp_helm_ib *ib);

/* ------------------------------------------------------------------ behaviours */

typedef struct kelp_bhv kelp_bhv;
typedef struct kelp_helm kelp_helm;

/** Activity states (Figure 3). NONE before the first iteration. */
typedef enum kelp_bhv_state {
    KELP_BHV_NONE = 0,
    KELP_BHV_IDLE,
    KELP_BHV_RUNNING,
    KELP_BHV_ACTIVE,
    KELP_BHV_COMPLETED
} kelp_bhv_state;

const char *kelp_helm_bhv_state_name(kelp_bhv_state s);

/** Storage a behaviour uses to build its function in onRunState. out/out_cap: pieces of the
 *  returned function (valid until the solve of this iteration). tmp, dwork, pq: scratch. */
typedef struct kelp_helm_work {
    kelp_ivp_piece *out;
    size_t out_cap;
    kelp_ivp_piece *tmp;
    size_t tmp_cap;
    double *dwork;
    size_t dwork_cap;
    kelp_ivp_pq_entry *pq;
    size_t pq_cap;
} kelp_helm_work;

/** A behaviour type: the overloadable functions (setParam, onIdleState, onRunState) plus a
 *  constructor. Helm-invoked immutable functions live in the helm. */
typedef struct kelp_bhv_ops {
    const char *type;                  /**< "BHV_SimpleWaypoint" (matched case-insensitively) */
    /** Constructor: defaults, subdomain of the helm domain, addInfoVars. May be NULL. */
    void (*init)(kelp_bhv *b);
    /** setParam: param is lower-cased (a leading '_' removed), value trimmed. 0 = accepted,
     *  <0 = not recognised or malformed. Called after the general parameters declined. */
    int (*set_param)(kelp_bhv *b, const char *param, const char *value);
    /** After the .bhv parameters and after each applied update (onSetParamComplete). <0 at
     *  startup refuses the configuration (with kelp_helm_bhv_fail's reason). May be NULL. */
    int (*params_done)(kelp_bhv *b);
    /** onIdleState. May be NULL. */
    void (*on_idle)(kelp_bhv *b);
    /** onRunState: 1 = *out holds a function built in w->out, 0 = no function. */
    int (*on_run)(kelp_bhv *b, const kelp_helm_work *w, kelp_ivp_func *out);
    /** postConfigStatus: post BHV_SETTINGS after configuration and each applied update. May be NULL. */
    void (*post_config)(kelp_bhv *b);
    /** onHelmStart: once at kelp_helm_start, for every behaviour and every spawn template (a
     *  template posts its BCM_ALERT_REQUEST here). May be NULL. */
    void (*on_helm_start)(kelp_bhv *b);
    /** onCompleteState: once, when the behaviour completes (kelp_helm_bhv_set_complete on a
     *  behaviour that is not perpetual: its duration ran out, or it completed itself). May be NULL. */
    void (*on_complete)(kelp_bhv *b);
} kelp_bhv_ops;

typedef enum kelp_bhv_flag_kind {
    KELP_FLAG_RUN = 0,
    KELP_FLAG_IDLE,
    KELP_FLAG_ACTIVE,
    KELP_FLAG_INACTIVE,
    KELP_FLAG_END,
    KELP_FLAG_RUNX,                    /**< runxflag: every iteration in the running state */
    KELP_FLAG_SPAWNX,                  /**< spawnx_flag: the behaviour's first helm iteration */
    KELP_FLAG_CONFIG,                  /**< configflag: once, on the first iteration after configuration */
    KELP_FLAG_SPAWN                    /**< spawnflag: when a template spawns the behaviour */
} kelp_bhv_flag_kind;

/** A variable-value pair (flags, initialize lines): a quoted or non-numeric value is a
 *  string, a number is a double (MOOS VarDataPair "auto"). */
typedef struct kelp_helm_pair {
    char var[KELP_MAX_NAME];
    bool is_str;
    double dval;
    char sval[KELP_HELM_MAX_FLAG_VAL];
} kelp_helm_pair;

typedef struct kelp_bhv_flag {
    kelp_bhv_flag_kind kind;
    kelp_helm_pair p;
} kelp_bhv_flag;

/* Built-in behaviour state. */
typedef struct kelp_bhv_pt { double x, y; } kelp_bhv_pt;

typedef struct kelp_bhv_swpt {         /* BHV_SimpleWaypoint (MIT-CSAIL-TR-2009-037 ch. 5) */
    kelp_bhv_pt nextpt;
    double desired_speed, arrival_radius;
    bool reflector;                    /* ipf_type */
    double osx, osy;
} kelp_bhv_swpt;

/** visual_hints of a behaviour's drawings (VIEW_SEGLIST, VIEW_POINT, VIEW_POLYGON). */
typedef struct kelp_bhv_hints {
    char vertex_color[24], edge_color[24], label_color[24], nextpt_color[24], nextpt_lcolor[24];
    double vertex_size, edge_size, nextpt_vertex_size;
} kelp_bhv_hints;

typedef struct kelp_bhv_wpt {          /* BHV_Waypoint */
    kelp_bhv_pt pts[KELP_HELM_MAX_PTS];
    unsigned npts;
    unsigned char init;                /* points = empty (1) or start (2): no points on purpose */
    double speed, capture_radius, slip_radius, lead, lead_damper;
    double speed_alt;                  /* speed_alt (used with use_alt_speed), <0 unset */
    double course_pct;                 /* crs_spd_zaic_ratio: course share of the coupling, 1..99 */
    long repeat;                       /* extra passes through the list; <0 forever */
    bool reverse;
    bool lead_to_start;                /* lead on the first leg from where the vehicle started */
    bool use_alt_speed;
    bool capture_line;                 /* crossing the line through the point, square to the leg */
    bool efficiency;                   /* efficiency_measure = all */
    bool wpt_flag_on_start;            /* wptflag_on_start: the wptflags also when it first runs */
    bool reset_on_idle;                /* reset_on_idle: back to the first point when it goes idle */
    bool eager_prev;                   /* eager_prev_index_flag: $(PI) set as the flags post */
    char lead_cond[2][KELP_HELM_MAX_COND_LEN]; /* lead_condition: lead steering only while all hold */
    double slow_dist, stop_dist;       /* end_spd: slow down from slow_dist to stop at stop_dist (to the end; <0 off) */
    bool greedy_pending;               /* greedy_tour: reorder the points nearest-first at the next run */
    unsigned nlead_cond;
    kelp_bhv_flag cycleflag[4], wptflag[4];
    unsigned ncycleflag, nwptflag;
    char var_report[KELP_MAX_NAME];    /* WPT_STAT (wpt_status_var), "silent" */
    char var_index[KELP_MAX_NAME];     /* WPT_INDEX (wpt_index_var), "silent" */
    char var_cyindex[KELP_MAX_NAME];   /* CYCLE_INDEX (cycle_index_var), "silent" */
    char var_dist_prev[KELP_MAX_NAME]; /* wpt_dist_to_prev, "" off */
    char var_dist_next[KELP_MAX_NAME]; /* wpt_dist_to_next, "" off */
    char suffix[24];                   /* post_suffix ("_" added) */
    kelp_bhv_hints hints;              /* visual_hints */
    /* state */
    unsigned index;                    /* next point */
    unsigned long cycles;              /* completed passes */
    unsigned long cycles_posted;       /* the CYCLE_INDEX last posted (0 before any) */
    unsigned long captured, slipped;   /* arrivals by capture / by slip radius (a capture line's: neither) */
    unsigned long repeats_done;        /* passes counted against repeat (24.8's repeats so far) */
    bool wpt_flag_published;           /* the wptflags went out at least once */
    int prev_index;                    /* $(PI): the previous point's index, -1 none */
    kelp_bhv_pt nextpt;                /* $(NX), $(NY): the point steered for (0,0 before any) */
    bool have_prev;                    /* trackline start known */
    kelp_bhv_pt prev;                  /* start of the current leg */
    bool have_mark;                    /* where the vehicle was when the first leg began */
    kelp_bhv_pt mark;
    double min_dist;                   /* closest approach to the current point so far */
    bool restart;                      /* re-seed the leg at the next run (idle->run) */
    double osx, osy, osh;              /* ownship: NAV_X, NAV_Y, NAV_HEADING (0..360) */
    /* odometry (WPT_ODO, efficiency_measure) */
    bool odo_virgin;
    bool odo_set, odo_disq;            /* a leg's start is marked; the next mark only marks */
    double odo_px, odo_py, odo_leg, odo_setx, odo_sety, odo_settime;
    double eff_linear, eff_odo;        /* sums over measured legs: straight-line and travelled metres */
    double eff_tlinear, eff_todo;      /* ... and seconds (straight line at cruise speed; taken) */
} kelp_bhv_wpt;

typedef struct kelp_bhv_loiter {       /* BHV_Loiter (MOOS-IvP 24.8's, with its loiter and waypoint engines) */
    kelp_bhv_pt pts[KELP_HELM_MAX_PTS];  /* the polygon in visiting order (clockwise or not), 0.1 m snapped */
    signed char side[KELP_HELM_MAX_PTS]; /* edge i -> i+1: the side the other vertices lie on (0/1; -1 mixed) */
    unsigned npts;
    bool convex;
    /* configuration */
    double speed, speed_alt;           /* speed_alt (with use_alt_speed) when >= 0 */
    double capture_radius, slip_radius, acquire_dist;
    double patience;                   /* the course function's share of the coupling, 1..99 (50) */
    double slingshot;                  /* complete after this many degrees of bearing change; < 0 off */
    double spiral_factor;              /* bonus (negative) of the vertex ahead when acquiring from inside */
    bool clockwise, dynamic_clockwise, center_activate, use_alt_speed;
    bool zaic_spd;                     /* ipf_type = zaic_spd: the speed function is ZAIC_SPD's */
    kelp_bhv_hints hints;              /* visual_hints (label_color "" = not set) */
    char poly_label[KELP_MAX_NAME];    /* visual_hints label= (the drawing's label; "" = <us>_<name>) */
    char spec_label[KELP_MAX_NAME];    /* the polygon spec's own label= (in BHV_SETTINGS) */
    char suffix[24];                   /* post_suffix: "_" and the value upper-cased */
    char center_assign[KELP_HELM_MAX_FLAG_VAL]; /* a pending centre: present_position, "x,y", "x=..,y=.." */
    bool center_pending;
    /* state */
    unsigned index;                    /* the vertex steered for (the waypoint engine's current index) */
    double cpa;                        /* closest approach to it so far; < 0: none yet */
    unsigned long capture_hits, nonmono_hits;
    bool acquire;                      /* acquire mode (true until a vertex is reached) */
    unsigned char mode;                /* idle, stable, acquiring_/recovering_ external/internal */
    double dist_to_poly, eta_to_poly;  /* inside: a negative distance */
    double ptx, pty;                   /* the vertex steered for */
    double osx, osy, osh, osv;         /* ownship at the last update */
    double bng_total, bng_last;        /* slingshot: bearing change to the centre; last bearing (-1 none) */
} kelp_bhv_loiter;

#define KELP_BHV_AVD_MAX_FILTER 4      /* match_/ignore_ name, type, group entries of each kind */
#define KELP_BHV_AVD_MAX_REGION 2      /* match_/ignore_region polygons */
#define KELP_BHV_AVD_MAX_LINES 4       /* bearing_lines colour:threshold entries */
#define KELP_BHV_AVD_MAX_CNFLAGS 4     /* cnflag lines */

/** Contact state a contact behaviour works with (from the helm's ledger). */
typedef struct kelp_helm_contact {
    char name[KELP_MAX_NAME];
    char type[KELP_MAX_NAME];
    char group[KELP_MAX_NAME];
    double x, y, hdg, spd;
    double utc;                        /**< the report's TIME (MOOS time); -1 when absent */
    double seen;                       /**< buffer time it arrived */
} kelp_helm_contact;

typedef struct kelp_bhv_avoid {        /* BHV_AvoidCollision (MOOS-IvP's parameters and defaults) */
    char contact[KELP_MAX_NAME];
    double pwt_outer_dist, pwt_inner_dist, completed_dist;
    double min_util_cpa_dist, max_util_cpa_dist;
    int pwt_grade;                     /* 0 linear, 1 quadratic, 2 quasi (power 1.5) */
    double roc_max_dampen, roc_max_heighten;   /* accepted; kelp does not use them */
    double time_on_leg;                /* CPA horizon of the objective function, s */
    double decay_start, decay_end;     /* extrapolation decay */
    double collision_depth, pcheck_thresh;
    bool extrapolate, on_no_contact_ok, post_per_contact_info, no_alert_request;
    bool bearing_line_show, bearing_line_label_show, bearing_info_range;
    bool use_refinery, check_plateaus, check_validity, verbose, can_disable, use_plat_model;
    bool exit_on_filter_vtype, exit_on_filter_group, exit_on_filter_region;
    int strict_ignore;                 /* -1 unset, 0, 1 */
    char match_name[KELP_BHV_AVD_MAX_FILTER][KELP_MAX_NAME], ignore_name[KELP_BHV_AVD_MAX_FILTER][KELP_MAX_NAME];
    char match_type[KELP_BHV_AVD_MAX_FILTER][KELP_MAX_NAME], ignore_type[KELP_BHV_AVD_MAX_FILTER][KELP_MAX_NAME];
    char match_group[KELP_BHV_AVD_MAX_FILTER][KELP_MAX_NAME], ignore_group[KELP_BHV_AVD_MAX_FILTER][KELP_MAX_NAME];
    unsigned nmatch_name, nignore_name, nmatch_type, nignore_type, nmatch_group, nignore_group;
    char match_region[KELP_BHV_AVD_MAX_REGION][KELP_HELM_MAX_FLAG_VAL];
    char ignore_region[KELP_BHV_AVD_MAX_REGION][KELP_HELM_MAX_FLAG_VAL];
    unsigned nmatch_region, nignore_region;
    char line_color[KELP_BHV_AVD_MAX_LINES][24];
    double line_thresh[KELP_BHV_AVD_MAX_LINES];
    unsigned nlines;
    char cnflag[KELP_BHV_AVD_MAX_CNFLAGS][KELP_HELM_MAX_FLAG_VAL];
    unsigned ncnflag;
    /* state of the last update */
    kelp_helm_contact cn;              /* the contact, position extrapolated */
    double osx, osy, osh, osv;
    double range, relevance, roc;
    double prev_range;                 /* the range at the update before (cnflag @< / @>) */
    bool have_range;
    bool nav_warned;
} kelp_bhv_avoid;

#define KELP_SKEEP_HIST 240           /**< BHV_StationKeep's distance history: 10 s of iterations up to 24 Hz */
typedef struct kelp_bhv_skeep {       /* BHV_StationKeep (MOOS-IvP 24.8's) */
    double station_x, station_y;       /**< the station in use */
    double static_x, static_y;         /**< station_pt / point */
    bool static_defined, center_activate, center_pending, station_set, was_running;
    double outer_radius, inner_radius, outer_speed, extra_speed, pskeep_radius, swing_time;
    double dist, mark_time, osx, osy, osh;
    uint8_t pskeep_state, transit_state; /**< hibernation and transit states (bhv_skeep.c) */
    char vertex_color[24], edge_color[24], label_color[24];
    double vertex_size, edge_size;
    double hist_d[KELP_SKEEP_HIST], hist_t[KELP_SKEEP_HIST]; /**< distance history, a ring */
    unsigned hist_n, hist_head;        /**< entries; index of the newest */
} kelp_bhv_skeep;

typedef struct kelp_bhv_c1 {           /* BHV_ConstantDepth / ConstantSpeed / ConstantHeading */
    double value, peakwidth, basewidth, summitdelta;
    bool have_value;
    char mismatch_var[KELP_MAX_NAME];  /* depth/speed/heading_mismatch_var: |desired - actual| */
    double complete_thresh;            /* heading: complete within this many degrees (0 off) */
} kelp_bhv_c1;

/** One behaviour instance (IvPBehavior plus its subclass state). Members are public for
 *  tests and reports; change them through the functions below. */
struct kelp_bhv {
    const kelp_bhv_ops *ops;
    kelp_helm *helm;
    int line;                          /**< .bhv line of the Behavior block (0 if built in code) */
    char type[KELP_MAX_NAME];
    char name[KELP_MAX_NAME];
    char us[KELP_MAX_NAME];            /**< vehicle name (MOOS "us", default: helm's) */
    double pwt;                        /**< priority weight, default 100 */
    double pwt_factor;                 /**< set by on_run to scale pwt for this function (reset to 1) */
    bool ipf_gel_set;                  /**< on_run built its function with the Reflector: BHV_IPF's */
    int32_t ipf_gel[KELP_IVP_MAX_DIM]; /**< grid element box is its uniform piece (extent - 1) */
    kelp_ivp_domain dom;               /**< behaviour's (sub)domain; dim 0 = null */
    char cond[KELP_HELM_MAX_CONDS][KELP_HELM_MAX_COND_LEN];
    unsigned ncond;
    int failed_cond;                   /* the condition that kept it idle this iteration, -1 none */
    kelp_bhv_flag flag[KELP_HELM_MAX_FLAGS];
    unsigned nflag;
    unsigned long bhv_iter;            /**< helm iterations this behaviour has been through */
    char templating[12];               /**< "disallowed" (default), "clone" or "spawn" */
    unsigned long max_spawnings;       /**< a template's limit on spawns made (0: none) */
    unsigned long spawns_made, spawns_tried;   /**< a template's counts */
    bool spawned;                      /**< made from a template at run time */
    char spawn_base[KELP_MAX_NAME];    /**< the template's name ("avd_") when spawned */
    uint32_t uid;                      /**< helm-unique instance number (duplicate filter owner) */
    char build_info[64];               /**< build_info / precision (accepted, recorded) */
    char updates[KELP_MAX_NAME];       /**< UPDATES variable, "" none */
    uint64_t prev_update_hash;         /**< last fully applied update string */
    unsigned long good_updates, bad_updates;
    char update_summary[48];           /**< "good/attempted" for BHV_STATUS, "n/a" without UPDATES */
    double duration;                   /**< <0: no limit */
    char duration_status[KELP_MAX_NAME];
    char duration_reset_var[KELP_MAX_NAME];
    char duration_reset_val[KELP_HELM_MAX_FLAG_VAL];
    bool duration_idle_decay;          /**< default true */
    bool perpetual;
    char starve[KELP_HELM_MAX_INFOVARS][KELP_MAX_NAME];
    unsigned nstarve;
    double starve_time;                /**< NOSTARVE seconds */
    char map_from[KELP_HELM_MAX_MAPPINGS][KELP_MAX_NAME];
    char map_to[KELP_HELM_MAX_MAPPINGS][KELP_MAX_NAME];
    unsigned nmap;
    char infovars[KELP_HELM_MAX_INFOVARS][KELP_MAX_NAME];
    unsigned ninfovars;
    /* run state */
    kelp_bhv_state state;              /**< state reported for the last iteration */
    bool completed;                    /**< setComplete() was called (not perpetual) */
    bool death_posted;                 /**< its IVPHELM_LIFE_EVENT death went out */
    bool state_ok;                     /**< cleared by postEMessage for this iteration */
    double state_entered;              /**< buffer time the current state began */
    bool dur_started;
    double dur_start, dur_idle_time, dur_prev_time, dur_reset_stamp;
    double dur_run_total, dur_idle_total; /**< $[DUR_RUN_TIME] / $[DUR_IDLE_TIME]: time running / idle since the start or a duration reset */
    bool dur_have_prev;
    const char *fail;                  /**< reason of a rejected parameter (first wins) */
    union {
        kelp_bhv_swpt swpt;
        kelp_bhv_wpt wpt;
        kelp_bhv_loiter loiter;
        kelp_bhv_c1 c1;
        kelp_bhv_avoid avoid;
        kelp_bhv_skeep skeep;
        double raw[64];                /**< for behaviour types outside kelp (cast it) */
    } u;
};

/* ---- implementor-invoked utilities (section 4.5.1) ---- */

/** Post end flags (and inactive flags); completed from the next iteration unless perpetual
 *  (then the type's on_complete runs, once). */
void kelp_helm_bhv_set_complete(kelp_bhv *b);
/** addInfoVars("NAV_X, NAV_Y"): one or comma-separated; duplicates ignored. <0 when full. */
KELP_MUST_CHECK int kelp_helm_bhv_add_info_vars(kelp_bhv *b, const char *names);
bool kelp_helm_bhv_buf_double(const kelp_bhv *b, const char *var, double *out);
bool kelp_helm_bhv_buf_string(const kelp_bhv *b, const char *var, char *buf, size_t cap);
double kelp_helm_bhv_buf_time(const kelp_bhv *b, const char *var);
double kelp_helm_bhv_buf_now(const kelp_bhv *b);
unsigned kelp_helm_bhv_buf_ndeltas(const kelp_bhv *b, const char *var);
bool kelp_helm_bhv_buf_delta(const kelp_bhv *b, const char *var, unsigned k, double *dval, const char **sval);
/** postMessage: queued for the end of the iteration. key NULL/"" = default key; "repeatable"
 *  bypasses the duplicate filter. post_mapping applies (a mapping to "silent" drops it). */
void kelp_helm_bhv_post_string(kelp_bhv *b, const char *var, const char *val, const char *key);
void kelp_helm_bhv_post_double(kelp_bhv *b, const char *var, double val, const char *key);
void kelp_helm_bhv_post_bool(kelp_bhv *b, const char *var, bool val, const char *key);
/** postIntMessage: rounded to the nearest integer (2.6 -> 3, -2.6 -> -3). */
void kelp_helm_bhv_post_int(kelp_bhv *b, const char *var, double val, const char *key);
/** postWMessage: BHV_WARNING = "<name>: <msg>" (repeatable). */
void kelp_helm_bhv_post_warning(kelp_bhv *b, const char *msg);
/** postRetractWMessage: BHV_WARNING = "<name>: <msg>" withdrawing that warning. 24.8 posts the
 *  text as a BHV_WARNING too, once per behaviour and text (its "retract" key), and counts no
 *  warning for it. */
void kelp_helm_bhv_post_retract(kelp_bhv *b, const char *msg);
/** postEMessage: BHV_ERROR = "<name>: <msg>" (repeatable); state_ok=false -> helm all-stop. */
void kelp_helm_bhv_post_error(kelp_bhv *b, const char *msg);
/** Record why a parameter was refused (first wins) and return KELP_ERR_PARSE. */
KELP_MUST_CHECK int kelp_helm_bhv_fail(kelp_bhv *b, const char *why);

/** setParam as the helm applies it: general parameters (section 4.2) first, then the type's.
 *  param is matched case-insensitively. 0 or <0 (b->fail says why). b must belong to a helm
 *  (kelp_helm_add): the trimmed value is kept in the helm's ws_param (KELP_ERR_ARG otherwise). */
KELP_MUST_CHECK int kelp_helm_bhv_set_param(kelp_bhv *b, const char *param, const char *value);

/** relAng: compass bearing from (xa,ya) to (xb,yb) in [0,360): 0 = +y, 90 = +x; 0 if equal. */
double kelp_helm_relang(double xa, double ya, double xb, double yb);
/** Parse a MOOS point list into pts: "x,y:x,y", "pts={x,y:x,y}", "{x,y:...}", "(x,y)",
 *  "x=1,y=2", or a regular polygon "format=radial, x=, y=, radius=, pts=[, snap=]" (also
 *  "radial:: x=, ..." and the short "radial: x, y, radius, pts[, snap]"), laid out as MOOS-IvP
 *  24.8 does: the first vertex half a step clockwise of north of the centre (22.5 degrees for
 *  8), then clockwise. A radius without format=radial is KELP_ERR_UNSUPPORTED (24.8 reads no
 *  polygon from it). */
KELP_MUST_CHECK int kelp_helm_parse_points(const char *s, kelp_bhv_pt *pts, size_t cap, unsigned *n);

/** The built-in behaviour types (BHV_SimpleWaypoint, BHV_Waypoint, BHV_Loiter,
 *  BHV_ConstantDepth, BHV_ConstantSpeed, BHV_ConstantHeading, BHV_AvoidCollision),
 *  NULL-terminated. */
extern const kelp_bhv_ops *const kelp_bhv_builtin_types[];
extern const kelp_bhv_ops kelp_bhv_simple_waypoint_ops;
extern const kelp_bhv_ops kelp_bhv_waypoint_ops;
extern const kelp_bhv_ops kelp_bhv_loiter_ops;
extern const kelp_bhv_ops kelp_bhv_constant_depth_ops;
extern const kelp_bhv_ops kelp_bhv_constant_speed_ops;
extern const kelp_bhv_ops kelp_bhv_constant_heading_ops;
extern const kelp_bhv_ops kelp_bhv_avoid_collision_ops;
extern const kelp_bhv_ops kelp_bhv_station_keep_ops;
/** BHV_AvoidCollision's objective at (course, speed): CPA range within the horizon mapped to
 *  utility 0 at or inside min_util_cpa_dist, 100 at or beyond max_util_cpa_dist, linear between. */
#ifndef KELP_BHV_AVD_UNITS
#define KELP_BHV_AVD_UNITS 360 /**< course points whose unit vectors AvoidCollision keeps between builds */
#endif
typedef struct kelp_bhv_avoid_aof {
    kelp_cpa_fast cpa;
    double min_util, max_util;
    int icrs, ispd;
    /* private: unit[2 i], unit[2 i + 1] is kelp_cpa_unit of course i * unit_delta + unit_low
     * (i < unit_n), kept from build to build: every instance's objective is set up in the
     * helm's one workspace, so the trigonometry is done once per course domain */
    uint32_t unit_n;
    double unit_low, unit_delta;
    double unit[2 * KELP_BHV_AVD_UNITS];
} kelp_bhv_avoid_aof;
double kelp_helm_bhv_avoid_aof_eval(const double *pt, void *user);
/** Priority factor at range: 0 at or beyond outer, 1 at inner, graded by (outer - range) /
 *  (outer - inner) (grade 0 linear, 1 quadratic, 2 quasi = power 1.5), that fraction going on
 *  past 1 inside inner as MOOS-IvP's getRelevance; 1 when outer <= inner. */
double kelp_helm_bhv_avoid_relevance(double range, double inner, double outer, int grade);

/** The AOF_SimpleWaypoint objective (0..100) at (course, speed) for the reflector build. */
typedef struct kelp_bhv_swpt_aof {
    double desired_speed, osx, osy, ptx, pty;
    double angle_to_wpt, min_speed, max_speed;
    int icrs, ispd;                    /* indices of course and speed in the domain */
} kelp_bhv_swpt_aof;
double kelp_helm_bhv_swpt_aof_eval(const double *pt, void *user);

/* ------------------------------------------------------------------ the helm */

/** One posting leaving the helm. aux: "<iter>:<behaviour>" for behaviour posts, else NULL. */
typedef struct kelp_helm_post {
    const char *var;
    bool is_str;
    const char *sval;
    double dval;
    const char *aux;
    bool retract; /**< a BHV_WARNING that withdraws an earlier one (MOOS-IvP's postRetractWMessage):
                       posted as the warning's text, not counted as a warning */
} kelp_helm_post;

typedef void (*kelp_helm_sink)(const kelp_helm_post *p, void *user);

/** Headings kept for TURN_RATE (the last 5 s of iterations: 25 Hz fits) */
#ifndef KELP_HELM_HDG_HIST
#define KELP_HELM_HDG_HIST 128
#define KELP_HELM_IPF_PACKET 2000 /**< size of a BHV_IPF packet (24.8's HelmIvP) */
#endif
#define KELP_HELM_TURN_WINDOW 5.0 /**< s of heading history TURN_RATE averages (PlatModelGenerator) */

typedef struct kelp_helm_config {
    kelp_ivp_domain domain;            /**< the helm's IvP domain (Domain = lines) */
    bool optional[KELP_IVP_MAX_DIM];   /**< ":optional" domain variables (no all-stop if undecided) */
    char us[KELP_MAX_NAME];            /**< vehicle (community) name */
    bool start_engaged;                /**< start in DRIVE (start_engaged, start_in_drive); default
                                            false: PARK until MOOS_MANUAL_OVERRIDE = false (24.8) */
    bool allow_park;                   /**< an override may park the helm (default true) */
    bool park_on_allstop;              /**< park when the decision is an all-stop (default false) */
    char other_override[KELP_MAX_NAME];/**< another variable read like MOOS_MANUAL_OVERRIDE ("" none) */
    kelp_helm_sink sink;
    void *user;
    const kelp_bhv_ops *const *types;  /**< NULL-terminated list; NULL = kelp_bhv_builtin_types */
    /** Optional CPU clock (seconds) the helm reads around building and solving, for
     *  IVPHELM_CREATE_CPU / IVPHELM_LOOP_CPU and the summary's times; NULL: not measured. */
    double (*cpu_clock)(void *user);
} kelp_helm_config;

void kelp_helm_config_default(kelp_helm_config *cfg);
/** Add one "Domain = name:low:high:points[:optional]" line to cfg. @return 0, or <0 with the
 *  reason in d (NULL allowed). */
KELP_MUST_CHECK int kelp_helm_config_add_domain(kelp_helm_config *cfg, const char *spec, kelp_diag *d);

/** Storage of one helm: pieces of all functions of one iteration (pool), scratch pieces,
 *  doubles and priority-queue entries for builders, and the solver's work. A Reflector
 *  function of 1000 pieces needs ~1100 pool pieces and as many pq entries; a ZAIC function
 *  needs tmp/dwork of the variable's point count. */
typedef struct kelp_helm_mem {
    kelp_ivp_piece *pool;
    size_t pool_cap;
    kelp_ivp_piece *tmp;
    size_t tmp_cap;
    double *dwork;
    size_t dwork_cap;
    kelp_ivp_pq_entry *pq;
    size_t pq_cap;
    void *solve_work;
    size_t solve_work_size;
} kelp_helm_mem;

typedef struct kelp_helm_filter_entry {
    uint64_t key, val;
    uint32_t owner;                    /* uid of the posting behaviour (0: the helm) */
} kelp_helm_filter_entry;

typedef struct kelp_helm_qpost {
    uint16_t bhv;
    bool is_str, repeatable;
    double dval;
    uint32_t var, sval, key;            /* offsets into the post pool */
} kelp_helm_qpost;

/** The last iteration's outcome. */
typedef struct kelp_helm_report {
    unsigned long iteration;
    double time;                       /**< buffer time */
    unsigned ofnum;                    /**< functions solved */
    bool halted;                       /**< a behaviour error (state_ok false) */
    bool decided[KELP_IVP_MAX_DIM];
    double decision[KELP_IVP_MAX_DIM]; /**< per helm domain variable */
    char allstop[96];                  /**< "clear", "NothingToDo", "BehaviorError", "ManualOverride", "MissingDecVars:x" */
    unsigned nactive, nrunning, nidle, ncompleted;
    unsigned long warnings;            /**< BHV_WARNING posts so far */
    unsigned long errors;              /**< BHV_ERROR posts so far */
    double create_time, solve_time, loop_time;          /**< CPU seconds this iteration (cpu_clock) */
    double max_create_time, max_solve_time, max_loop_time;
    unsigned long pcs_formed;          /**< pieces of this iteration's functions */
    unsigned long total_pcs_formed;    /**< ... summed over all iterations */
    bool active_goal;                  /**< a goal (non-constraint) behaviour produced a function */
    char halt_msg[KELP_HELM_MAX_SVAL / 2]; /**< why the helm halted: "BHV_ERROR: ...", "DomainVar x not recognized" */
} kelp_helm_report;

/** One hierarchical mode declaration of a .bhv file:
 *
 *     set MODE = SURVEYING {
 *       MODE = ACTIVE            <- a condition on the mode variable: the prefix "ACTIVE"
 *       RETURN != true
 *     } RETURNING                <- the else value
 *
 * Entries are evaluated in file order every iteration: all conditions true gives the value,
 * otherwise the conditions on the mode variable alone true gives the else value (if any); a
 * result is prefixed "PREFIX:" and is seen by the entries after it, so the last result wins
 * ("ACTIVE:SURVEYING"). */
/** What the last IVPHELM_SUMMARY showed (HelmReport's previous report): a hash per field */
typedef struct kelp_helm_sumprev {
    bool valid;                        /**< a summary was posted */
    bool cmpl_nonempty;                /**< its completed list was not empty */
    uint64_t h[20];
} kelp_helm_sumprev;

typedef struct kelp_helm_mode {
    char var[KELP_MAX_NAME];
    char val[KELP_MAX_NAME];
    char elseval[KELP_MAX_NAME];
    char prefix[128];
    char cond[KELP_HELM_MAX_CONDS][KELP_HELM_MAX_COND_LEN];
    unsigned ncond;
    uint32_t modevar_conds;            /**< bit i: cond[i] is the prefix condition */
} kelp_helm_mode;

struct kelp_helm {
    kelp_helm_config cfg;
    kelp_helm_mem mem;
    kelp_helm_ib ib;
    kelp_bhv bhv[KELP_HELM_MAX_BHVS];
    unsigned nbhv;
    /* templates (templating = spawn): configured, never run; instances are copies of them */
    kelp_bhv tmpl[KELP_HELM_MAX_TEMPLATES];
    unsigned ntmpl;
    unsigned nspawned;                 /**< spawned instances alive */
    unsigned long bhv_cnt_ever;        /**< behaviours instantiated ever (IVPHELM_BHV_CNT_EVER) */
    unsigned long spawn_refused;       /**< spawns refused by KELP_HELM_MAX_SPAWNED / _BHVS */
    unsigned long completed_removed;   /**< spawned behaviours removed after completing */
    uint32_t next_uid;
    /* contact ledger from NODE_REPORT mail */
    kelp_helm_contact ledger[KELP_HELM_MAX_CONTACTS];
    unsigned ncontacts;
    kelp_helm_pair init[KELP_HELM_MAX_INIT];
    bool init_defer[KELP_HELM_MAX_INIT];
    unsigned ninit;
    /* variables the helm needs (registration list) */
    char need[KELP_HELM_MAX_VARS][KELP_MAX_NAME];
    unsigned nneed, nneed_reported;
    /* IVPHELM_REGISTER at run time (24.8's registerNewVariables): need[i] posted as one of the
     * behaviours' information variables; the behaviour count (ever) at the last walk, plus 1 */
    uint8_t info_posted[KELP_HELM_MAX_VARS];
    unsigned long info_walked;
    /* postings of the current iteration */
    kelp_helm_qpost q[KELP_HELM_MAX_POSTS];
    unsigned nq;
    size_t qpool_used;
    char qpool[KELP_HELM_POST_POOL];
    unsigned long posts_dropped;
    kelp_helm_filter_entry filter[KELP_HELM_MAX_FILTER];
    unsigned nfilter;
    bool engaged;
    bool started;
    double t0;                      /* MOOS time of helm time 0; moved by a clock step (below) */
    kelp_clock clock;               /* the newest `now`, to tell a clock step */
    unsigned long clock_steps;      /* clock steps taken out of helm time */
    unsigned long iteration;        /* every call of kelp_helm_iterate */
    unsigned long dec_iter;         /* 24.8's helm iteration: the decisions made (engaged loops) */
    double first_iter_time;         /* helm time of the first iteration (life events' time=) */
    bool startup_events_pending;    /* the behaviours' spawn events, posted by the first decision */
    bool config_pending;            /* the behaviours' start-up settings, posted by the first decision */
    kelp_helm_sumprev sum;          /* the last IVPHELM_SUMMARY's fields */
    bool rejournal;                 /* IVPHELM_REJOURNAL: the next summary in full */
    kelp_helm_report rep;
    kelp_ivp_func fn[KELP_HELM_MAX_BHVS];   /* functions of the current iteration */
    kelp_ivp_problem prob;
    char last_lists[3][256];           /* last IVPHELM_BHV_ACTIVE / RUNNING / IDLE posted */
    unsigned no_decisions;             /* iterations in a row with NothingToDo / MissingDecVars */
    char updatevars_posted[256];       /* IVPHELM_UPDATEVARS last posted ("": none yet) */
    unsigned statevars_posted;         /* names in the IVPHELM_STATEVARS last posted */
    char allstop_posted[96];           /* the all-stop reason last posted ("" at start): posted again only when it changes */
    unsigned long ledger_reports;      /* NODE_REPORTs taken into the ledger (IVPHELM_LEDGER_SUMMARY reps) */
    double hdg_t[KELP_HELM_HDG_HIST], hdg_v[KELP_HELM_HDG_HIST]; /* TURN_RATE's heading history, a ring */
    unsigned hdg_n, hdg_head;          /* entries, index of the newest */
    unsigned ncompleted_seen;          /* behaviours marked completed at the last count */
    int completed_pending_posted;      /* IVPHELM_COMPLETED_PENDING last posted: -1 none, 0, 1 */
    unsigned completed_count_posted;   /* IVPHELM_COMPLETED_COUNT last posted (0 at start) */
    kelp_helm_mode modes[KELP_HELM_MAX_MODES];
    unsigned nmodes;
    char mode_posted[KELP_HELM_MAX_MODES][128]; /* last value posted per mode variable (by first entry) */
    char mode_summary[KELP_HELM_MAX_SVAL];      /* "MODE@ACTIVE:SURVEYING#MODE2@X" after the iteration */
    unsigned last_cnt[5];              /* last IVPHELM_BHV_CNT, IVPHELM_BHV_CNT_EVER posted (0: none); [2] the
                                          start-up zeros of the list counts posted */
    kelp_diag diag;                    /**< configuration failure (first wins): code, .bhv line, reason */
    struct {                        /* workspace of one iteration's postings (keeps the stack small) */
        char buf[KELP_HELM_MAX_SVAL], dom[KELP_HELM_MAX_SVAL / 2];
        char lists[4][256], tmp[256];
        char status[KELP_HELM_MAX_SVAL]; /**< a BHV_STATUS text */
        char mode_value[KELP_HELM_MAX_MODES][128]; /**< this iteration's value of each mode variable */
    } ws_out;
    char ws_ipf[KELP_MAX_SVAL + 1];    /* workspace: one BHV_IPF string */
    char ws_ipf_pkt[KELP_HELM_IPF_PACKET + 1]; /* workspace: one BHV_IPF packet */
    kelp_helm_work ws_work;            /* workspace: the storage handed to a behaviour's on_run */
    unsigned long ipf_posted, ipf_oversize; /**< BHV_IPF postings; functions too long for one value */
    struct {                        /* workspace of a behaviour's updates (keeps the stack small) */
        char val[KELP_HELM_MAX_SVAL], bad[KELP_HELM_MAX_SVAL - 128], msg[KELP_HELM_MAX_SVAL];
        char param[KELP_MAX_NAME];
    } ws_upd;
    /** workspace of kelp_helm_bhv_set_param (the trimmed value; keeps the stack small): a behaviour's
     *  set_param must not call kelp_helm_bhv_set_param again */
    char ws_param[KELP_HELM_MAX_SVAL];
    char ws_pname[KELP_MAX_NAME];      /**< ... and the lower-cased parameter name */
    /** workspace of kelp_helm_load_bhv: a behaviour's type, then each of its parameters' names
     *  (one at a time; keeps the stack small) */
    char ws_key[KELP_MAX_NAME];
    /** workspace of a flag's value with its macros expanded (keeps the stack small) */
    char ws_flag[KELP_HELM_MAX_SVAL];
    /** workspace of the macro expansion: a number formatted for $[PWT] / $[UTC] */
    char ws_macro[48];
    /** workspace of the general parameters' VAR=value checks (kelp_helm_bhv_set_param) */
    kelp_helm_pair ws_pair;
    /** workspace of the solve: the sub-domain the objective functions span */
    kelp_ivp_domain ws_sub;
    /** workspace of an iteration: which behaviours produced an objective function */
    bool ws_has_fn[KELP_HELM_MAX_BHVS];
    /** workspace of a spawn: the requested name and the instance's full name */
    char ws_spawn_name[2][KELP_MAX_NAME];
    /** workspace of the built-in behaviours (keeps the stack small, as the firmware's 1 KB
     *  bound on every path through the behaviour tables needs). One behaviour callback runs
     *  at a time and none of them re-enters the helm; each member belongs to the one function
     *  named, so a member is never in use twice at once. */
    struct {
        kelp_ivp_zaic_peak zaic;               /* bhv_zaic1: the ZAIC being built */
        char zaic_msg[KELP_IVP_MAX_WARN + 48]; /* bhv_zaic1: its warning */
        kelp_ivp_func cs[2];                   /* bhv_course_speed_zaic_ratio: speed and course */
        char msg[KELP_HELM_MAX_SVAL];          /* kelp_helm_bhv_post_warning / _error: "name: msg" */
        kelp_ivp_reflector refl;               /* a behaviour's Reflector (SimpleWaypoint, AvoidCollision) */
        kelp_bhv_avoid_aof avd_aof;            /* build (AvoidCollision): the objective refl samples */
        kelp_bhv_swpt_aof swpt_aof;            /* build_reflector (SimpleWaypoint): the same */
        kelp_bhv_pt pts[KELP_HELM_MAX_PTS];    /* a polygon or point list being parsed or tested */
        /* The posting helpers of a behaviour callback (post_polygon, post_stat, ...) compose in
         * these one after another: the helm copies each posting when it is queued, so a helper
         * is done with them when it returns, and none calls another while it holds them. */
        char post[KELP_HELM_MAX_SVAL];         /* a posting being composed by a behaviour callback */
        char post2[KELP_HELM_MAX_SVAL / 2];    /* ... a second part of it */
        char num[12][32];                      /* ... numbers formatted for it */
        char var[KELP_MAX_NAME + 24];          /* ... the variable it goes to (a name + post_suffix) */
        kelp_helm_pair pair;                   /* contact_flags (AvoidCollision): a cnflag's VAR=value */
    } ws_bhv;
};

/** Initialise an empty helm. The storage in mem must outlive the helm. */
KELP_MUST_CHECK int kelp_helm_init(kelp_helm *h, const kelp_helm_config *cfg, const kelp_helm_mem *mem);
/** Instantiate a behaviour of a registered type (constructor run). KELP_ERR_NOTFOUND for an
 *  unknown type, KELP_ERR_NOSPACE when full. Then set parameters with kelp_helm_bhv_set_param
 *  and call kelp_helm_configured(). */
KELP_MUST_CHECK int kelp_helm_add(kelp_helm *h, const char *type, kelp_bhv **out);
/** Add an initialize line ("initialize VAR = value"; defer: "initialize_", posted only if
 *  the variable is still unknown at the first iteration). */
KELP_MUST_CHECK int kelp_helm_add_init(kelp_helm *h, const char *var, const char *value, bool defer);
/** Load a parsed .bhv file: "initialize VAR = value" lines and "Behavior = BHV_X { ... }"
 *  blocks. Any bad line (unknown type, unknown or malformed parameter, other top-level
 *  lines) refuses the file: KELP_ERR_PARSE with the reason and .bhv line in h->diag. */
KELP_MUST_CHECK int kelp_helm_load_bhv(kelp_helm *h, const kelp_mission *m);
/** Finish configuration: params_done of every behaviour, domain checks. <0 with h->diag. */
KELP_MUST_CHECK int kelp_helm_configured(kelp_helm *h);
/** Start: buffer time 0 = now; publish the (non-deferred) initialize values to the sink and
 *  the buffer. */
void kelp_helm_start(kelp_helm *h, kelp_time now);
/** Mail (OnNewMail). MOOS_MANUAL_OVERIDE / MOOS_MANUAL_OVERRIDE = true|false park / drive
 *  the helm; everything else goes to the buffer. */
void kelp_helm_mail_double(kelp_helm *h, const char *var, double v);
void kelp_helm_mail_string(kelp_helm *h, const char *var, const char *v);
/** One helm iteration at MOOS time now. Returns 0, or <0 only for misuse. */
KELP_MUST_CHECK int kelp_helm_iterate(kelp_helm *h, kelp_time now);
/** Variables to register for that were not yet returned (conditions, updates, nostarve,
 *  info vars, duration_reset): call after configuration and after each iteration. */
const char *kelp_helm_next_new_var(kelp_helm *h);
/** Find a behaviour by name, or NULL (templates are not behaviours: see kelp_helm_find_template). */
kelp_bhv *kelp_helm_find(kelp_helm *h, const char *name);
kelp_bhv *kelp_helm_find_template(kelp_helm *h, const char *name);

/* ---- templates and spawning (as MOOS-IvP's helm spawns behaviours from templates) ----
 * A behaviour configured with "templating = spawn" is moved out of the behaviour set by
 * kelp_helm_configured() and never runs; its on_helm_start runs at kelp_helm_start (an
 * avoidance template posts BCM_ALERT_REQUEST). Each iteration, before the behaviours run,
 * every string received on a template's UPDATES variable that holds a "name=N" piece is a
 * spawn request: the instance name is N when N begins with the template's name, else the
 * template's name followed by N ("avd_" + "vessel_023"). If no behaviour has that name (nor
 * N itself) a copy of the template is made, the request's other "param=value" pieces are set on
 * it, and it joins the behaviour set (IVPHELM_LIFE_EVENT event=spawn, its spawnflags, its
 * BHV_SETTINGS); a bad piece aborts it (event=abort, BHV_WARNING). A template's own
 * max_spawnings (0: none) caps its spawns made; KELP_HELM_MAX_SPAWNED caps the instances alive
 * (refused with a BHV_WARNING naming the limit). Later updates naming the instance (by N or by
 * its full name) reach it through the ordinary updates mechanism; updates naming another
 * instance are a name_mismatch for it. A spawned behaviour that completes is removed at the end
 * of that iteration (IVPHELM_LIFE_EVENT event=death); behaviours of the .bhv file stay listed
 * as completed, as before.
 *
 * The ledger: every NODE_REPORT received (parsed with kelp_nodereport_parse) updates the
 * record of its NAME; reports naming ownship (the helm's us) are ignored. */
const kelp_helm_contact *kelp_helm_contact_get(const kelp_helm *h, const char *name);
/** The ledger update the helm does at each iteration start, exposed for tests and apps that
 *  feed reports directly. Returns 0 or KELP_ERR_PARSE / KELP_ERR_NOSPACE (never crashes). */
KELP_MUST_CHECK int kelp_helm_ledger_report(kelp_helm *h, const char *report);

#ifdef __cplusplus
}
#endif

#endif
