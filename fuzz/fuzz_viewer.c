/* Fuzz: kelp-viewer's mail path (NODE_REPORT, every VIEW_* kind and APPCAST into the model, time
 * moving, the JSON out after each) and its button / action configuration lines. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/viewer.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const vars[] = {"NODE_REPORT", "NODE_REPORT_LOCAL", "VIEW_POINT", "VIEW_CIRCLE",
                                       "VIEW_POLYGON", "VIEW_SEGLIST", "VIEW_MARKER", "VIEW_COMMS_PULSE",
                                       "VIEW_RANGE_PULSE", "button_one", "action", "action+", "APPCAST"};
    static kelp_viewer *v;
    static char out[1 << 18];
    if (!v) {
        v = malloc(sizeof *v);
        if (!v) return 0;
        kelp_viewer_init(v);
        if (kelp_viewer_set_datum(v, 43.8253, -70.3304) < 0) abort();
        (void)kelp_viewer_config(v, "trails_length", "8", NULL);
    }
    if (size < 1) return 0;
    unsigned which = data[0] % (sizeof vars / sizeof vars[0]);
    /* exact-length copy: the parsers must not read past len; a NUL-terminated one for config */
    char *s = malloc(size);
    memcpy(s, data + 1, size - 1);
    s[size - 1] = '\0';
    static double now;
    now += (data[0] >> 4) * 0.5;
    if (which >= 9 && which <= 11) {
        kelp_diag why = { 0 };
        int rc = kelp_viewer_config(v, vars[which], s, &why);
        if (rc < 0 && why.code == KELP_OK) abort();
        if (v->ncmds > KELP_VIEWER_MAX_CMDS) abort();
        if (v->ncmds == KELP_VIEWER_MAX_CMDS) v->ncmds = 0;
    } else {
        (void)kelp_viewer_mail(v, vars[which], s, size - 1, now);
    }
    (void)kelp_viewer_tick(v, now);
    size_t n = 0;
    uint32_t since = kelp_viewer_seq(v) > 3 ? kelp_viewer_seq(v) - 3 : 0;
    int rc = kelp_viewer_json_changes(v, since, now, 1, out, sizeof out, &n);
    if (rc == 0 && strlen(out) != n) abort();
    rc = kelp_viewer_json_snapshot(v, now, 1, out, sizeof out, &n);
    if (rc == 0 && strlen(out) != n) abort();
    free(s);
    return 0;
}
