/* udpm_cork: a corked socket's postings arrive complete and in publication order.
 *
 *   udpm_cork URL gso|plain
 *
 * A receiver and a sender join URL's group. The sender corks, publishes 300 short messages
 * with a fragmented one (100 kB) in the middle, checks how many the receiver saw while corked
 * (the batches that filled: a multiple of the batch, never a partial one), uncorks, and the
 * receiver must then hold all 301 in order. Prints the sender's stats. Exit 0 on success.
 * With "gso" the sender must have used segmented sends (the URL leaves them on) and a message
 * may arrive padded: its payload, then only zero bytes, at most KELP_UDPM_PAD_MAX of them
 * (message 200 is 600 bytes, too long to share a send with its neighbours). With "plain"
 * (the URL says gso=0) none may be used and every payload arrives exactly. The receiver
 * reads a segmented send whole (UDP GRO) and splits it, unless its URL says gso=0. */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/udpm.h>
#include <kelp/udpm.h>

static int padded, gso_mode;
static char medium[600];

/* the payload message k was published with */
static size_t payload(int k, char *v, size_t cap)
{
    if (k == 200) {
        memcpy(v, medium, sizeof medium);
        return sizeof medium;
    }
    return (size_t)snprintf(v, cap, "value %d", k);
}

static int take(kelp_udpm_sock *r, int want, int *next, int wait_ms)
{
    int got = 0;
    for (;;) {
        kelp_udpm_msg m;
        int rc = kelp_udpm_sock_next(r, &m);
        if (rc == 1) {
            int k;
            if (strcmp(m.channel, "BIG") == 0) k = 150;
            else if (sscanf(m.channel, "C%d", &k) != 1) return fprintf(stderr, "FAIL: channel %s\n", m.channel), -1;
            if (k != *next) return fprintf(stderr, "FAIL: message %d arrived where %d was due\n", k, *next), -1;
            if (k == 150 && m.len != 100000) return fprintf(stderr, "FAIL: BIG has %zu bytes\n", m.len), -1;
            if (k != 150) {
                char v[sizeof medium];
                size_t n = payload(k, v, sizeof v);
                if (m.len < n || memcmp(m.data, v, n) != 0) return fprintf(stderr, "FAIL: message %d's payload\n", k), -1;
                if (m.len > n) {
                    if (!gso_mode) return fprintf(stderr, "FAIL: message %d padded without gso\n", k), -1;
                    if (m.len - n > KELP_UDPM_PAD_MAX) return fprintf(stderr, "FAIL: message %d: %zu bytes of padding\n", k, m.len - n), -1;
                    for (size_t i = n; i < m.len; i++)
                        if (m.data[i]) return fprintf(stderr, "FAIL: message %d: padding byte %zu is not zero\n", k, i), -1;
                    padded++;
                }
            }
            (*next)++;
            if (++got == want) return got;
            continue;
        }
        struct pollfd p = { kelp_udpm_sock_fd(r), POLLIN, 0 };
        if (poll(&p, 1, wait_ms) <= 0) return got;
    }
}

int main(int argc, char **argv)
{
    if (argc != 3) return fprintf(stderr, "usage: udpm_cork URL gso|plain\n"), 2;
    gso_mode = strcmp(argv[2], "gso") == 0;
    memset(medium, 'm', sizeof medium);
    kelp_diag d = { 0 };
    kelp_udpm_sock *r = kelp_udpm_sock_open(argv[1], &d), *s = kelp_udpm_sock_open_tx(argv[1], &d);
    if (!r || !s) return fprintf(stderr, "FAIL: open: %s\n", kelp_diag_text(&d)), 1;
    static uint8_t big[100000];
    memset(big, 'x', sizeof big);
    kelp_udpm_sock_cork(s, true);
    for (int k = 0; k < 301; k++) {
        char ch[16];
        int rc;
        if (k == 150) rc = kelp_udpm_sock_publish(s, "BIG", big, sizeof big);
        else {
            snprintf(ch, sizeof ch, "C%d", k);
            char pv[sizeof medium];
            size_t n = payload(k, pv, sizeof pv);
            rc = kelp_udpm_sock_publish(s, ch, pv, n);
        }
        if (rc != 0) return fprintf(stderr, "FAIL: publish %d: %d\n", k, rc), 1;
    }
    int next = 0;
    int early = take(r, 301, &next, 300);
    if (early < 0) return 1;
    printf("while corked: %d of 301 arrived\n", early);
    /* 0..149 went as two full batches and a flush before BIG, BIG itself; 151..300 wait
     * except for the full batches among them (64 each) */
    if (early == 301) return fprintf(stderr, "FAIL: everything arrived while corked\n"), 1;
    kelp_udpm_sock_cork(s, false);
    int rest = take(r, 301 - early, &next, 2000);
    if (rest < 0) return 1;
    kelp_udpm_sock_stats st;
    kelp_udpm_sock_get_stats(s, &st);
    printf("after uncork: %d more; sender: %llu sent in %llu batches, %llu errors\n", rest,
           (unsigned long long)st.sent, (unsigned long long)st.send_batches, (unsigned long long)st.send_errors);
    if (next != 301) return fprintf(stderr, "FAIL: %d of 301 arrived\n", next), 1;
    if (st.sent != 301 || st.send_batches < 4 || st.send_errors) return fprintf(stderr, "FAIL: sender stats\n"), 1;
    printf("segmented sends: %llu carrying %llu messages; %d arrived padded\n", (unsigned long long)st.gso_sends,
           (unsigned long long)st.gso_segments, padded);
    kelp_udpm_sock_stats rs;
    kelp_udpm_sock_get_stats(r, &rs);
    printf("receiver: %llu datagrams, %llu coalesced runs split\n", (unsigned long long)rs.rx.datagrams,
           (unsigned long long)rs.gro_runs);
    if (gso_mode && (st.gso_sends == 0 || padded == 0)) return fprintf(stderr, "FAIL: no segmented send or no padding\n"), 1;
    if (gso_mode && rs.gro_runs == 0) return fprintf(stderr, "FAIL: the receiver read no coalesced run\n"), 1;
    if (!gso_mode && rs.gro_runs != 0) return fprintf(stderr, "FAIL: coalesced runs with gso=0\n"), 1;
    if (!gso_mode && st.gso_sends != 0) return fprintf(stderr, "FAIL: segmented sends with gso=0\n"), 1;
    kelp_udpm_sock_close(s);
    kelp_udpm_sock_close(r);
    return 0;
}
