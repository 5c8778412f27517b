/* Fuzz: uTimerScript's text parsers and expansion -- an event line, a rand_var line, any other
 * parameter, then a script built from what was accepted, run against mail carrying the text
 * (pause / forward / reset commands, conditions' variables) with the value expanded.
 * The first byte picks the parameter; the rest is the text. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/timerscript.h>

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || !*var || (is_string && (!sval || strlen(sval) >= KELP_TS_MAX_VAL))) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const keys[] = { "event", "rand_var", "condition", "time_warp", "delay_start",
                                        "reset_time", "reset_max", "block_on" };
    static kelp_timerscript_cfg c;
    static kelp_timerscript ts;
    if (size < 1) return 0;
    size_t n = size - 1;
    char *t = malloc(n + 1);
    memcpy(t, data + 1, n);
    t[n] = 0;
    kelp_timerscript_cfg_default(&c, "uTimerScript", "alpha");
    kelp_diag why = { 0 };
    (void)kelp_timerscript_cfg_set(&c, "event", "var=FIXED, val=x=$[X]|{2+3}|$(3)|$[DBTIME], time=0", &why);
    (void)kelp_timerscript_cfg_set(&c, "rand_var", "varname=X, min=0, max=9, key=at_post", &why);
    unsigned nev = c.nev, nrv = c.nrv;
    int rc = kelp_timerscript_cfg_set(&c, keys[data[0] % 8], t, &why);
    if (rc < 0 && why.code == KELP_OK) abort();
    if (rc < 0 && (c.nev != nev || c.nrv != nrv)) abort(); /* refused: nothing added */
    if (c.nev > KELP_TS_MAX_EVENTS || c.nrv > KELP_TS_MAX_RANDVARS) abort();
    if (kelp_timerscript_init(&ts, &c, data[0]) == 0) {
        kelp_field_sink sink = { NULL, pub, NULL };
        const char *vars[] = { "UTS_PAUSE", "UTS_FORWARD", "UTS_RESET", "DB_CLIENTS", "GO" };
        for (int i = 0; i < 5; i++) (void)kelp_timerscript_mail(&ts, vars[i], (data[0] & 8) != 0, t, 3, 100, &sink);
        for (double now = 100; now < 200; now += 7) (void)kelp_timerscript_iterate(&ts, now, &sink);
        char out[KELP_TS_MAX_VAL];
        double d;
        if (kelp_timerscript_expand(&ts, t, 200, out, sizeof out, &d) >= 0 && strlen(out) >= sizeof out) abort();
    }
    free(t);
    return 0;
}
