/* kelp-acomms-replay (private). */
#ifndef KELP_ACOMMS_REPLAY_H
#define KELP_ACOMMS_REPLAY_H
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <kelp/mmdriver.h>

int replay_main(int argc, char **argv);

/* the Micro-Modem driver on the timeline (modem.c) */
typedef struct rmodem {
    kelp_mmdriver mm;
    bool on;
    FILE *out;
    int64_t start_us;
} rmodem;

int rmodem_start(rmodem *m, int modem_id, FILE *out, int64_t start_us, int64_t now_us);
void rmodem_tick(rmodem *m, int64_t now_us);
int rmodem_feed(rmodem *m, const char *line, int64_t now_us);
int rmodem_cycle(rmodem *m, unsigned rate, const kelp_mmdriver_frame *frames, size_t n, int64_t now_us);
#endif
