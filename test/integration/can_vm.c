/* Real-SocketCAN test, run inside the vcan microVM (test/integration/can_vm.sh) as a static
 * program. Three CAN_RAW sockets on vcan0:
 *   - kelp-canbridge's CAN side: kelp_canbridge + the SocketCAN port with kernel filters
 *     (what apps/kelp-canbridge runs; the community side is replaced by direct calls, the VM
 *     having no LCM),
 *   - the firmware node of firmware/can_node.c (publishes DEPTH, obeys THRUST_CMD, answers
 *     FW_STATUS),
 *   - an injector writing raw frames: a message with its frames out of order, one with a
 *     dropped frame, junk, and frames the kernel filters must keep from the bridge.
 * Then the interface goes down and up, and is deleted and re-added: both ports reopen and
 * the round trip works again. All of it in classic CAN, then in CAN FD.
 * Prints CAN_VM lines; exit status 0 when every check passed. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/socket.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <kelp/can.h>
#include <kelp/util.h>
#include <kelp/edge/can.h>
#include <kelp/canbridge.h>
#include "can_node.h"

static int failures;
#define CHECK(c, ...)                                                  \
    do {                                                               \
        if (!(c)) {                                                    \
            failures++;                                                \
            printf("CAN_VM FAIL %s:%d: %s: ", __FILE__, __LINE__, #c); \
            printf(__VA_ARGS__);                                       \
            printf("\n");                                              \
        }                                                              \
    } while (0)

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static kelp_canbridge B;
static kelp_can_port BP, FP;
static fw_node F;
static int inj = -1;
static double depth = 12.25;

/* what the bridge published into the "community" */
#define MAXPUB 16
static struct {
    char name[KELP_MAX_NAME];
    kelp_var v;
    unsigned long count;
} pubs[MAXPUB];

static const kelp_var *published(const char *name, unsigned long *count)
{
    for (int i = 0; i < MAXPUB; i++)
        if (strcmp(pubs[i].name, name) == 0) {
            if (count) *count = pubs[i].count;
            return &pubs[i].v;
        }
    if (count) *count = 0;
    return NULL;
}

static void publish(const kelp_var *v)
{
    for (int i = 0; i < MAXPUB; i++)
        if (strcmp(pubs[i].name, v->name) == 0 || pubs[i].name[0] == 0) {
            memcpy(pubs[i].name, v->name, sizeof pubs[i].name);
            pubs[i].v = *v;
            pubs[i].count++;
            return;
        }
}

static int port_emit(void *user, const kelp_can_frame *f)
{
    kelp_can_port *p = user;
    for (int tries = 0; tries < 100; tries++) {
        int rc = kelp_can_port_write(p, f);
        if (rc != KELP_ERR_NOSPACE) return rc;
        usleep(1000); /* the interface queue is full: let it drain */
    }
    return KELP_ERR_NOSPACE;
}

/* run both ends for ms milliseconds */
static void pump(int ms)
{
    static kelp_var out;
    double end = mono() + ms / 1000.0;
    while (mono() < end) {
        struct pollfd pf[2] = { { BP.fd, POLLIN, 0 }, { FP.fd, POLLIN, 0 } };
        (void)poll(pf, 2, 5);
        double now = mono();
        kelp_can_frame f;
        int rc;
        while ((rc = kelp_can_port_read(&BP, &f)) == 1)
            if (kelp_canbridge_from_can(&B, &f, now, &out) == 1) publish(&out);
        while ((rc = kelp_can_port_read(&FP, &f)) == 1) fw_node_frame(&F, &f, now);
        kelp_can_rx_expire(&B.rx, now);
        if (!FP.down) (void)fw_node_tick(&F, now, depth, port_emit, &FP);
        if (kelp_can_port_maintain(&BP) == 1) printf("CAN_VM bridge port reopened\n");
        if (kelp_can_port_maintain(&FP) == 1) printf("CAN_VM firmware port reopened\n");
    }
}

static void command(double thrust)
{
    static kelp_var v;
    memset(&v, 0, sizeof v);
    strcpy(v.name, "DESIRED_THRUST");
    strcpy(v.source, "pHelmIvP");
    strcpy(v.community, "alder");
    v.kind = KELP_VAR_DOUBLE;
    v.dval = thrust;
    int rc = kelp_canbridge_from_bus(&B, &v, port_emit, &BP);
    CHECK(rc >= 1, "bridge send rc %d", rc);
}

