/* kelp: every build-time limit. Override with -DKELP_MAX_...=N. */
#ifndef KELP_CONFIG_H
#define KELP_CONFIG_H

#ifdef __cplusplus
extern "C" {
#endif

/** A compile-time check that C11 and C++ (11 and later) both accept. */
#ifdef __cplusplus
#define KELP_STATIC_ASSERT(cond, msg) static_assert(cond, msg)
#else
#define KELP_STATIC_ASSERT(cond, msg) _Static_assert(cond, msg)
#endif

/** Time in every core interface: MOOS time, seconds since 1970-01-01 UTC (times MOOSTimeWarp
 *  when warped), as a double: a core function never reads a clock, the caller passes `now` in.
 *  A double holds today's epoch seconds to better than half a microsecond. */
typedef double kelp_time;

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
#ifndef KELP_BUS_CACHE_HASH
#define KELP_BUS_CACHE_HASH 1024    /**< name index over the retained values (2 bytes each, in
                                         kelp_bus; a power of two, 0 = none): used when the
                                         cache holds at most half as many variables */
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

#ifndef KELP_UDPM_MAX_FRAGS
#define KELP_UDPM_MAX_FRAGS 1024    /**< fragments in one reassembled UDP multicast message */
#endif

#ifndef KELP_BUS_SYNC_PEERS
#define KELP_BUS_SYNC_PEERS 16      /**< requesters whose sync-reply budget a client tracks */
#endif

/* ---- mission files ---- */
#ifndef KELP_MAX_LINE
#define KELP_MAX_LINE 1024          /**< bytes in one mission-file line */
#endif

KELP_STATIC_ASSERT(KELP_MAX_NAME >= 16, "KELP_MAX_NAME too small");
KELP_STATIC_ASSERT((KELP_BUS_CACHE_HASH & (KELP_BUS_CACHE_HASH - 1)) == 0 && KELP_BUS_CACHE_HASH <= 32768,
                   "KELP_BUS_CACHE_HASH must be 0 or a power of two up to 32768");
