/* Example vehicle-firmware node on a kelp CAN bus: see can_node.h. The node logic is built
 * into the Cortex-M image by `make firmware` (with a stand-in board below) and into the
 * microVM integration test against real SocketCAN (-DKELP_FW_HOSTED, no board). */
#include <string.h>
#include <kelp/util.h>
#include "can_node.h"

int fw_node_init(fw_node *n, unsigned node, bool fd)
{
    memset(n, 0, sizeof *n);
    kelp_can_dict_init(&n->dict);
    if (kelp_can_dict_add(&n->dict, FW_VAR_THRUST_CMD, "THRUST_CMD") < 0 ||
        kelp_can_dict_add(&n->dict, FW_VAR_DEPTH, "DEPTH") < 0)
        return KELP_ERR_NOSPACE;
    kelp_can_rx_init(&n->rx, 0.5);
    return kelp_can_tx_init(&n->tx, node, fd);
}

void fw_node_frame(fw_node *n, const kelp_can_frame *f, double now)
{
    kelp_can_msg m;
    if (kelp_can_rx_frame(&n->rx, &n->dict, f, now, &m) != 1) return;
    if (m.var == FW_VAR_THRUST_CMD && m.kind == KELP_CAN_KIND_F64) {
        n->thrust = m.dval;
        n->commands++;
        n->status_due = true;
    }
}

/* "thrust=42.5,commands=3" (kelp's own formatter: no stdio in the image) */
static size_t status_text(const fw_node *n, char *p, size_t cap)
{
    int k = kelp_util_snprintf(p, cap, "thrust=");
    int w = kelp_util_fmt_fixed(p + k, cap - (size_t)k, n->thrust, 2, true);
    if (w < 0) w = kelp_util_snprintf(p + k, cap - (size_t)k, "range");
    k += w;
    k += kelp_util_snprintf(p + k, cap - (size_t)k, ",commands=%lu", n->commands);
    return (size_t)k < cap ? (size_t)k : cap - 1;
}

int fw_node_tick(fw_node *n, double now, double depth, kelp_can_emit_fn emit, void *user)
{
    int frames = 0, rc;
    kelp_can_rx_expire(&n->rx, now);
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    if (now >= n->next_publish) {
        n->next_publish = now + FW_PUBLISH_PERIOD;
        m.name = "DEPTH";
        m.kind = KELP_CAN_KIND_F64;
        m.dval = depth;
        rc = kelp_can_send(&n->tx, &n->dict, &m, emit, user);
        if (rc < 0) return rc;
        frames += rc;
    }
    if (n->status_due) {
        char text[64];
        n->status_due = false;
        m.name = "FW_STATUS";
        m.kind = KELP_CAN_KIND_STRING;
        m.sval = (const uint8_t *)text;
        m.slen = status_text(n, text, sizeof text);
        rc = kelp_can_send(&n->tx, &n->dict, &m, emit, user);
        if (rc < 0) return rc;
        frames += rc;
    }
    return frames;
}

#ifndef KELP_FW_HOSTED
/* A stand-in board: a memory-mapped CAN mailbox and a pressure sensor register. A real port
 * replaces these with its CAN peripheral driver (one frame in, one frame out). */
typedef struct board_mailbox {
    volatile uint32_t id;
    volatile uint8_t len, fd, full;
    volatile uint8_t data[64];
} board_mailbox;
static board_mailbox *const tx_box = (board_mailbox *)0x40006400u;
static board_mailbox *const rx_box = (board_mailbox *)0x40006480u;
static volatile uint32_t *const pressure_reg = (volatile uint32_t *)0x40010000u;
static volatile uint32_t *const ms_counter = (volatile uint32_t *)0x40010004u;

static int board_emit(void *user, const kelp_can_frame *f)
{
    (void)user;
    while (tx_box->full) {
    }
    tx_box->id = f->id;
    tx_box->len = f->len;
    tx_box->fd = f->fd;
    for (uint8_t i = 0; i < f->len; i++) tx_box->data[i] = f->data[i];
    tx_box->full = 1;
    return 0;
}

int main(void);

int main(void)
{
    static fw_node node;
    static kelp_can_frame f;
    if (fw_node_init(&node, 2, false) < 0) return 1;
    for (;;) {
        double now = (double)*ms_counter / 1000.0;
        if (rx_box->full) {
            f.id = rx_box->id;
            f.len = rx_box->len > 64 ? 64 : rx_box->len;
            f.fd = rx_box->fd != 0;
            for (uint8_t i = 0; i < f.len; i++) f.data[i] = rx_box->data[i];
            rx_box->full = 0;
            fw_node_frame(&node, &f, now);
        }
        double depth = (double)*pressure_reg * 0.001; /* mbar to metres, roughly */
        (void)fw_node_tick(&node, now, depth, board_emit, NULL);
    }
}
#endif
