/* pAcommsHandler (private): the app's state and callbacks. */
#ifndef PACOMMS_HANDLER_H
#define PACOMMS_HANDLER_H

#include <stdio.h>

#include <kelp/acomms.h>
#include <kelp/edge/app.h>
#include <kelp/link.h>

/* the core handler (kelp_acomms_handler) and what it is wired to */
typedef struct handler {
    kelp_acomms_config cfg;
    kelp_acomms_dccl *dccl;   /* the DCCL glue (message files loaded at start-up) */
    kelp_acomms_codec codec;  /* ... as the core handler sees it */
    kelp_acomms_handler core;
    kelp_queue_entry *pool;
    kelp_link *link;          /* DRIVER_WHOI_MICROMODEM: serial port or TCP */
    kelp_acomms_lcm *lcm;     /* the LCM structures (ACOMMS_*_LCM) */
    kelp_app *app;
    unsigned long write_errors;
    bool codec_only;          /* run as pGeneralCodec: DCCL encode/decode, no driver, MAC or queue */
} handler;

handler *handler_new(void);
void handler_free(handler *h);
int handler_startup(kelp_app *app, void *state);
void handler_mail(kelp_app *app, void *state, const kelp_var *v);
int handler_iterate(kelp_app *app, void *state, double now);
void handler_report(kelp_app *app, void *state, FILE *out);
void handler_shutdown(kelp_app *app, void *state);

#define PACOMMS_EXAMPLE                                                                                     \
    "Every field, in full (Goby 1.1 pAcommsHandler TextFormat):\n"                                      \
    "  common {  # (opt)\n"                                                                                \
    "    log: true  log_path: \"./\"  community: \"AUV23\"  lat_origin: 42.5  lon_origin: 10.9\n"         \
    "    app_tick: 10  comm_tick: 10\n"                                                                    \
    "    verbosity: VERBOSITY_VERBOSE  # QUIET, WARN, VERBOSE, DEBUG, GUI\n"                               \
    "    initializer { type: INI_DOUBLE moos_var: \"SOME_MOOS_VAR\" dval: 3.454 }  # (repeat)\n"           \
    "    initializer { type: INI_DOUBLE global_cfg_var: \"LatOrigin\" moos_var: \"LAT_ORIGIN\" }\n"        \
    "    initializer { type: INI_STRING moos_var: \"VEHICLE_NAME\" sval: \"a string\" }\n"                 \
    "  }\n"                                                                                                \
    "  modem_id: 1  # 1-31 (req); 0 is broadcast\n"                                                        \
    "  driver_type: DRIVER_WHOI_MICROMODEM  # DRIVER_NONE (default), DRIVER_WHOI_MICROMODEM\n"             \
    "  driver_cfg {\n"                                                                                     \
    "    connection_type: CONNECTION_SERIAL  # CONNECTION_TCP_AS_CLIENT, CONNECTION_TCP_AS_SERVER\n"        \
    "    line_delimiter: \"\\r\\n\"\n"                                                                     \
    "    serial_port: \"/dev/ttyS0\"  # any device path, pseudo-terminals included\n"                     \
    "    serial_baud: 19200\n"                                                                             \
    "    tcp_server: \"192.168.1.111\"  # CONNECTION_TCP_AS_CLIENT\n"                                      \
    "    tcp_port: 50010                # TCP_AS_CLIENT: connect to; TCP_AS_SERVER: listen on\n"           \
    "    [MicroModemConfig.reset_nvram]: false  # true: $CCCFG,ALL,0 at start-up\n"                        \
    "    [MicroModemConfig.nvram_cfg]: \"DTO,2\"  # (repeat) sent after the reset (SRC is modem_id)\n"     \
    "    # [MicroModemConfig.hydroid_gateway_id]: 1  # only with a Hydroid gateway buoy\n"                \
    "  }\n"                                                                                                \
    "  mac_cfg {\n"                                                                                        \
    "    type: MAC_FIXED_DECENTRALIZED  # MAC_NONE (default), MAC_AUTO_DECENTRALIZED, MAC_POLLED\n"        \
    "    slot { src: 1 dest: 2 rate: 0 type: SLOT_DATA slot_seconds: 10 }  # (repeat) in cycle order\n"   \
    "    slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 10 }\n"                              \
    "    # MAC_AUTO_DECENTRALIZED: rate: 0  slot_seconds: 15  expire_cycles: 30\n"                        \
    "  }\n"                                                                                                \
    "  queue_cfg {\n"                                                                                      \
    "    message_file { path: \"simple_status.xml\" manipulator: NO_MANIP }  # DCCL queues: <queuing>\n"  \
    "    queue {  # CCL queues\n"                                                                          \
    "      key { type: QUEUE_CCL id: 14 }  # the CCL message's first byte\n"                               \
    "      name: \"Remus_State\"  in_pubsub_var: \"IN_REMUS_STATUS\"  out_pubsub_var: \"OUT_REMUS_STATUS\"\n" \
    "      ack: true  blackout_time: 0  max_queue: 0  newest_first: true  value_base: 1  ttl: 1800\n"      \
    "    }\n"                                                                                              \
    "  }\n"                                                                                                \
    "  dccl_cfg {\n"                                                                                       \
    "    message_file { path: \"example1.xml\" manipulator: LOOPBACK }\n"                                 \
    "    # manipulators: NO_MANIP, NO_ENCODE, NO_DECODE, NO_QUEUE, LOOPBACK, ON_DEMAND, TCP_SHARE_IN\n"   \
    "    crypto_passphrase: \"twinkletoes%24\"  # (opt) the same on every node\n"                          \
    "  }\n"                                                                                                \
    "  modem_id_lookup_path: \"modemidlookup.txt\"  # \"id,name,type\" lines\n"                           \
    "  tcp_share_enable: false  tcp_share_port: 11000  # experimental in Goby: not implemented\n"

#endif
