/* kelp: every build-time limit. Override with -DKELP_MAX_...=N. */
#ifndef KELP_CONFIG_H
#define KELP_CONFIG_H

/* ---- bus ---- */
#ifndef KELP_MAX_NAME
#define KELP_MAX_NAME 64            /**< bytes in a variable / app / community name, with NUL */
#endif
#ifndef KELP_MAX_SVAL
#define KELP_MAX_SVAL 4096          /**< bytes in a string or binary value */
#endif
#ifndef KELP_MAX_SUBS
#define KELP_MAX_SUBS 128           /**< registrations per bus client */
#endif
#ifndef KELP_MAX_CACHE
#define KELP_MAX_CACHE 512          /**< variables whose latest value a client retains */
#endif

/* ---- mission files ---- */
#ifndef KELP_MAX_LINE
#define KELP_MAX_LINE 1024          /**< bytes in one mission-file line */
#endif

_Static_assert(KELP_MAX_NAME >= 16, "KELP_MAX_NAME too small");
_Static_assert(KELP_MAX_SVAL >= 256, "KELP_MAX_SVAL too small");

#endif
