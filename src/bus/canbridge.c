/* kelp-canbridge's core: routes with renaming between a community and a CAN bus. */
#include <string.h>
#include <kelp/bridge.h>
#include <kelp/can.h>
#include <kelp/canbridge.h>
#include "bus_int.h"

int kelp_canbridge_init(kelp_canbridge *b, unsigned node, bool fd, double timeout)
{
    memset(b, 0, sizeof *b);
    kelp_can_dict_init(&b->dict);
    kelp_can_rx_init(&b->rx, timeout);
    return kelp_can_tx_init(&b->tx, node, fd);
}

int kelp_canbridge_add(kelp_canbridge *b, bool to_can, const char *line, kelp_diag *d)
{
    int ns, na;
    bool glob;
    /* checked first, then read straight into the route table */
    int rc = kelp_bridge_rename_list(line, NULL, NULL, 0, &ns, &na, &glob, d);
    if (rc < 0) return rc;
    if (na && glob) return kelp_fail(d, KELP_ERR_PARSE, "a glob cannot be renamed");
    size_t *cnt = to_can ? &b->nto : &b->nfrom;
    char(*src)[KELP_MAX_NAME] = to_can ? b->to_src : b->from_src;
    char(*alias)[KELP_MAX_NAME] = to_can ? b->to_alias : b->from_alias;
    size_t n = (size_t)ns;
    if (*cnt + n > KELP_CANBRIDGE_MAX_ROUTES) return kelp_fail(d, KELP_ERR_NOSPACE, "too many routes");
    memset(src[*cnt], 0, n * KELP_MAX_NAME);
    memset(alias[*cnt], 0, n * KELP_MAX_NAME);
    (void)kelp_bridge_rename_list(line, src[*cnt], alias[*cnt], KELP_MAX_NAME, &ns, &na, &glob, d);
    for (size_t i = 0; i < n; i++) {
        const char *can_name = to_can ? (alias[*cnt][0] ? alias[*cnt] : src[*cnt]) : src[*cnt];
        if (strlen(can_name) >= KELP_CAN_NAME) return kelp_fail(d, KELP_ERR_RANGE, "a CAN name is longer than 63");
        (*cnt)++;
    }
    return KELP_OK;
}

size_t kelp_canbridge_filters(const kelp_canbridge *b, kelp_can_filter *out, size_t cap)
{
    uint16_t ids[KELP_CANBRIDGE_MAX_ROUTES];
    size_t n = 0;
    for (size_t i = 0; i < b->nfrom; i++) {
        int id = strpbrk(b->from_src[i], "*?") ? -1 : kelp_can_dict_id(&b->dict, b->from_src[i]);
        ids[n++] = id < 0 ? (uint16_t)KELP_CAN_VAR_NAMED : (uint16_t)id;
    }
    if (n == 0) { /* nothing comes in: keep the socket quiet with a filter nothing kelp matches */
        if (cap == 0) return 0;
        out[0].id = KELP_CAN_FILTER_EFF | (KELP_CAN_TAG << 21) | 0x1FFu;
        out[0].mask = KELP_CAN_FILTER_EFF | KELP_CAN_EFF_MASK; /* node 0 never sends */
        return 1;
    }
    return kelp_can_filters(ids, n, out, cap);
}

int kelp_canbridge_from_bus(kelp_canbridge *b, const kelp_var *v, kelp_can_emit_fn emit, void *user)
{
    if (v->flags & KELP_VAR_FLAG_BRIDGED) return 0;
    for (size_t i = 0; i < b->nto; i++) {
        if (!kelp_bus_match(b->to_src[i], v->name)) continue;
        kelp_can_msg m;
        kelp_can_msg_from_var(v, b->to_alias[i], &m);
        m.has_time = b->send_time;
        if (!b->send_source) m.source = NULL;
        int rc = kelp_can_send(&b->tx, &b->dict, &m, emit, user);
        if (rc < 0) {
            b->to_err++;
            return rc;
        }
        b->to_msgs++;
        b->to_frames += (unsigned long)rc;
        return rc;
    }
    return 0;
}

int kelp_canbridge_from_can(kelp_canbridge *b, const kelp_can_frame *f, kelp_time now, kelp_var *out)
{
    kelp_can_msg m;
    int rc = kelp_can_rx_frame(&b->rx, &b->dict, f, now, &m);
    if (rc <= 0) return rc;
    for (size_t i = 0; i < b->nfrom; i++) {
        if (!kelp_bus_match(b->from_src[i], m.name)) continue;
        rc = kelp_can_msg_to_var(&m, b->from_alias[i], now, out);
        if (rc < 0) return rc;
        out->flags |= KELP_VAR_FLAG_BRIDGED;
        b->from_msgs++;
        return 1;
    }
    b->not_routed++;
    return 0;
}