KELP_STATIC_ASSERT(KELP_MAX_SVAL >= 256, "KELP_MAX_SVAL too small");


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
KELP_STATIC_ASSERT(KELP_IVP_MAX_DIM >= 1 && KELP_IVP_MAX_DIM <= 16, "KELP_IVP_MAX_DIM out of range");
KELP_STATIC_ASSERT(KELP_IVP_MAX_VARNAME >= 8, "KELP_IVP_MAX_VARNAME too small");
KELP_STATIC_ASSERT(KELP_IVP_MAX_FUNCS >= 1, "KELP_IVP_MAX_FUNCS too small");
KELP_STATIC_ASSERT(KELP_IVP_MAX_COMPONENTS >= 1, "KELP_IVP_MAX_COMPONENTS too small");
KELP_STATIC_ASSERT(KELP_IVP_MAX_WARN >= 64, "KELP_IVP_MAX_WARN too small");
/* ---- acomms: priority queue, TDMA MAC, NMEA, WHOI Micro-Modem driver ---- */
#ifndef KELP_MAX_NMEA_LINE
#define KELP_MAX_NMEA_LINE 640      /**< bytes in one NMEA line (a rate-5 $CARXD is ~535) */
#endif
#ifndef KELP_MAX_NMEA_FIELDS
#define KELP_MAX_NMEA_FIELDS 40     /**< comma-separated fields in one sentence ($CACST has 29) */
#endif
#ifndef KELP_MAX_ACOMMS_FRAME
#define KELP_MAX_ACOMMS_FRAME 256   /**< bytes in one modem frame / one queued message */
#endif
#ifndef KELP_MAX_QUEUE_ACK_WAIT
#define KELP_MAX_QUEUE_ACK_WAIT 64  /**< (frame, queue) records awaiting an ack per packet */
#endif
#ifndef KELP_MAX_MAC_SLOTS
#define KELP_MAX_MAC_SLOTS 32       /**< slots in one TDMA cycle (AUTO: ids heard + own + blank) */
#endif
#ifndef KELP_MAX_MM_OUTQ
#define KELP_MAX_MM_OUTQ 16         /**< commands waiting for the modem */
#endif
#ifndef KELP_MAX_MM_FRAMES
#define KELP_MAX_MM_FRAMES 8        /**< frames cached for one cycle (rate 5 = 8) */
#endif
#ifndef KELP_MAX_MM_NVRAM
#define KELP_MAX_MM_NVRAM 16        /**< nvram_cfg entries sent at start-up */
#endif
#ifndef KELP_MAX_MM_NVRAM_LEN
#define KELP_MAX_MM_NVRAM_LEN 32    /**< bytes in one nvram_cfg entry ("CST,1"), with NUL */
#endif
#ifndef KELP_MAX_MM_BACKLOG
#define KELP_MAX_MM_BACKLOG 2048    /**< bytes held while the driver "sleeps" (Goby's sleep(1)/(2)) */
#endif
KELP_STATIC_ASSERT(KELP_MAX_NMEA_LINE >= 560, "KELP_MAX_NMEA_LINE must hold a 256-byte $CARXD");
KELP_STATIC_ASSERT(KELP_MAX_ACOMMS_FRAME >= 32 && KELP_MAX_ACOMMS_FRAME <= 65535, "KELP_MAX_ACOMMS_FRAME out of range");
KELP_STATIC_ASSERT(KELP_MAX_MM_FRAMES >= 8 && KELP_MAX_MM_FRAMES <= 32, "KELP_MAX_MM_FRAMES must be 8..32");
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
#ifndef KELP_DCCL_MAX_PUB_ARGS
#define KELP_DCCL_MAX_PUB_ARGS 64   /**< argument strings of one <publish> (message_var x elements) */
#endif
#ifndef KELP_DCCL_PUB_ALG_WORK
#define KELP_DCCL_PUB_ALG_WORK 1024 /**< bytes (codec workspace) for the strings of the <publish>
                                         arguments that run algorithms, one publication at a time */
#endif
KELP_STATIC_ASSERT(KELP_DCCL_MAX_STRLEN >= 32 && KELP_DCCL_MAX_STRLEN <= 65535, "KELP_DCCL_MAX_STRLEN out of range");
KELP_STATIC_ASSERT(KELP_DCCL_MAX_SIZE > 6 && KELP_DCCL_MAX_SIZE <= 8192, "KELP_DCCL_MAX_SIZE out of range");
KELP_STATIC_ASSERT(KELP_DCCL_MAX_PUB_ARGS >= 1 && KELP_DCCL_MAX_PUB_ARGS <= 1024, "KELP_DCCL_MAX_PUB_ARGS out of range");
KELP_STATIC_ASSERT(KELP_DCCL_PUB_ALG_WORK >= KELP_DCCL_MAX_STRLEN + 1 && KELP_DCCL_PUB_ALG_WORK <= 65535,
                   "KELP_DCCL_PUB_ALG_WORK must hold one string value");
KELP_STATIC_ASSERT(KELP_DCCL_MAX_ALG_REFS >= 2, "KELP_DCCL_MAX_ALG_REFS too small (TSD_to_soundspeed needs 2)");

/* ---- helm (IvP helm, behaviour framework, behaviours) ---- */
#ifndef KELP_HELM_MAX_BHVS
#define KELP_HELM_MAX_BHVS 32       /**< behaviours in one helm */
#endif
#ifndef KELP_HELM_MAX_TEMPLATES
#define KELP_HELM_MAX_TEMPLATES 4   /**< behaviours with templating = spawn in one helm */
#endif
#ifndef KELP_HELM_MAX_SPAWNED
#define KELP_HELM_MAX_SPAWNED 24    /**< spawned behaviour instances alive at once (all templates); a spawn
                                         past it is refused with a BHV_WARNING (a run warning in pHelmIvP) */
