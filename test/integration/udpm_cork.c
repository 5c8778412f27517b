/* udpm_cork: a corked socket's postings arrive complete and in publication order.
 *
 *   udpm_cork URL
 *
 * A receiver and a sender join URL's group. The sender corks, publishes 300 short messages
 * with a fragmented one (100 kB) in the middle, checks how many the receiver saw while corked
 * (the batches that filled: a multiple of the batch, never a partial one), uncorks, and the
 * receiver must then hold all 301 in order. Prints the sender's stats. Exit 0 on success. */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/udpm.h>

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
    if (argc != 2) return fprintf(stderr, "usage: udpm_cork URL\n"), 2;
    kelp_diag d = { 0 };
    kelp_udpm_sock *r = kelp_udpm_sock_open(argv[1], &d), *s = kelp_udpm_sock_open_tx(argv[1], &d);
    if (!r || !s) return fprintf(stderr, "FAIL: open: %s\n", kelp_diag_text(&d)), 1;
    static uint8_t big[100000];
    memset(big, 'x', sizeof big);
    kelp_udpm_sock_cork(s, true);
    for (int k = 0; k < 301; k++) {
        char ch[16], v[32];
        int rc;
        if (k == 150) rc = kelp_udpm_sock_publish(s, "BIG", big, sizeof big);
        else {
            snprintf(ch, sizeof ch, "C%d", k);
            int n = snprintf(v, sizeof v, "value %d", k);
            rc = kelp_udpm_sock_publish(s, ch, v, (size_t)n);
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
    kelp_udpm_sock_close(s);
    kelp_udpm_sock_close(r);
    return 0;
}
