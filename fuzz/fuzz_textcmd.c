/* Fuzz: the one-line text commands apps take from the bus and small config files --
 * POLLER_COMMAND, USM_RESET (a START_POS value), the modem-id lookup file, the bridge's
 * UDPSHARE and PMB_REGISTER lines and its ALLOW list, the simulator's and the marine PID's
 * "KEY=value" configuration (THRUST_MAP, DRIFT_VECTOR ...), pNodeReporter's rider and
 * plat_report_input, the helm's Domain lines, pHostInfo's mail. The first byte picks the parser;
 * the rest is the text (NUL-terminated copy of exact size). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/poller.h>
#include <kelp/bridge.h>
#include <kelp/dccl.h>
#include <kelp/modemsim.h>
#include <kelp/field.h>
#include <kelp/helm.h>
#include <kelp/pid.h>
#include <kelp/sim.h>

static void nop_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || (is_string && !sval)) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    size_t n = size - 1;
    char *t = malloc(n + 1);
    memcpy(t, data + 1, n);
    t[n] = 0;
    const char *why = NULL;
    kelp_diag dg = { 0 }; /* the field and sim modules' reason */
    switch (data[0] % 9) {
    case 0: {
        /* a list with a slot in it, then a command: all-or-nothing, the list stays sane */
        static kelp_poller_list l;
        memset(&l, 0, sizeof l);
        l.default_seconds = 15;
        if (kelp_poller_add(&l, "src=1,dest=2", NULL) != 0) abort();
        kelp_poller_list before = l;
        int rc = kelp_poller_command(&l, t, NULL);
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
        kelp_diag dg;
        kelp_diag_clear(&dg);
        if (kelp_bridge_parse_share(t, r, 16, &nr, &dg) == 0 && nr > 16) abort();
        (void)kelp_bridge_parse_register(t, r, &dg);
        break;
    }
    case 5: {
        /* "KEY=value" for the simulator, then the marine PID */
        char *eq = strchr(t, '=');
        if (eq) {
            *eq = 0;
            kelp_sim_params p;
            kelp_sim_state st;
            memset(&st, 0, sizeof st);
            kelp_sim_params_default(&p);
            if (kelp_sim_config_set(&p, &st, t, eq + 1, &dg) > 0 && p.nmap > KELP_SIM_MAX_MAP) abort();
            kelp_pid_marine_cfg c;
            kelp_pid_marine_cfg_default(&c);
            (void)kelp_pid_marine_cfg_set(&c, t, eq + 1, &dg);
        }
        break;
    }
    case 6: {
        kelp_field_nrep_cfg c;
        kelp_field_nrep_cfg_default(&c, "alpha");
        (void)kelp_field_nrep_add_rider(&c, t, &dg);
        (void)kelp_field_nrep_add_plat(&c, t, &dg);
        kelp_nrep_fill f;
        (void)kelp_field_nrep_parse_fill(t, &f);
        if (c.nriders > KELP_NREP_MAX_RIDERS || c.nplat > KELP_NREP_MAX_PLAT) abort();
        break;
    }
    case 7: {
        static kelp_helm_config hc;
        kelp_helm_config_default(&hc);
        kelp_diag hd = {0};
        (void)kelp_helm_config_add_domain(&hc, t, &hd);
        break;
    }
    case 8: {
        static kelp_field_hostinfo h;
        kelp_field_hostinfo_cfg c;
        kelp_field_hostinfo_cfg_default(&c);
        kelp_field_hostinfo_init(&h, &c);
        (void)kelp_field_hostinfo_mail(&h, (data[0] & 16) ? "PMB_UDP_LISTEN" : "PSHARE_INPUT_SUMMARY", true, t, 0);
        const char *names[1] = { "eth0" }, *ips[1] = { t };
        kelp_field_hostinfo_set(&h, names, ips, 1);
        kelp_field_sink sink = { NULL, nop_publish, NULL };
        (void)kelp_field_hostinfo_iterate(&h, &sink);
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
