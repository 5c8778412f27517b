/* kelp-ivp cpa CNX CNY CNH CNV OSX OSY OSH OSV [TOL]: the CPA engine's view of one encounter,
 * one name=value line per quantity (src/ivp/cpa.c does the arithmetic). */
#include <stdio.h>
#include <string.h>
#include <kelp/cpa.h>
#include <kelp/util.h>
#include "cli.h"

static void num(const char *name, double v)
{
    char buf[64];
    if (kelp_util_fmt_fixed(buf, sizeof buf, v, 6, true) < 0)
        (void)snprintf(buf, sizeof buf, "%g", v);
    printf("%s=%s\n", name, buf);
}

static void flag(const char *name, bool v)
{
    printf("%s=%s\n", name, v ? "true" : "false");
}

int kivp_cmd_cpa(int argc, char **argv)
{
    if (argc != 10 && argc != 11)
        return kivp_usage();
    double a[9] = {0, 0, 0, 0, 0, 0, 0, 0, 120};
    for (int i = 2; i < argc; i++)
        if (kelp_util_parse_double(argv[i], strlen(argv[i]), &a[i - 2]) != 0) {
            fprintf(stderr, "kelp-ivp: cpa: '%s' is not a number\n", argv[i]);
            return 1;
        }
    kelp_cpa_vessel cn = {a[0], a[1], a[2], a[3]}, os = {a[4], a[5], a[6], a[7]};
    kelp_cpa_result r;
    if (kelp_cpa_eval(&cn, &os, a[8], &r) != KELP_OK) {
        fprintf(stderr, "kelp-ivp: cpa: arguments must be finite numbers\n");
        return 1;
    }
    num("cpa", r.cpa);
    num("tcpa", r.tcpa);
    num("roc", r.roc);
    num("range", r.range);
    num("bearing_rate", r.bearing_rate);
    num("rel_bearing", r.rel_bearing);
    num("abs_bearing", r.abs_bearing);
    num("cn_rel_bearing", r.cn_rel_bearing);
    flag("cn_fore_of_os", r.cn_fore_of_os);
    flag("cn_aft_of_os", r.cn_aft_of_os);
    flag("cn_port_of_os", r.cn_port_of_os);
    flag("cn_star_of_os", r.cn_star_of_os);
    flag("os_fore_of_cn", r.os_fore_of_cn);
    flag("os_aft_of_cn", r.os_aft_of_cn);
    flag("os_port_of_cn", r.os_port_of_cn);
    flag("os_star_of_cn", r.os_star_of_cn);
    flag("os_crosses_cn_bow", r.os_crosses_cn_bow);
    num("os_crosses_cn_bow_dist", r.os_crosses_cn_bow_dist);
    flag("os_crosses_cn_stern", r.os_crosses_cn_stern);
    num("os_crosses_cn_stern_dist", r.os_crosses_cn_stern_dist);
    flag("os_passes_cn_port", r.os_passes_cn_port);
    num("os_passes_cn_port_dist", r.os_passes_cn_port_dist);
    flag("os_passes_cn_star", r.os_passes_cn_star);
    num("os_passes_cn_star_dist", r.os_passes_cn_star_dist);
    flag("cn_crosses_os_bow", r.cn_crosses_os_bow);
    num("cn_crosses_os_bow_dist", r.cn_crosses_os_bow_dist);
    flag("cn_crosses_os_stern", r.cn_crosses_os_stern);
    num("cn_crosses_os_stern_dist", r.cn_crosses_os_stern_dist);
    flag("cn_passes_os_port", r.cn_passes_os_port);
    num("cn_passes_os_port_dist", r.cn_passes_os_port_dist);
    flag("cn_passes_os_star", r.cn_passes_os_star);
    num("cn_passes_os_star_dist", r.cn_passes_os_star_dist);
    return 0;
}
