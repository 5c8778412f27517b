/* CAN framing speed for bench/can.sh: encode (kelp_can_send) + reassemble (kelp_can_rx_frame)
 * in one thread, no I/O, for classic and FD frames and three messages:
 *   dict-f32   a dictionary variable with a float value (one frame either way)
 *   named-f64  a named variable with time and a double (several classic frames)
 *   text-200   a named 200-byte string
 * Prints, per case: frames per message, frames/s and messages/s through encode+decode, and
 * the latency of one message (first frame encoded -> message delivered) median and p99. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/can.h>

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct ctx {
    kelp_can_rx *rx;
    const kelp_can_dict *d;
    int delivered;
    unsigned long frames;
} ctx;

/* every emitted frame goes straight into the receiver */
static int emit(void *user, const kelp_can_frame *f)
{
    ctx *c = user;
    kelp_can_msg m;
    c->frames++;
    if (kelp_can_rx_frame(c->rx, c->d, f, 0, &m) == 1) c->delivered++;
    return 0;
}

static kelp_can_tx tx;
static kelp_can_rx rx;

#define N 200000
#define LAT 20001
static double lat[LAT];

int main(void)
{
    kelp_can_dict d;
    kelp_diag why;
    kelp_diag_clear(&why);
    kelp_can_dict_init(&d);
    if (kelp_can_dict_parse(&d, "3=THRUST_CMD,7=DEPTH", &why) < 0) return 1;
    char text[201];
    memset(text, 'a', 200);
    text[200] = 0;
    for (int fd = 0; fd < 2; fd++) {
        for (int k = 0; k < 3; k++) {
            kelp_can_msg m;
            memset(&m, 0, sizeof m);
            const char *label = k == 0 ? "dict-f32" : k == 1 ? "named-f64" : "text-200";
            m.kind = k == 2 ? KELP_CAN_KIND_STRING : KELP_CAN_KIND_F64;
            m.name = k == 0 ? "DEPTH" : k == 1 ? "NAV_HEADING_OVER_GROUND" : "VEHICLE_STATUS";
            m.dval = k == 0 ? 12.25 : 123.456789;
            m.has_time = k == 1;
            m.time = 1700000000.5;
            m.sval = (const uint8_t *)text;
            m.slen = k == 2 ? 200 : 0;
            if (kelp_can_tx_init(&tx, 5, fd != 0) < 0) return 1;
            kelp_can_rx_init(&rx, 1.0);
            ctx c = { &rx, &d, 0, 0 };
            int iters = k == 2 ? N / 10 : N;
            double t0 = now_ns();
            for (int i = 0; i < iters; i++)
                if (kelp_can_send(&tx, &d, &m, emit, &c) < 0) return 1;
            double dt = (now_ns() - t0) / 1e9;
            unsigned long timed_frames = c.frames;
            if (c.delivered != iters) {
                fprintf(stderr, "delivered %d of %d\n", c.delivered, iters);
                return 1;
            }
            for (int i = 0; i < LAT; i++) {
                double a = now_ns();
                if (kelp_can_send(&tx, &d, &m, emit, &c) < 0) return 1;
                lat[i] = now_ns() - a;
            }
            qsort(lat, LAT, sizeof lat[0], cmp);
            printf("%-7s %-9s %2lu frames/msg  %6.2f M frames/s  %6.2f M msgs/s  latency median %5.0f ns  p99 %5.0f ns\n",
                   fd ? "FD" : "classic", label, timed_frames / (unsigned long)iters, timed_frames / dt / 1e6,
                   iters / dt / 1e6, lat[LAT / 2], lat[LAT * 99 / 100]);
        }
    }
    return 0;
}