static void round_trip(double thrust, const char *what)
{
    unsigned long n_cmd = F.commands + 1;
    depth += 1.0;
    command(thrust);
    pump(400);
    CHECK(F.thrust == thrust && F.commands == n_cmd, "%s: firmware thrust %g commands %lu", what, F.thrust, F.commands);
    const kelp_var *d = published("NAV_DEPTH_FW", NULL);
    CHECK(d && d->dval == depth, "%s: NAV_DEPTH_FW %g want %g", what, d ? d->dval : -1, depth);
    CHECK(d && strcmp(d->source, "can2") == 0, "%s: source %s", what, d ? d->source : "-");
    const kelp_var *s = published("FW_STATUS", NULL);
    char want[64];
    char num[32];
    if (kelp_util_fmt_fixed(num, sizeof num, thrust, 2, true) < 0) snprintf(num, sizeof num, "%g", thrust);
    snprintf(want, sizeof want, "thrust=%s,commands=%lu", num, n_cmd);
    CHECK(s && strcmp(s->sval, want) == 0, "%s: FW_STATUS '%s' want '%s'", what, s ? s->sval : "-", want);
    printf("CAN_VM %s: THRUST_CMD %g reached the firmware; NAV_DEPTH_FW %g and FW_STATUS '%s' came back\n", what,
           thrust, d ? d->dval : -1, s ? s->sval : "-");
}

/* the injector writes a frame as a raw CAN_RAW socket */
static void inj_write(const kelp_can_frame *f, uint32_t flags)
{
    struct canfd_frame c;
    memset(&c, 0, sizeof c);
    c.can_id = f->id | flags;
    c.len = f->len;
    memcpy(c.data, f->data, f->len);
    size_t sz = f->fd ? CANFD_MTU : CAN_MTU;
    for (int tries = 0; tries < 100; tries++) {
        if (write(inj, &c, sz) == (ssize_t)sz) return;
        usleep(1000);
    }
    printf("CAN_VM injector write failed: %s\n", strerror(errno));
    failures++;
}

typedef struct rec {
    kelp_can_frame f[80];
    int n;
} rec;

static int rec_emit(void *user, const kelp_can_frame *f)
{
    rec *r = user;
    if (r->n >= 80) return KELP_ERR_NOSPACE;
    r->f[r->n++] = *f;
    return 0;
}

static const char *TEXT = "injected status: all thrusters nominal, leak sensors dry, battery 87 percent, "
                          "heading hold engaged, depth hold engaged, altimeter locked at 12.4 m, DVL bottom lock, "
                          "GPS fix stale (submerged), acoustic modem idle, payload logging at 10 Hz, no faults";