#endif
#ifndef KELP_HELM_MAX_CONTACTS
#define KELP_HELM_MAX_CONTACTS 64   /**< contacts the helm's ledger keeps from NODE_REPORT (oldest replaced) */
#endif
#ifndef KELP_HELM_MAX_VARS
#define KELP_HELM_MAX_VARS 128      /**< variables held in the information buffer */
#endif
#ifndef KELP_HELM_MAX_SVAL
#define KELP_HELM_MAX_SVAL 512      /**< bytes of a string value in the buffer or a posting, with NUL */
#endif
#ifndef KELP_HELM_MAX_DELTAS
#define KELP_HELM_MAX_DELTAS 256    /**< values kept for the buffer's per-iteration vectors (all variables) */
#endif
#ifndef KELP_HELM_DELTA_POOL
#define KELP_HELM_DELTA_POOL 16384  /**< bytes of string storage for those values */
#endif
#ifndef KELP_HELM_MAX_POSTS
#define KELP_HELM_MAX_POSTS 256     /**< behaviour postings queued in one iteration */
#endif
#ifndef KELP_HELM_POST_POOL
#define KELP_HELM_POST_POOL 32768   /**< bytes of string storage for those postings */
#endif
#ifndef KELP_HELM_MAX_FILTER
#define KELP_HELM_MAX_FILTER 512    /**< keys remembered by the duplicate-posting filter */
#endif
#ifndef KELP_HELM_MAX_CONDS
#define KELP_HELM_MAX_CONDS 8       /**< condition lines per behaviour */
#endif
#ifndef KELP_HELM_MAX_COND_LEN
#define KELP_HELM_MAX_COND_LEN 160  /**< bytes of one condition expression, with NUL */
#endif
#ifndef KELP_HELM_MAX_FLAGS
#define KELP_HELM_MAX_FLAGS 16      /**< run/idle/active/inactive/end flags per behaviour (all kinds) */
#endif
#ifndef KELP_HELM_MAX_FLAG_VAL
#define KELP_HELM_MAX_FLAG_VAL 160  /**< bytes of a flag (or initialize) value, with NUL */
#endif
#ifndef KELP_HELM_MAX_INFOVARS
#define KELP_HELM_MAX_INFOVARS 16   /**< addInfoVars / nostarve variables per behaviour */
#endif
#ifndef KELP_HELM_MAX_MAPPINGS
#define KELP_HELM_MAX_MAPPINGS 8    /**< post_mapping pairs per behaviour */
#endif
#ifndef KELP_HELM_MAX_INIT
#define KELP_HELM_MAX_INIT 32       /**< initialize lines of the behaviour files */
#endif
#ifndef KELP_HELM_MAX_MODES
#define KELP_HELM_MAX_MODES 16      /**< "set MODE = ..." entries of the behaviour files */
#endif
#ifndef KELP_HELM_MAX_PTS
#define KELP_HELM_MAX_PTS 64        /**< points of a waypoint list or loiter polygon */
#endif
KELP_STATIC_ASSERT(KELP_HELM_MAX_SVAL >= 64, "KELP_HELM_MAX_SVAL too small");
KELP_STATIC_ASSERT(KELP_HELM_MAX_BHVS >= 1 && KELP_HELM_MAX_BHVS <= 1024, "KELP_HELM_MAX_BHVS out of range");
KELP_STATIC_ASSERT(KELP_HELM_MAX_PTS >= 4, "KELP_HELM_MAX_PTS too small");
/* ---- sim: vehicle simulator, node reports, VIEW_* artifacts ---- */
#ifndef KELP_SIM_MAX_MAP
#define KELP_SIM_MAX_MAP 16             /**< thrust_map points of the simulator */
#endif
#ifndef KELP_TIME_STEP_MAX
#define KELP_TIME_STEP_MAX 300.0      /**< seconds: a longer gap between two iterations of a tool
                                           that runs on elapsed time (uSimMarine, uTimerScript...)
                                           is a clock step, not elapsed time (the time step rule,
                                           docs/ARCHITECTURE.md) */
