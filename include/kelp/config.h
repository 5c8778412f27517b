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


/* ---- dccl (Goby 1.1 DCCL codec) ---- */
#ifndef KELP_DCCL_MAX_STRLEN
#define KELP_DCCL_MAX_STRLEN 255    /**< bytes of a string value (string/hex fields, algorithm results) */
#endif
#ifndef KELP_DCCL_MAX_SIZE
#define KELP_DCCL_MAX_SIZE 1024     /**< bytes of one encoded message (<size> limit) */
#endif
#ifndef KELP_DCCL_MAX_ALG_REFS
#define KELP_DCCL_MAX_ALG_REFS 4    /**< reference arguments of one algorithm call (name:ref:ref) */
#endif
#ifndef KELP_DCCL_MAX_MODEM_NAME
#define KELP_DCCL_MAX_MODEM_NAME 32 /**< bytes of a vehicle name or type in the modem-id lookup */
#endif
#ifndef KELP_DCCL_MAX_NAME
#define KELP_DCCL_MAX_NAME 64       /**< bytes of a published variable name, with NUL */
#endif
#ifndef KELP_DCCL_MAX_PUBLEN
#define KELP_DCCL_MAX_PUBLEN 1024   /**< bytes of one published string value, with NUL */
#endif
_Static_assert(KELP_DCCL_MAX_STRLEN >= 32 && KELP_DCCL_MAX_STRLEN <= 65535, "KELP_DCCL_MAX_STRLEN out of range");
_Static_assert(KELP_DCCL_MAX_SIZE > 6 && KELP_DCCL_MAX_SIZE <= 8192, "KELP_DCCL_MAX_SIZE out of range");
_Static_assert(KELP_DCCL_MAX_ALG_REFS >= 2, "KELP_DCCL_MAX_ALG_REFS too small (TSD_to_soundspeed needs 2)");

#endif
