/* kelp-acomms-replay (private). */
#ifndef KELP_ACOMMS_REPLAY_H
#define KELP_ACOMMS_REPLAY_H
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <kelp/acomms.h>
#include <kelp/mmdriver.h>

#define TICK_US 100000LL /* Goby's do_work at AppTick 10 */

/* The replay's clock counts whole microseconds (the timeline's steps are exact); the core
 * takes kelp_time seconds. */
static inline kelp_time replay_sec(int64_t us) { return (kelp_time)us / 1e6; }
static inline int64_t replay_us(kelp_time t) { return (int64_t)llround(t * 1e6); }
#define MAX_LINE 4096

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

/* the replay: pAcommsHandler's core handler (queues, MAC, node, DCCL codec) on the timeline */
typedef struct replay {
    kelp_acomms_config cfg;
    kelp_acomms_dccl *dccl;
    kelp_acomms_codec codec;
    kelp_acomms_handler h;
    kelp_queue_entry *pool;
    int64_t start_us, now_us;
    bool auto_request;
    FILE *out;
    unsigned long lineno;
    unsigned long errors;
    rmodem modem;           /* the Micro-Modem driver, after "modem start" */
} replay;

/* output (timeline.c) */
const char *replay_name_of(const replay *r, kelp_queue_key key);
void replay_stamp(replay *r);
void replay_hex(FILE *f, const uint8_t *d, size_t n);
void replay_error(replay *r, const char *fmt, ...) KELP_PRINTF(2, 3);
void replay_on_event(void *ctx, const kelp_acomms_event *ev);
void replay_run_line(replay *r, char *line);

/* words of a command (timeline.c) */
bool replay_num(const char *s, double *out);
bool replay_int(const char *s, long *out);
const char *replay_opt(char **w, int n, const char *key);
bool replay_known_opts(replay *r, char **w, int n, const char *const *keys);
int replay_hex_bytes(const char *h, uint8_t *out, size_t cap, size_t *n);

/* commands (commands.c) */
void cmd_push(replay *r, char **w, int n);
void cmd_push_ccl(replay *r, char **w, int n);
void cmd_data_request(replay *r, char **w, int n);
void cmd_ack(replay *r, char **w, int n);
void cmd_flush(replay *r, char **w, int n);
void cmd_receive(replay *r, char **w, int n);
void cmd_transmit(replay *r, char **w, int n);
void cmd_modem(replay *r, char **w, int n);
void cmd_cycle(replay *r, char **w, int n);
void cmd_status(replay *r);
#endif