static void injector_tests(bool fd)
{
    static kelp_can_tx itx;
    static rec r;
    unsigned long n0, n1;
    CHECK(kelp_can_tx_init(&itx, 3, fd) == 0, "tx init");
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    m.name = "INJ_TEXT";
    m.kind = KELP_CAN_KIND_STRING;
    m.sval = (const uint8_t *)TEXT;
    m.slen = strlen(TEXT);

    /* 1. out of order: every frame reversed, first frame last */
    r.n = 0;
    CHECK(kelp_can_send(&itx, NULL, &m, rec_emit, &r) > 1, "encode");
    unsigned long ooo0 = B.rx.st.out_of_order;
    (void)published("INJ_TEXT", &n0);
    for (int i = r.n - 1; i >= 0; i--) inj_write(&r.f[i], CAN_EFF_FLAG);
    pump(200);
    const kelp_var *v = published("INJ_TEXT", &n1);
    CHECK(n1 == n0 + 1 && v && strcmp(v->sval, TEXT) == 0, "out-of-order message not delivered (%lu)", n1);
    CHECK(B.rx.st.out_of_order >= ooo0 + (unsigned long)r.n - 1, "out_of_order %lu", B.rx.st.out_of_order);
    printf("CAN_VM out of order: %d frames reversed, message delivered, out_of_order=%lu\n", r.n, B.rx.st.out_of_order);

    /* 2. a dropped frame: the message never completes and times out (counted) */
    r.n = 0;
    CHECK(kelp_can_send(&itx, NULL, &m, rec_emit, &r) > 2, "encode");
    unsigned long to0 = B.rx.st.timed_out;
    for (int i = 0; i < r.n; i++)
        if (i != 1) inj_write(&r.f[i], CAN_EFF_FLAG);
    pump(1300); /* bridge timeout is 1 s */
    (void)published("INJ_TEXT", &n1);
    CHECK(n1 == n0 + 1, "a message with a dropped frame was delivered");
    CHECK(B.rx.st.timed_out == to0 + 1, "timed_out %lu want %lu", B.rx.st.timed_out, to0 + 1);
    printf("CAN_VM dropped frame: not delivered, timed_out=%lu\n", B.rx.st.timed_out);

    /* 3. frames the kernel filter must keep away: other variable ids, other tags, standard ids
     *    (had they come through, foreign or not_routed would count them) */
    unsigned long fo0 = B.rx.st.foreign, nr0 = B.not_routed, cmd0 = F.commands;
    kelp_can_frame j;
    memset(&j, 0, sizeof j);
    j.len = 6;
    j.data[0] = 0x05;
    j.data[1] = KELP_CAN_KIND_I32;
    j.id = KELP_CAN_ID(4, 3, 0, 3); /* THRUST_CMD: the bridge does not take it from CAN */
    inj_write(&j, CAN_EFF_FLAG);
    j.id = KELP_CAN_ID(4, 3, 0, 7) ^ (1u << 23); /* another protocol's tag */
    inj_write(&j, CAN_EFF_FLAG);
    j.id = 0x123;
    inj_write(&j, 0); /* standard frame */
    pump(100);
    CHECK(B.rx.st.foreign == fo0 && B.not_routed == nr0, "kernel filters let frames through: foreign %lu "
          "not routed %lu", B.rx.st.foreign - fo0, B.not_routed - nr0);
    CHECK(F.commands == cmd0 + 1, "the firmware (filtering on THRUST_CMD) took the injected command");
    printf("CAN_VM kernel filters: 3 frames for others kept from the bridge; the firmware took the THRUST_CMD\n");

    /* 4. junk that passes the filters (kelp tag, named id): counted, nothing crashes */
    unsigned long bad0 = B.rx.st.bad_frame + B.rx.st.bad_body + B.rx.st.bad_crc + B.rx.st.duplicate + B.rx.st.slot_full;
    unsigned seed = 12345;
    for (int i = 0; i < 300; i++) {
        memset(&j, 0, sizeof j);
        seed = seed * 1103515245u + 12345u;
        j.id = KELP_CAN_ID(seed >> 29, 4 + (seed >> 8) % 8, seed >> 3, KELP_CAN_VAR_NAMED);
        j.fd = fd && (seed & 0x100u);
        j.len = j.fd ? kelp_can_fd_len((seed >> 12) % 65) : (uint8_t)((seed >> 12) % 9);
        for (int k = 0; k < 64; k++) {
            seed = seed * 1103515245u + 12345u;
            j.data[k] = (uint8_t)(seed >> 16);
        }
        inj_write(&j, CAN_EFF_FLAG);
        if (i % 50 == 49) pump(20);
    }
    pump(1200); /* let any junk half-messages time out */
    unsigned long bad1 = B.rx.st.bad_frame + B.rx.st.bad_body + B.rx.st.bad_crc + B.rx.st.duplicate + B.rx.st.slot_full;
    CHECK(bad1 > bad0 + 100, "junk counted %lu", bad1 - bad0);
    printf("CAN_VM junk: 300 frames, %lu counted bad (bad_frame=%lu bad_body=%lu bad_crc=%lu), timed_out=%lu\n",
           bad1 - bad0, B.rx.st.bad_frame, B.rx.st.bad_body, B.rx.st.bad_crc, B.rx.st.timed_out);
    /* and the bridge still works */
    r.n = 0;
    CHECK(kelp_can_send(&itx, NULL, &m, rec_emit, &r) > 1, "encode");
    for (int i = 0; i < r.n; i++) inj_write(&r.f[i], CAN_EFF_FLAG);
    pump(200);
    (void)published("INJ_TEXT", &n1);
    CHECK(n1 == n0 + 2, "message after junk not delivered (%lu)", n1);
}

