/* kelp mission files: loading from disk (edge). */
#include <errno.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/edge/mission.h>

int kelp_mission_load_text(kelp_mission_file *f, const char *name, const char *text, size_t len)
{
    memset(f, 0, sizeof *f);
    snprintf(f->path, sizeof f->path, "%s", name);
    f->text = malloc(len + 1);
    if (!f->text) {
        snprintf(f->error, sizeof f->error, "%s: out of memory", name);
        return KELP_ERR_NOSPACE;
    }
    memcpy(f->text, text, len);
    f->text[len] = 0;
    int rc = kelp_mission_parse(&f->m, f->text, len, NULL, 0);
    if (rc == 0) {
        size_t n = f->m.nnodes ? f->m.nnodes : 1;
        kelp_mission_node *nodes = calloc(n, sizeof *nodes);
        if (!nodes) {
            snprintf(f->error, sizeof f->error, "%s: out of memory", name);
            kelp_mission_free(f);
            return KELP_ERR_NOSPACE;
        }
        rc = kelp_mission_parse(&f->m, f->text, len, nodes, n);
        if (rc < 0) free(nodes);
    }
    if (rc < 0) {
        if (rc == KELP_ERR_PARSE)
            snprintf(f->error, sizeof f->error, "%s:%d: %s", name, f->m.diag.line, kelp_diag_text(&f->m.diag));
        else
            snprintf(f->error, sizeof f->error, "%s: %s", name, kelp_err_str(rc));
        free(f->text);
        f->text = NULL;
        f->m.nodes = NULL;
        return rc;
    }
    return KELP_OK;
}

int kelp_mission_load(kelp_mission_file *f, const char *path)
{
    memset(f, 0, sizeof *f);
    /* a FIFO or a device would block or never end: only regular files (checked before open) */
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        snprintf(f->error, sizeof f->error, "%s: not a regular file", path);
        return KELP_ERR_IO;
    }
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        snprintf(f->error, sizeof f->error, "%s: cannot open: %s", path, strerror(errno));
        return KELP_ERR_IO;
    }
    size_t cap = 65536, len = 0;
    char *buf = malloc(cap);
    while (buf) {
        size_t n = fread(buf + len, 1, cap - len, fp);
        len += n;
        if (len < cap) break;
        if (cap >= (64u << 20)) { free(buf); buf = NULL; break; }
        char *nb = realloc(buf, cap * 2);
        if (!nb) { free(buf); buf = NULL; break; }
        buf = nb;
        cap *= 2;
    }
    int ioerr = ferror(fp);
    fclose(fp);
    if (!buf || ioerr) {
        free(buf);
        snprintf(f->error, sizeof f->error, "%s: cannot read (or larger than 64 MiB)", path);
        return KELP_ERR_IO;
    }
    int rc = kelp_mission_load_text(f, path, buf, len);
    free(buf);
    return rc;
}

void kelp_mission_free(kelp_mission_file *f)
{
    if (!f) return;
    free(f->m.nodes);
    free(f->text);
    f->m.nodes = NULL;
    f->text = NULL;
}
