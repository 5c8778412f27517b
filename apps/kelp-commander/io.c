/* kelp-commander: files (DCCL XML import, save files) and sending through the bus. */
#include <stdlib.h>
#include <string.h>

#include "cmdr.h"

static void full_path(const cmdr_app *s, const char *path, char *out, size_t cap)
{
    if (path[0] != '/' && s->base_dir[0])
        (void)snprintf(out, cap, "%s/%s", s->base_dir, path);
    else
        (void)snprintf(out, cap, "%s", path);
}

int cmdr_import(cmdr_app *s, const char *path, kelp_diag *d)
{
    char p[1024];
    full_path(s, path, p, sizeof p);
    return kelp_dccl_load_file(&s->ld, p, NULL, d);
}

int cmdr_load_file(cmdr_app *s, const char *path, kelp_diag *d)
{
    char p[1024];
    full_path(s, path, p, sizeof p);
    FILE *f = fopen(p, "r");
    if (!f) return kelp_failf(d, KELP_ERR_IO, "%s: cannot read", p);
    static char text[256 * 1024];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    kelp_diag why;
    kelp_diag_clear(&why);
    int rc = kelp_commander_load(&s->core, text, &why);
    if (rc < 0) {
        (void)kelp_failf(d, rc, "%s:%d: %s", p, why.line, kelp_diag_text(&why));
        (void)kelp_diag_where(d, why.line, 0);
    }
    return rc;
}

int cmdr_save_file(cmdr_app *s, const char *path, kelp_diag *d)
{
    static char text[256 * 1024];
    size_t n;
    char p[1024];
    full_path(s, path, p, sizeof p);
    if (kelp_commander_save(&s->core, text, sizeof text, &n) < 0) return kelp_fail(d, KELP_ERR_NOSPACE, "too much to save");
    FILE *f = fopen(p, "w");
    if (!f || fwrite(text, 1, n, f) != n) {
        if (f) fclose(f);
        return kelp_failf(d, KELP_ERR_IO, "%s: cannot write", p);
    }
    return fclose(f) == 0 ? KELP_OK : kelp_failf(d, KELP_ERR_IO, "%s: cannot write", p);
}

/* publish a message's variables for pAcommsHandler; text gets what was sent (or why not) */
int cmdr_send(cmdr_app *s, unsigned msg, char *text, size_t cap)
{
    kelp_commander_pub pubs[KELP_CMDR_MAX_PUBS];
    size_t n, at = 0;
    kelp_diag why;
    kelp_diag_clear(&why);
    int rc = kelp_commander_send(&s->core, msg, kelp_app_time(s->app), pubs, KELP_CMDR_MAX_PUBS, &n, &why);
    if (rc < 0) {
        (void)snprintf(text, cap, "not sent: %s", kelp_diag_text(&why)[0] ? kelp_diag_text(&why) : kelp_err_str(rc));
        return rc;
    }
    text[0] = 0;
    for (size_t i = 0; i < n; i++) {
        if (kelp_app_notify_string(s->app, pubs[i].var, pubs[i].val) < 0) {
            (void)snprintf(text, cap, "cannot publish %s", pubs[i].var);
            return KELP_ERR_IO;
        }
        int k = snprintf(text + at, cap - at, "%s: %s\n", pubs[i].var, pubs[i].val);
        if (k > 0 && (size_t)k < cap - at) at += (size_t)k;
    }
    return KELP_OK;
}