static void sh(const char *cmd)
{
    int rc = system(cmd);
    if (rc != 0) printf("CAN_VM '%s' exit %d\n", cmd, rc);
}

static int run(bool fd)
{
    const char *mode = fd ? "FD" : "classic";
    kelp_diag why;
    kelp_diag_clear(&why);
    memset(pubs, 0, sizeof pubs);
    CHECK(kelp_canbridge_init(&B, 1, fd, 1.0) == 0, "init");
    CHECK(kelp_can_dict_parse(&B.dict, "3=THRUST_CMD, 7=DEPTH", &why) == 0, "dict");
    CHECK(kelp_canbridge_add(&B, true, "DESIRED_THRUST -> THRUST_CMD", &why) == 0, "to");
    CHECK(kelp_canbridge_add(&B, false, "DEPTH -> NAV_DEPTH_FW", &why) == 0, "from");
    CHECK(kelp_canbridge_add(&B, false, "[FW_STATUS, INJ_*]", &why) == 0, "from");
    kelp_can_filter f[8];
    size_t nf = kelp_canbridge_filters(&B, f, 8);
    if (kelp_can_port_open(&BP, &kelp_can_socketcan_ops, "vcan0", f, nf, fd) < 0) {
        printf("CAN_VM FAIL bridge open: %s\n", kelp_diag_text(&BP.diag));
        return 1;
    }
    CHECK(fw_node_init(&F, 2, fd) == 0, "fw init");
    const uint16_t fwvars[] = { FW_VAR_THRUST_CMD };
    kelp_can_filter ff[2];
    size_t nff = kelp_can_filters(fwvars, 1, ff, 2);
    if (kelp_can_port_open(&FP, &kelp_can_socketcan_ops, "vcan0", ff, nff, fd) < 0) {
        printf("CAN_VM FAIL firmware open: %s\n", kelp_diag_text(&FP.diag));
        return 1;
    }
    inj = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
    int on = 1;
    (void)setsockopt(inj, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on);
    struct sockaddr_can a = { .can_family = AF_CAN, .can_ifindex = (int)if_nametoindex("vcan0") };
    CHECK(bind(inj, (struct sockaddr *)&a, sizeof a) == 0, "injector bind: %s", strerror(errno));
    printf("CAN_VM %s: bridge node 1 (%zu kernel filters), firmware node 2, injector node 3\n", mode, nf);

    pump(150);
    round_trip(42.5, mode);
    round_trip(-13.75, mode);
    injector_tests(fd);

    /* the interface goes down and comes back */
    sh("ip link set vcan0 down");
    pump(200);
    CHECK(BP.went_down >= 1 && FP.went_down >= 1, "ports noticed down: %lu %lu", BP.went_down, FP.went_down);
    sh("ip link set vcan0 up");
    pump(800);
    CHECK(!BP.down && BP.reopened >= 1, "bridge reopened %lu (%s)", BP.reopened, kelp_diag_text(&BP.diag));
    round_trip(7.5, "after down/up");
    /* deleted and re-created: the old binding is gone, the reopen binds the new interface */
    close(inj);
    sh("ip link del vcan0");
    pump(200);
    sh("ip link add dev vcan0 type vcan && ip link set vcan0 mtu 72 && ip link set vcan0 up");
    pump(800);
    CHECK(!BP.down && BP.reopened >= 2, "bridge reopened %lu after re-create (%s)", BP.reopened, kelp_diag_text(&BP.diag));
    round_trip(99, "after re-create");
    a.can_ifindex = (int)if_nametoindex("vcan0");
    inj = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
    (void)setsockopt(inj, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on);
    CHECK(bind(inj, (struct sockaddr *)&a, sizeof a) == 0, "injector bind: %s", strerror(errno));
    printf("CAN_VM %s: bridge sent %lu messages in %lu frames; received %lu frames, %lu messages; went down %lu, "
           "reopened %lu\n",
           mode, B.to_msgs, B.to_frames, B.rx.st.frames, B.rx.st.messages, BP.went_down, BP.reopened);
    close(inj);
    kelp_can_port_close(&BP);
    kelp_can_port_close(&FP);
    return 0;
}

