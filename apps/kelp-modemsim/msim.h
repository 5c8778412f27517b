/* kelp-modemsim (private): the app's state and its configuration reader. */
#ifndef KELP_MODEMSIM_APP_H
#define KELP_MODEMSIM_APP_H

#include <kelp/edge/app.h>
#include <kelp/edge/hostport.h>
#include <kelp/lcmbus.h>
#include <kelp/modemsim.h>

#define DEFAULT_CHANNEL "ACOMMS_SIM_CHANNEL"

typedef struct msim_app {
    kelp_app *app;
    kelp_modemsim m;
    int modem_id;
    /* host side */
    kelp_hostport host;            /* pty or TCP server */
    char pty_link[256];
    unsigned tcp_port;
    /* channel */
    char channel_var[KELP_MAX_NAME];
    char channel_url[400];
    kelp_lcmbus *chan;             /* separate channel bus, or NULL = the community bus */
    unsigned long pkts_out, pkts_in, pkts_bad, pkts_sync_ignored;
    /* position source */
    char node_report_var[KELP_MAX_NAME];
    bool nav_vars;
    double nav_x, nav_y, nav_depth;
    bool publish_events;
    double last_status;
    uint8_t enc[KELP_MODEMSIM_PKT_MAX_ENCODED];
    kelp_modemsim_pkt rxpkt;
} msim_app;

/** Read the ProcessConfig block into s and c (0, or <0 after a configuration error). */
int msim_config(kelp_app *app, msim_app *s, kelp_modemsim_cfg *c);
/** A number that tells this process's transmissions apart on the channel. */
uint32_t msim_instance(void);

#endif