#endif
#ifndef KELP_SIM_MAX_SUBSTEPS
#define KELP_SIM_MAX_SUBSTEPS 2000000L  /**< sub-steps one kelp_sim_step may take (a time jump bound) */
#endif
#ifndef KELP_NODEREPORT_MAX_FIELD
#define KELP_NODEREPORT_MAX_FIELD 48    /**< bytes of a text field of a node report (NAME, TYPE, MODE...), with NUL */
#endif
#ifndef KELP_NODEREPORT_MAX_LEN
#define KELP_NODEREPORT_MAX_LEN 512     /**< bytes of a formatted node report, with NUL */
#endif
/* a function kept out of its callers (a recursive caller's frame stays small) */
#if defined(__GNUC__)
#define KELP_NOINLINE __attribute__((noinline))
#else
#define KELP_NOINLINE
#endif

#ifndef KELP_HELM_COND_MAX_DEPTH
#define KELP_HELM_COND_MAX_DEPTH 16     /**< nesting of parentheses / not in a condition (bounds the stack) */
#endif

#ifndef KELP_VIEW_MAX_PTS
#define KELP_VIEW_MAX_PTS 64            /**< vertices of one VIEW_POLYGON / VIEW_SEGLIST */
#endif
#ifndef KELP_VIEW_MAX_FIELD
#define KELP_VIEW_MAX_FIELD 64          /**< bytes of a text field of a VIEW_* artifact (label, colour...), with NUL */
#endif
KELP_STATIC_ASSERT(KELP_NODEREPORT_MAX_FIELD >= 16, "KELP_NODEREPORT_MAX_FIELD too small");
KELP_STATIC_ASSERT(KELP_NODEREPORT_MAX_LEN >= 256, "KELP_NODEREPORT_MAX_LEN too small for a full report");
KELP_STATIC_ASSERT(KELP_VIEW_MAX_PTS >= 4, "KELP_VIEW_MAX_PTS too small");
KELP_STATIC_ASSERT(KELP_VIEW_MAX_FIELD >= 16, "KELP_VIEW_MAX_FIELD too small");
/* ---- viewer (kelp-viewer, the pMarineViewer role: include/kelp/viewer.h) ---- */
#ifndef KELP_VIEWER_MAX_VEHICLES
#define KELP_VIEWER_MAX_VEHICLES 512    /**< vehicles one viewer tracks (the bench runs 500) */
#endif
#ifndef KELP_VIEWER_MAX_TRAIL
#define KELP_VIEWER_MAX_TRAIL 256       /**< trail points kept per vehicle (trails_length is clipped to it) */
#endif
#ifndef KELP_VIEWER_MAX_ARTIFACTS
#define KELP_VIEWER_MAX_ARTIFACTS 256   /**< VIEW_* artifacts held at once, keyed by (kind, label) */
#endif
#ifndef KELP_VIEWER_MAX_CMDS
#define KELP_VIEWER_MAX_CMDS 48         /**< buttons (button_one..button_twenty) plus action menu entries */
#endif
#ifndef KELP_VIEWER_MAX_POKES
#define KELP_VIEWER_MAX_POKES 8         /**< var=value pokes of one button or action */
#endif
#ifndef KELP_VIEWER_MAX_POKE_VAL
#define KELP_VIEWER_MAX_POKE_VAL 160    /**< bytes of one poke's string value, with NUL */
#endif
#ifndef KELP_VIEWER_MAX_CASTS
#define KELP_VIEWER_MAX_CASTS 64        /**< AppCasts (APPCAST strings) held at once, keyed by (node, proc) */
#endif
KELP_STATIC_ASSERT(KELP_VIEWER_MAX_VEHICLES >= 1 && KELP_VIEWER_MAX_TRAIL >= 2, "viewer tables too small");
KELP_STATIC_ASSERT(KELP_VIEWER_MAX_ARTIFACTS >= 8 && KELP_VIEWER_MAX_CMDS >= 20, "viewer tables too small");

