/* Fuzz: uFldHazardSensor's hazard-file lines and block parameters, its config, sensor and
 * classify requests and node reports, and uFldPathCheck's mail. The first byte picks the case
 * and options; the rest is the text (NUL-terminated copy). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/hazardsensor.h>
#include <kelp/pathcheck.h>

static void check_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || !var[0] || strlen(var) >= KELP_MAX_NAME + KELP_NODEREPORT_MAX_FIELD || (is_string && !sval)) abort();
}

static kelp_hazardsensor_cfg C;
static kelp_hazardsensor H;
static kelp_pathcheck P;

static void hazard(uint8_t opt, const char *t)
{
    kelp_diag why = { 0 };
    kelp_hazardsensor_cfg_default(&C);
    unsigned before = C.nobjects;
    int rc = kelp_hazardsensor_hazard_line(&C, t, &why);
    if (rc < 0 && why.code == KELP_OK) abort();
    if (rc == 1 && C.nobjects != before + 1) abort();
    if (rc == 1 && (!C.object[0].label[0] || strlen(C.object[0].label) >= KELP_UHZ_LABEL_LEN)) abort();
    static const char *const keys[] = { "sensor_config", "hazard", "show_reports", "swath_length", "rn_algorithm",
                                        "default_hazard_color", "random_seed", "min_reset_interval" };
    kelp_diag_clear(&why);
    rc = kelp_hazardsensor_config(&C, keys[opt % 8], t, &why);
    if (rc < 0 && why.code == KELP_OK) abort();
    (void)kelp_hazardsensor_config(&C, "sensor_config", "width=25,exp=4,pclass=0.9,max=1", &why);
    (void)kelp_hazardsensor_config(&C, "sensor_config", "width=10,exp=6,pclass=0.95", &why);
    (void)kelp_hazardsensor_hazard_line(&C, "x=1,y=1,type=hazard,label=12", &why);
    (void)kelp_hazardsensor_hazard_line(&C, "x=-3,y=2,type=benign,label=b,hr=0.3,aspect=40,aspect_min=10,aspect_max=30", &why);
    C.ignore_resemblances = opt & 0x10;
    if (kelp_hazardsensor_init(&H, &C) != 0) abort();
    kelp_field_sink sink = { NULL, check_publish, NULL };
    static const char *const vars[] = { "NODE_REPORT", "UHZ_SENSOR_REQUEST", "UHZ_CONFIG_REQUEST",
                                        "UHZ_CLASSIFY_REQUEST" };
    (void)kelp_hazardsensor_mail(&H, "NODE_REPORT", "NAME=archie,X=0,Y=0,HDG=0", "archie", 0, &sink);
    (void)kelp_hazardsensor_mail(&H, "UHZ_SENSOR_REQUEST", "vname=archie", "archie", 0, &sink);
    for (int i = 0; i < 4; i++) {
        (void)kelp_hazardsensor_mail(&H, vars[(opt >> 5) % 4], t, "archie", i, &sink);
        (void)kelp_hazardsensor_mail(&H, vars[i], t, t, i, &sink);
        kelp_hazardsensor_iterate(&H, 40.0 * i, &sink);
    }
    char buf[4096];
    (void)kelp_hazardsensor_report(&H, t, 100, buf, sizeof buf);
    if (strlen(buf) >= sizeof buf) abort();
}

static void pathcheck(const char *t)
{
    kelp_pathcheck_cfg c;
    kelp_diag why = { 0 };
    kelp_pathcheck_cfg_default(&c);
    if (kelp_pathcheck_config(&c, "history_length", t, &why) < 0 && why.code == KELP_OK) abort();
    if (kelp_pathcheck_init(&P, &c) != 0) abort();
    kelp_field_sink sink = { NULL, check_publish, NULL };
    (void)kelp_pathcheck_mail(&P, "NODE_REPORT", true, "NAME=a,X=0,Y=0,TIME=1", 1, &sink);
    (void)kelp_pathcheck_mail(&P, "NODE_REPORT", true, t, 2, &sink);
    (void)kelp_pathcheck_mail(&P, "UPC_TRIP_RESET", true, t, 3, &sink);
    (void)kelp_pathcheck_iterate(&P, 3, &sink);
    char buf[2048];
    (void)kelp_pathcheck_report(&P, 4, 1, buf, sizeof buf);
    if (strlen(buf) >= sizeof buf) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 4096) return 0;
    char *t = malloc(size);
    memcpy(t, data + 1, size - 1);
    t[size - 1] = 0;
    if (data[0] & 0x80) pathcheck(t);
    else hazard(data[0], t);
    free(t);
    return 0;
}
