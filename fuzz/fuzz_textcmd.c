/* Fuzz: the one-line text commands apps take from the bus and small config files --
 * POLLER_COMMAND, USM_RESET (a START_POS value), the modem-id lookup file, the bridge's
 * UDPSHARE and PMB_REGISTER lines and its ALLOW list. The first byte picks the parser;
 * the rest is the text (NUL-terminated copy of exact size). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/bridge.h>
#include <kelp/dccl.h>
#include <kelp/modemsim.h>
#include <kelp/sim.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    size_t n = size - 1;
    char *t = malloc(n + 1);
    memcpy(t, data + 1, n);
    t[n] = 0;
    const char *why = NULL;
    switch (data[0] % 5) {
    case 0: {
        /* a list with a slot in it, then a command: all-or-nothing, the list stays sane */
        static kelp_poller_list l;
        memset(&l, 0, sizeof l);
        l.default_seconds = 15;
        if (kelp_poller_add(&l, "src=1,dest=2", &why) != 0) abort();
        kelp_poller_list before = l;
        int rc = kelp_poller_command(&l, t, &why);
        if (l.n > KELP_MAX_MSIM_POLL_SLOTS) abort();
        if (rc < 0 && memcmp(&before, &l, sizeof l) != 0) abort(); /* refused: unchanged */
        (void)kelp_poller_cycle_seconds(&l);
        break;
    }
    case 1: {
        kelp_sim_state st;
        memset(&st, 0, sizeof st);
        (void)kelp_sim_parse_start(t, &st);
        break;
    }
    case 2: {
        static kelp_dccl_modem_entry modems[8];
        kelp_dccl_builtin bi;
        kelp_dccl_builtin_init(&bi, modems, 8);
        (void)kelp_dccl_builtin_parse_modems(&bi, t, n);
        break;
    }
    case 3: {
        kelp_bridge_route r[16];
        size_t nr = 0;
        if (kelp_bridge_parse_share(t, r, 16, &nr, &why) == 0 && nr > 16) abort();
        (void)kelp_bridge_parse_register(t, r, &why);
        break;
    }
    default: {
        /* "ALLOW-list|name" */
        char *bar = strchr(t, '|');
        if (bar) {
            *bar = 0;
            (void)kelp_bridge_allowed(t, bar + 1);
        }
        break;
    }
    }
    free(t);
    return 0;
}
