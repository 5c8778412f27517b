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

#ifndef KELP_MAX_SYNC_PATTERNS
#define KELP_MAX_SYNC_PATTERNS 16   /**< patterns in one sync request */
#endif
#ifndef KELP_MAX_LOOPBACK_CLIENTS
#define KELP_MAX_LOOPBACK_CLIENTS 8 /**< clients on one in-process loopback network */
#endif
#ifndef KELP_LOOPBACK_FIFO
#define KELP_LOOPBACK_FIFO 65536    /**< bytes queued on one loopback network */
#endif
#ifndef KELP_BUS_MAX_DEPTH
#define KELP_BUS_MAX_DEPTH 8        /**< nested publish-from-handler depth on loopback */
#endif

/* ---- mission files ---- */
#ifndef KELP_MAX_LINE
#define KELP_MAX_LINE 1024          /**< bytes in one mission-file line */
#endif

_Static_assert(KELP_MAX_NAME >= 16, "KELP_MAX_NAME too small");
_Static_assert(KELP_MAX_SVAL >= 256, "KELP_MAX_SVAL too small");


/* ---- ivp (IvP domain, functions, ZAIC/Reflector/Coupler, solver) ---- */
#ifndef KELP_IVP_MAX_DIM
#define KELP_IVP_MAX_DIM 4          /**< decision variables in one IvP domain */
#endif
#ifndef KELP_IVP_MAX_VARNAME
#define KELP_IVP_MAX_VARNAME 32     /**< bytes in an IvP domain variable name, with NUL */
#endif
#ifndef KELP_IVP_MAX_FUNCS
#define KELP_IVP_MAX_FUNCS 64       /**< IvP functions in one solver problem */
#endif
#ifndef KELP_IVP_MAX_COMPONENTS
#define KELP_IVP_MAX_COMPONENTS 8   /**< ZAIC_PEAK components (modes) */
#endif
#ifndef KELP_IVP_MAX_REFINE
#define KELP_IVP_MAX_REFINE 8       /**< queued Reflector refine_region/refine_piece pairs */
#endif
#ifndef KELP_IVP_MAX_WARN
#define KELP_IVP_MAX_WARN 256       /**< bytes of accumulated builder warning text, with NUL */
#endif
_Static_assert(KELP_IVP_MAX_DIM >= 1 && KELP_IVP_MAX_DIM <= 16, "KELP_IVP_MAX_DIM out of range");
_Static_assert(KELP_IVP_MAX_VARNAME >= 8, "KELP_IVP_MAX_VARNAME too small");
_Static_assert(KELP_IVP_MAX_FUNCS >= 1, "KELP_IVP_MAX_FUNCS too small");
_Static_assert(KELP_IVP_MAX_COMPONENTS >= 1, "KELP_IVP_MAX_COMPONENTS too small");
_Static_assert(KELP_IVP_MAX_WARN >= 64, "KELP_IVP_MAX_WARN too small");

#endif