/* ---- modemsim (WHOI Micro-Modem simulator: modem-side protocol, acoustic channel) ---- */
#ifndef KELP_MAX_MSIM_ARRIVALS
#define KELP_MAX_MSIM_ARRIVALS 16   /**< packets on their way to (or recently heard by) one modem */
#endif
#ifndef KELP_MAX_MSIM_TXQ
#define KELP_MAX_MSIM_TXQ 8         /**< own transmissions scheduled (CI, data, ack, ping replies) */
#endif
#ifndef KELP_MAX_MSIM_TXLOG
#define KELP_MAX_MSIM_TXLOG 8       /**< own past transmissions remembered (half-duplex check) */
#endif
#ifndef KELP_MAX_MSIM_NVRAM
#define KELP_MAX_MSIM_NVRAM 64      /**< NVRAM (CFG) parameters the simulated modem holds */
#endif
#ifndef KELP_MAX_MSIM_POLL_SLOTS
#define KELP_MAX_MSIM_POLL_SLOTS 32 /**< slots in a pAcommsPoller cycle */
#endif
KELP_STATIC_ASSERT(KELP_MAX_MSIM_ARRIVALS >= 4, "KELP_MAX_MSIM_ARRIVALS too small");
KELP_STATIC_ASSERT(KELP_MAX_MSIM_TXQ >= 4, "KELP_MAX_MSIM_TXQ too small");

#endif
/* ---- acomms glue, links, pAcommsHandler, kelp-acomms-replay (branch acomms2) ---- */
#ifndef KELP_ACOMMS_MAX_TEXT
#define KELP_ACOMMS_MAX_TEXT 256    /**< bytes of a configured string (initializer sval, passphrase) */
#endif
#ifndef KELP_ACOMMS_MAX_PATH
#define KELP_ACOMMS_MAX_PATH 256    /**< bytes of a configured path (message file, serial port, host) */
#endif
#ifndef KELP_ACOMMS_MAX_INIT
#define KELP_ACOMMS_MAX_INIT 32     /**< common.initializer entries */
#endif
#ifndef KELP_ACOMMS_MAX_CCL
#define KELP_ACOMMS_MAX_CCL 16      /**< queue_cfg.queue (CCL) entries */
#endif
#ifndef KELP_ACOMMS_MAX_FILES
#define KELP_ACOMMS_MAX_FILES 16    /**< DCCL message files (queue_cfg + dccl_cfg, merged) */
#endif
#ifndef KELP_ACOMMS_MAX_QUEUES
#define KELP_ACOMMS_MAX_QUEUES 64   /**< queues of one node (DCCL messages + CCL queues) */
#endif
#ifndef KELP_ACOMMS_MAX_POOL
#define KELP_ACOMMS_MAX_POOL 512    /**< messages held over all queues of one node */
#endif
#ifndef KELP_ACOMMS_MAX_PRINT
#define KELP_ACOMMS_MAX_PRINT 4096  /**< bytes of one TextFormat ACOMMS_* string, with NUL */
#ifdef __cplusplus
}
#endif

#endif
KELP_STATIC_ASSERT(KELP_ACOMMS_MAX_PRINT >= 6 * KELP_MAX_ACOMMS_FRAME, "KELP_ACOMMS_MAX_PRINT must hold an ack of a full frame");
KELP_STATIC_ASSERT(KELP_ACOMMS_MAX_QUEUES >= 2 && KELP_ACOMMS_MAX_POOL >= 8, "acomms node storage too small");
