/* kelp edge: postings from an LCM log or a MOOS .alog (kelp/edge/alog.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/alog.h>
#include <kelp/bus.h>
#include <kelp/edge/alog.h>
#include <kelp/edge/lcmlog.h>
#include <kelp/util.h>

#define POSTLOG_LINE_MAX (KELP_MAX_SVAL + 512)

struct kelp_alog_postlog {
    bool alog, marking;
    double start;
    kelp_lcmlog_reader *lcm;
    FILE *f;
    kelp_var v;
    char line[POSTLOG_LINE_MAX + 2];
    char var[KELP_MAX_NAME], src[KELP_MAX_NAME], comm[KELP_MAX_NAME], def_comm[KELP_MAX_NAME];
    char sval[KELP_MAX_SVAL + 1];
    kelp_alog_postlog_stats st;
};

kelp_alog_postlog *kelp_alog_postlog_open(const char *path, const char *default_community, kelp_diag *d)
{
    kelp_alog_postlog *p = calloc(1, sizeof *p);
    if (!p) {
        (void)kelp_fail(d, KELP_ERR_IO, "out of memory");
        return NULL;
    }
    p->start = NAN;
    snprintf(p->def_comm, sizeof p->def_comm, "%s", default_community ? default_community : "");
    FILE *f = fopen(path, "rb");
    if (!f) {
        (void)kelp_failf(d, KELP_ERR_IO, "cannot open %s: %s", path, strerror(errno));
        free(p);
        return NULL;
    }
    uint8_t b[4] = { 0 };
    size_t n = fread(b, 1, 4, f);
    uint32_t sync = ((uint32_t)b[0] << 24) | ((uint32_t)b[1] << 16) | ((uint32_t)b[2] << 8) | b[3];
    if (n == 4 && sync == KELP_LCMLOG_SYNC) {
        fclose(f);
        p->lcm = kelp_lcmlog_open(path, 0, d);
        if (!p->lcm) {
            free(p);
            return NULL;
        }
        return p;
    }
    rewind(f);
    p->f = f;
    p->alog = true;
    return p;
}

bool kelp_alog_postlog_is_alog(const kelp_alog_postlog *p) { return p->alog; }
double kelp_alog_postlog_start(const kelp_alog_postlog *p) { return p->start; }
kelp_alog_postlog_stats kelp_alog_postlog_get_stats(const kelp_alog_postlog *p) { return p->st; }

static int next_lcm(kelp_alog_postlog *p, kelp_post *out)
{
    kelp_lcmlog_event ev;
    const char *channel;
    int rc;
    while ((rc = kelp_lcmlog_next(p->lcm, &ev, &channel)) > 0) {
        /* a write goes out on the channel of its own name; sync replies and requests do not */
        if (kelp_var_decode(ev.data, ev.data_len, &p->v) < 0 || strcmp(channel, p->v.name) != 0 ||
            p->v.kind == KELP_VAR_BINARY) {
            p->st.skipped++;
            continue;
        }
        if (isnan(p->start)) p->start = p->v.time;
        *out = (kelp_post){ .time = p->v.time, .log_us = ev.timestamp, .var = p->v.name, .src = p->v.source,
                            .community = p->v.community, .is_string = p->v.kind == KELP_VAR_STRING,
                            .sval = p->v.kind == KELP_VAR_STRING ? p->v.sval : "", .dval = p->v.dval };
        p->st.posts++;
        return 1;
    }
    p->st.damaged = kelp_lcmlog_get_stats(p->lcm).damaged;
    return rc;
}

/* copy s[0..n) into dst[cap], false when it does not fit */
static bool copy(char *dst, size_t cap, const char *s, size_t n)
{
    if (n + 1 > cap) return false;
    memcpy(dst, s, n);
    dst[n] = 0;
    return true;
}

static int next_alog(kelp_alog_postlog *p, kelp_post *out)
{
    while (fgets(p->line, sizeof p->line, p->f)) {
        size_t len = strlen(p->line);
        if (len && p->line[len - 1] != '\n' && !feof(p->f)) { /* longer than any value: skip the rest */
            int c;
            while ((c = fgetc(p->f)) != EOF && c != '\n') {
            }
            p->st.skipped++;
            continue;
        }
        while (len && (p->line[len - 1] == '\n' || p->line[len - 1] == '\r')) len--;
        if (p->line[0] == '%') {
            double t;
            const char *c = strstr(p->line, "COMMUNITY");
            if (kelp_alog_parse_logstart(p->line, len, &t) == 1) p->start = t;
            else if (kelp_alog_is_marking(p->line, len)) p->marking = true;
            else if (c && (size_t)(c - p->line) < 8) {
                c += 9;
                while (*c == ' ' || *c == '\t') c++;
                size_t cl = strcspn(c, " \t\r\n");
                if (!copy(p->def_comm, sizeof p->def_comm, c, cl)) p->def_comm[0] = 0;
            }
            continue;
        }
        kelp_alog_line l;
        int rc = kelp_alog_parse_line(p->line, len, &l);
        if (rc == 0) continue;
        const char *s = NULL;
        size_t sl = 0;
        double d = 0;
        int kind = rc < 0 ? rc : kelp_alog_value(l.val, l.val_len, p->marking, &d, &s, &sl);
        const char *at = rc < 0 ? NULL : memchr(l.src, '@', l.src_len);
        size_t srcl = at ? (size_t)(at - l.src) : l.src_len;
        if (kind < 0 || !copy(p->var, sizeof p->var, l.var, l.var_len) || !copy(p->src, sizeof p->src, l.src, srcl) ||
            (kind == 0 && !copy(p->sval, sizeof p->sval, s, sl)) ||
            !(at ? copy(p->comm, sizeof p->comm, at + 1, l.src_len - srcl - 1)
                 : copy(p->comm, sizeof p->comm, p->def_comm, strlen(p->def_comm)))) {
            p->st.skipped++;
            continue;
        }
        double t0 = isnan(p->start) ? 0 : p->start;
        *out = (kelp_post){ .time = t0 + l.time, .log_us = (int64_t)llround((t0 + l.time) * 1e6), .var = p->var,
                            .src = p->src, .community = p->comm, .is_string = kind == 0,
                            .sval = kind == 0 ? p->sval : "", .dval = d };
        p->st.posts++;
        return 1;
    }
    return ferror(p->f) ? KELP_ERR_IO : 0;
}

int kelp_alog_postlog_next(kelp_alog_postlog *p, kelp_post *out) { return p->alog ? next_alog(p, out) : next_lcm(p, out); }

void kelp_alog_postlog_close(kelp_alog_postlog *p)
{
    if (!p) return;
    if (p->lcm) kelp_lcmlog_close(p->lcm);
    if (p->f) fclose(p->f);
    free(p);
}