static void inj_open(void)
{
    int on = 1;
    struct sockaddr_can a = { .can_family = AF_CAN, .can_ifindex = (int)if_nametoindex("vcan0") };
    inj = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
    (void)setsockopt(inj, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on);
    CHECK(bind(inj, (struct sockaddr *)&a, sizeof a) == 0, "injector bind: %s", strerror(errno));
}

static void inject_message(int drop, bool reverse)
{
    static kelp_can_tx itx;
    static rec r;
    if (itx.node == 0) CHECK(kelp_can_tx_init(&itx, 3, false) == 0, "tx init");
    kelp_can_msg m;
    memset(&m, 0, sizeof m);
    m.name = "INJ_TEXT";
    m.kind = KELP_CAN_KIND_STRING;
    m.sval = (const uint8_t *)TEXT;
    m.slen = strlen(TEXT);
    r.n = 0;
    CHECK(kelp_can_send(&itx, NULL, &m, rec_emit, &r) > 2, "encode");
    for (int k = 0; k < r.n; k++) {
        int i = reverse ? r.n - 1 - k : k;
        if (i != drop) inj_write(&r.f[i], CAN_EFF_FLAG);
    }
}

/* The firmware node alone, next to the real kelp-canbridge (can_vm.sh's app test): obeys
 * THRUST_CMD, publishes DEPTH and FW_STATUS; the injector sends INJ_TEXT reversed, then with a
 * dropped frame, then junk, then once more whole. */
static int fwnode(double secs)
{
    memset(&BP, 0, sizeof BP);
    BP.fd = -1;
    CHECK(fw_node_init(&F, 2, false) == 0, "fw init");
    const uint16_t fwvars[] = { FW_VAR_THRUST_CMD };
    kelp_can_filter ff[2];
    size_t nff = kelp_can_filters(fwvars, 1, ff, 2);
    if (kelp_can_port_open(&FP, &kelp_can_socketcan_ops, "vcan0", ff, nff, false) < 0) {
        printf("FWNODE FAIL open: %s\n", kelp_diag_text(&FP.diag));
        return 1;
    }
    inj_open();
    double t0 = mono(), done = 0, t_cmd = 0;
    int step = 0;
    /* until the third command has been answered (or secs). The injections are timed from the
     * first command: it proves kelp-canbridge is up and reading vcan0 (under TCG on a loaded
     * host the bridge can take seconds to start, and frames sent before it opens are lost). */
    while (mono() - t0 < secs && !(done > 0 && mono() > done)) {
        if (done == 0 && F.commands >= 3) done = mono() + 1.0;
        pump(50);
        if (t_cmd == 0 && F.commands >= 1) t_cmd = mono();
        double t = t_cmd > 0 ? mono() - t_cmd + 1.5 : 0;
        if (step == 0 && t > 3.0) inject_message(-1, true), step++;
        else if (step == 1 && t > 3.5) inject_message(2, false), step++;
        else if (step == 2 && t > 4.0) {
            kelp_can_frame j;
            unsigned seed = 777;
            for (int i = 0; i < 100; i++) {
                memset(&j, 0, sizeof j);
                seed = seed * 1103515245u + 12345u;
                j.id = KELP_CAN_ID(4, 3, seed >> 27, KELP_CAN_VAR_NAMED);
                j.len = (uint8_t)((seed >> 12) % 9);
                for (int k = 0; k < 8; k++) j.data[k] = (uint8_t)(seed >> (k + 8));
                j.data[0] = (uint8_t)(0xC0u | (seed >> 20)); /* reserved PCI: certainly bad */
                if (j.len == 0) j.len = 1;
                inj_write(&j, CAN_EFF_FLAG);
            }
            step++;
        } else if (step == 3 && t > 5.5) {
            inject_message(-1, false);
            step++;
        }
    }
    printf("FWNODE commands=%lu thrust=%g\n", F.commands, F.thrust);
    return failures ? 1 : 0;
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IONBF, 0);
    if (argc > 2 && strcmp(argv[1], "fwnode") == 0) return fwnode(atof(argv[2]));
    if (run(false) != 0 || run(true) != 0) failures++;
    printf("CAN_VM %s (%d failures)\n", failures ? "FAILED" : "PASSED", failures);
    return failures ? 1 : 0;
}
