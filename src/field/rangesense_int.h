/* Private pieces shared by the beacon and contact range sensors (src/field/rangesense.c). */
#ifndef KELP_RANGESENSE_INT_H
#define KELP_RANGESENSE_INT_H
#include <kelp/beaconrange.h>

/** Value with a trailing ';' and blanks removed, into v (cap bytes). @return length or <0. */
int rs_value(const char *val, char *v, size_t cap, kelp_diag *d);
/** A negative push or pull is "nolimit": always heard; else push + pull >= d. */
bool rs_trans(double push, double pull, double d);
/** Index of a vehicle (its exact name, as 24.8's ledger), or -1. */
int rs_find(const kelp_rangesense_node *nodes, unsigned n, const char *name);
/* a request from v at now is in time for ping_wait `wait` (KELP_RSENSE_LATE) */
bool rs_in_time(const kelp_rangesense_node *v, double now, double wait);
/** Apply a node report: 1 stored (*idx; *first on the first report of that vehicle), 0 when
 *  its GROUP is `ignore_group` (the vehicle is dropped), <0 (reason in d). Vehicles stay sorted
 *  by name; a new vehicle has not pinged (24.8's clock at 0). */
int rs_node_report(kelp_rangesense_node *nodes, unsigned *n, const char *s, const kelp_geo *geo, bool have_geo,
                   const char *ignore_group, double start, int *idx, bool *first, kelp_diag *d);
/** The name of a "name=V" request (24.8 reads name= only), or <0. */
int rs_request_name(const char *s, char *name, size_t cap);
/** Post a range report: <pfx>_RANGE_REPORT "vname=V,range=R,<key>=<id>[,x=..,y=..],time=T"
 *  and/or <pfx>_RANGE_REPORT_<V> without vname (gt: <pfx>_RANGE_REPORT_GT[_<V>]). */
void rs_post_report(const kelp_field_sink *out, const char *pfx, bool gt, kelp_rangesense_vars vars, const char *vname,
                    double range, const char *key, const char *id, const double *xy, double now,
                    char ws[KELP_RSENSE_POST_WS]);
/** VIEW_RANGE_PULSE as 24.8's XYRangePulse spec with fill 0.9:
 *  "x=..,y=..,radius=..,fill=0.9,label=..,edge_color=C,fill_color=C,time=..,duration=..,edge_size=1". */
void rs_pulse(const kelp_field_sink *out, double x, double y, double radius, double duration, const char *label,
              const char *color, double now, char ws[KELP_RSENSE_POST_WS]);
/** Ends the piece lists of rs_log and rs_warn. */
#define RS_END ((const char *)0)
/** A verbose line made of pieces (no format strings from data); NULL ends the list. */
void rs_log(kelp_rangesense_log_fn fn, void *ctx, const char *a, ...);
/** Warn through the sink with pieces; NULL ends the list. */
void rs_warn(const kelp_field_sink *out, const char *a, ...);
/** Upper-case / lower-case ASCII letters in place. */
void rs_upper(char *s);
void rs_lower(char *s);
/** Copy at most cap-1 bytes. */
void rs_copy(char *dst, size_t cap, const char *src, size_t n);

#endif
