/* kelp bus: in-process loopback transport (for unit tests and single-image firmware). */
#include <string.h>
#include <kelp/bus.h>
#include <kelp/loopback.h>

void kelp_loopback_init(kelp_loopback *net)
{
    memset(net, 0, sizeof *net);
}

void kelp_loopback_set_time(kelp_loopback *net, kelp_time now)
{
    net->now = now;
}

static int lb_subscribe(void *ctx, const char *pattern)
{
    /* Every client sees every datagram; the bus core filters by its registrations. */
    (void)ctx;
    (void)pattern;
    return KELP_OK;
}

/* The FIFO is linear: it is reset whenever it drains, and a record that does not fit is
 * dropped (counted) rather than wrapped. */
static int lb_publish(void *ctx, const char *channel, const uint8_t *data, size_t len)
{
    kelp_loopback *net = ((kelp_loopback_port *)ctx)->net;
    size_t clen = strlen(channel);
    size_t need = 2 + clen + 1 + 4 + len;
    if (clen > 0xffff || len > 0xffffffffu) return KELP_ERR_ARG;
    if (need > sizeof net->fifo - net->tail) {
        net->dropped++;
        return KELP_ERR_NOSPACE;
    }
    uint8_t *p = net->fifo + net->tail;
    p[0] = (uint8_t)(clen >> 8);
    p[1] = (uint8_t)clen;
    memcpy(p + 2, channel, clen + 1);
    p += 2 + clen + 1;
    p[0] = (uint8_t)(len >> 24);
    p[1] = (uint8_t)(len >> 16);
    p[2] = (uint8_t)(len >> 8);
    p[3] = (uint8_t)len;
    if (len) memcpy(p + 4, data, len);
    net->tail += need;
    if (!net->pumping) kelp_loopback_pump(net);
    return KELP_OK;
}

void kelp_loopback_pump(kelp_loopback *net)
{
    if (net->pumping) return;
    net->pumping = true;
    while (net->head < net->tail) {
        const uint8_t *p = net->fifo + net->head;
        size_t clen = ((size_t)p[0] << 8) | p[1];
        const char *chan = (const char *)(p + 2);
        const uint8_t *q = p + 2 + clen + 1;
        size_t len = ((size_t)q[0] << 24) | ((size_t)q[1] << 16) | ((size_t)q[2] << 8) | q[3];
        net->head += 2 + clen + 1 + 4 + len;
        for (size_t i = 0; i < net->nclients; i++)
            KELP_IGNORE(kelp_bus_receive(net->clients[i], chan, q + 4, len, net->now));
    }
    net->head = net->tail = 0;
    net->pumping = false;
}

void kelp_loopback_transport(kelp_loopback *net, kelp_loopback_port *port, kelp_bus_transport *tr)
{
    port->net = net;
    tr->publish = lb_publish;
    tr->subscribe = lb_subscribe;
    tr->ctx = port;
}

int kelp_loopback_attach(kelp_loopback *net, kelp_bus *b)
{
    if (net->nclients >= KELP_MAX_LOOPBACK_CLIENTS) return KELP_ERR_NOSPACE;
    net->clients[net->nclients++] = b;
    return KELP_OK;
}
