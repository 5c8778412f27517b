/* Fuzz: the NODE_MESSAGE parser and uFldMessageHandler's mail, flags and report; uFldScope's
 * SCOPE / LAYOUT configuration, its report mail, keys and render. The first byte picks the
 * case and options; the rest is the text (exact-length copy for the parser, a NUL-terminated
 * copy for the rest). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/field.h>

static void check_publish(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    (void)ctx, (void)dval;
    if (!var || !var[0] || strlen(var) >= KELP_MAX_NAME || (is_string && !sval)) abort();
}

static void check_text(const char *buf, size_t n, size_t cap)
{
    if (n >= cap || strlen(buf) != n) abort();
}

static void msghandler(uint8_t opt, const char *exact, const char *t, size_t n)
{
    kelp_node_message m;
    kelp_diag why = { 0 };
    int rc = kelp_field_nodemsg_parse(exact, n, &m, &why);
    if (rc < 0 && why.code == KELP_OK) abort(); /* every rejection has a reason */
    if (rc == 0) {
        /* every span lies inside the input */
        const kelp_field_text *sp[] = { &m.src_node, &m.dest_node, &m.dest_group, &m.var_name, &m.string_val };
        for (size_t i = 0; i < sizeof sp / sizeof sp[0]; i++)
            if (sp[i]->n && (sp[i]->p < exact || sp[i]->p + sp[i]->n > exact + n)) abort();
        /* at most one value; with neither, 24.8 posts the double 0 */
        if (!m.src_node.n || !m.var_name.n || (m.has_string && m.has_double)) abort();
        if (!m.has_double && !m.has_string && m.double_val != 0.0) abort();
        (void)kelp_field_nodemsg_to(&m, "bravo");
    }
    static kelp_field_umh h;
    kelp_field_umh_cfg c;
    kelp_field_umh_cfg_default(&c, "bravo");
    c.strict = opt & 1;
    c.aux_app = opt & 2;
    c.trunc = (opt & 4) ? 10 : 0;
    if (kelp_field_umh_config(&c, "msg_flag", "GOT=$[CTR]/$[GOOD_CTR]/$[BAD_CTR]$[", &why) != 1) abort();
    if (kelp_field_umh_config(&c, "bad_msg_flag", "BAD=3", &why) != 1) abort();
    (void)kelp_field_umh_config(&c, "msg_flag", t, &why); /* the text as a flag too */
    (void)kelp_field_umh_config(&c, (opt & 8) ? "aux_info" : "appcast_trunc_msg", t, &why);
    kelp_field_umh_init(&h, &c);
    kelp_field_sink sink = { NULL, check_publish, NULL };
    for (int i = 0; i < 7; i++) {
        rc = kelp_field_umh_mail(&h, "NODE_MESSAGE", true, t, i, &sink);
        if (rc != 1 && rc != KELP_ERR_PARSE && rc != KELP_ERR_ARG) abort();
    }
    /* as 24.8 counts: every message is valid (well formed) or invalid; a rejected one is valid */
    if (h.valid + h.invalid != h.total || h.rejected > h.valid || h.nsrc > KELP_UMH_MAX_SOURCES) abort();
    (void)kelp_field_umh_iterate(&h, 10, &sink);
    static char buf[8192];
    check_text(buf, kelp_field_umh_report(&h, 10, buf, sizeof buf), sizeof buf);
    char small[32];
    check_text(small, kelp_field_umh_report(&h, 10, small, sizeof small), sizeof small);
}

static void scope(uint8_t opt, char *t)
{
    kelp_field_ufs_cfg c;
    memset(&c, 0, sizeof c);
    kelp_diag why = { 0 };
    static const char *const base[] = { "var=R,key=vname,fld=a", "var=R,fld=b,alias=B", "var=S,key=name,fld=c" };
    for (int i = 0; i < 3; i++)
        if (kelp_field_ufs_config(&c, "SCOPE", base[i], &why) != 1) abort();
    /* "config-text|report-text|keys" */
    char *bar = strchr(t, '|');
    char *report = bar ? bar + 1 : t, *keys = NULL;
    if (bar) *bar = 0;
    char *bar2 = strchr(report, '|');
    if (bar2) *bar2 = 0, keys = bar2 + 1;
    (void)kelp_field_ufs_config(&c, (opt & 1) ? "LAYOUT" : "SCOPE", t, &why);
    if (kelp_field_ufs_config(&c, "LAYOUT", "a, B, nosuch", &why) != 1) abort();
    if (c.nelem > KELP_UFS_MAX_ELEMS || c.nlayout > KELP_UFS_MAX_LAYOUTS) abort();
    static kelp_field_ufs s;
    kelp_field_ufs_init(&s, &c);
    const char *vars[] = { "R", "S", kelp_field_ufs_subscription(&s, 3) };
    for (int i = 0; i < 3; i++)
        if (vars[i]) (void)kelp_field_ufs_mail(&s, vars[i], true, report);
    if (s.nrow > KELP_UFS_MAX_ROWS) abort();
    for (const char *k = keys; k && *k; k++) {
        (void)kelp_field_ufs_key(&s, (unsigned char)*k);
        if (s.layout > s.cfg.nlayout) abort();
    }
    static char buf[16384];
    check_text(buf, kelp_field_ufs_render(&s, buf, sizeof buf), sizeof buf);
    char small[24];
    check_text(small, kelp_field_ufs_render(&s, small, sizeof small), sizeof small);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    size_t n = size - 1;
    char *exact = malloc(n ? n : 1), *t = malloc(n + 1);
    memcpy(exact, data + 1, n);
    memcpy(t, data + 1, n);
    t[n] = 0;
    if (data[0] & 0x80) scope(data[0], t);
    else msghandler(data[0], exact, t, n);
    free(exact);
    free(t);
    return 0;
}
