/* Fuzz: behaviour files (.bhv through the mission parser and kelp_helm_load_bhv), run
 * conditions, point lists, and helm iterations fed with the input as mail (UPDATES strings,
 * condition variables, NAV_X/NAV_Y, spawn requests to templates, NODE_REPORT). Nothing may crash, hang or read out of bounds. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/helm.h>
#include <kelp/mission.h>

static kelp_helm g_h;
static kelp_ivp_piece g_pool[8192], g_tmp[2048];
static double g_dwork[2048];
static kelp_ivp_pq_entry g_pq[4096];
static unsigned char g_solve[2 << 20];
static kelp_mission_node g_nodes[256];

static void sink(const kelp_helm_post *p, void *user)
{
    (void)user;
    if (!p->var || (p->is_str && !p->sval))
        abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 8192)
        return 0;
    char *z = malloc(size + 1);
    memcpy(z, data, size);
    z[size] = '\0';
    /* stand-alone parsers */
    static kelp_helm_ib ib;
    kelp_helm_ib_init(&ib);
    (void)kelp_helm_ib_set_double(&ib, "K", 4, 0, false);
    (void)kelp_helm_ib_set_string(&ib, "DEPLOY", "true", 0, false);
    int c = kelp_helm_cond_eval(z, &ib);
    if (c != 0 && c != 1 && c != KELP_ERR_PARSE)
        abort();
    if ((c == KELP_ERR_PARSE) != (kelp_helm_cond_check(z, NULL, NULL) == KELP_ERR_PARSE))
        abort();
    kelp_bhv_pt pts[KELP_HELM_MAX_PTS];
    unsigned n = 0;
    if (kelp_helm_parse_points(z, pts, KELP_HELM_MAX_PTS, &n) == 0 && (n == 0 || n > KELP_HELM_MAX_PTS))
        abort();
    /* the input as a behaviour file */
    kelp_helm_config cfg;
    kelp_helm_config_default(&cfg);
    cfg.start_engaged = true; /* driving from the start (the default parks, as 24.8) */
    kelp_diag e = {0};
    if (kelp_ivp_domain_parse(&cfg.domain, "course:0:359:36,speed:0:4:9,depth:0:100:11", &e) != 0)
        abort();
    cfg.optional[2] = true;
    cfg.sink = sink;
    kelp_helm_mem mem = {g_pool, 8192, g_tmp, 2048, g_dwork, 2048, g_pq, 4096, g_solve, sizeof g_solve};
    if (kelp_helm_init(&g_h, &cfg, &mem) != 0)
        abort();
    char *text = malloc(size + 1);
    memcpy(text, z, size + 1);
    kelp_mission m;
    if (kelp_mission_parse(&m, text, size, g_nodes, 256) == 0 && kelp_helm_load_bhv(&g_h, &m) == 0 &&
        kelp_helm_configured(&g_h) == 0) {
        kelp_helm_start(&g_h, 100);
        for (int i = 0; i < 3; i++) {
            kelp_helm_mail_double(&g_h, "NAV_X", (double)(size % 97) - 40 + i);
            kelp_helm_mail_double(&g_h, "NAV_Y", (double)(size % 53) - 20);
            for (unsigned b = 0; b < g_h.nbhv; b++) {
                if (g_h.bhv[b].updates[0])
                    kelp_helm_mail_string(&g_h, g_h.bhv[b].updates, z);
                for (unsigned k = 0; k < g_h.bhv[b].nstarve; k++)
                    kelp_helm_mail_double(&g_h, g_h.bhv[b].starve[k], 1);
            }
            for (unsigned t = 0; t < g_h.ntmpl; t++) /* spawn requests and contact reports */
                if (g_h.tmpl[t].updates[0])
                    kelp_helm_mail_string(&g_h, g_h.tmpl[t].updates, z);
            kelp_helm_mail_string(&g_h, "NODE_REPORT", z);
            kelp_helm_mail_double(&g_h, "NAV_HEADING", 45);
            kelp_helm_mail_double(&g_h, "NAV_SPEED", 1);
            kelp_helm_mail_string(&g_h, "DEPLOY", "true");
            if (kelp_helm_iterate(&g_h, 100 + i) != 0)
                abort();
        }
    } else if (g_h.diag.code == KELP_OK && kelp_mission_parse(&m, text, size, g_nodes, 256) == 0) {
        abort(); /* a refused file always says why */
    }
    free(text);
    free(z);
    return 0;
}
