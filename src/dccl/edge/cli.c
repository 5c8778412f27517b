/* kelp DCCL: the kelp-dccl command (encode, decode, publish, info). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "programs.h"
#include <kelp/edge/cli.h>
#include <kelp/edge/dccl.h>

#define CLI_MAX_XML 64
#define CLI_MAX_ALGS 64
#define CLI_MAX_MODEMS 256

typedef struct cli {
    const char *cmd;
    const char *xml[CLI_MAX_XML];
    size_t n_xml;
    const char *msg;
    const char *passphrase;
    const char *lookup;
    unsigned modem_id;
    double now;
    bool have_now, plain, have_lat, have_lon, no_algs;
    double lat, lon;
    unsigned long repeat;
    char **pos;
    int n_pos;
} cli;

enum { O_XML = 256, O_MSG, O_PASS, O_LOOKUP, O_MODEM_ID, O_NOW, O_REPEAT, O_LAT, O_LON, O_PLAIN, O_NO_ALGS };

static const kelp_cli_opt cli_opts[] = {
    { "xml", required_argument, O_XML, "FILE", "a DCCL message file (repeatable)" },
    { "msg", required_argument, O_MSG, "NAME", "the message to encode" },
    { "modem-id", required_argument, O_MODEM_ID, "N", "this modem's id (source of encoded messages)" },
    { "now", required_argument, O_NOW, "UNIXTIME", "the time used for time fields (default: now)" },
    { "passphrase", required_argument, O_PASS, "PW", "encrypt/decrypt with this passphrase" },
    { "plain", no_argument, O_PLAIN, NULL, "no encryption" },
    { "repeat", required_argument, O_REPEAT, "N", "do it N times (timing)" },
    { "lat-origin", required_argument, O_LAT, "DEG", "datum for the lat/lon algorithms" },
    { "lon-origin", required_argument, O_LON, "DEG", "datum for the lat/lon algorithms" },
    { "modem-lookup", required_argument, O_LOOKUP, "FILE", "\"id,name,type\" lines for the modem algorithms" },
    { "no-algorithms", no_argument, O_NO_ALGS, NULL,
      "register none (algorithm names are then ignored, as in a bare Goby DCCLCodec)" },
    { NULL, 0, 0, NULL, NULL },
};

static const kelp_cli cli_def = {
    .name = "kelp-dccl",
    .purpose = "Encode, decode, publish and inspect Goby 1.1 DCCL messages.",
    .synopsis = "encode  --xml FILE... --msg NAME [OPTIONS] FIELD=VALUE|FIELD#=NUMBER...\n"
                "decode  --xml FILE... [OPTIONS] HEX\n"
                "publish --xml FILE... [OPTIONS] HEX\n"
                "info    --xml FILE...",
    .opts = cli_opts,
};

static int die(const char *fmt, const char *a, const char *b) KELP_PRINTF(1, 0);

/* fmt holds at most two %s */
static int die(const char *fmt, const char *a, const char *b)
{
    char msg[1024];
    size_t i = 0, o = 0;
    const char *args[2] = {a ? a : "", b ? b : ""};
    unsigned k = 0;
    while (fmt[i] && o < sizeof msg - 1) {
        if (fmt[i] == '%' && fmt[i + 1] == 's' && k < 2) {
            const char *s = args[k++];
            while (*s && o < sizeof msg - 1) msg[o++] = *s++;
            i += 2;
        } else {
            msg[o++] = fmt[i++];
        }
    }
    msg[o] = '\0';
    fprintf(stderr, "kelp-dccl: %s\n", msg);
    return 2;
}

static bool parse_num(const char *s, double *out)
{
    char *end;
    if (!s || !*s) return false;
    errno = 0;
    *out = strtod(s, &end);
    return *end == '\0' && errno != ERANGE;
}

/* 0, or KELP_CLI_EXIT with *status set (help, version, usage error) */
static int parse_args(cli *c, int argc, char **argv, int *status)
{
    int o;
    double d;
    memset(c, 0, sizeof *c);
    c->repeat = 1;
    *status = 2;
    while ((o = kelp_cli_next(&cli_def, argc, argv, status)) != -1) {
        const char *val = optarg;
        switch (o) {
        case KELP_CLI_EXIT: return KELP_CLI_EXIT;
        case O_PLAIN: c->plain = true; break;
        case O_NO_ALGS: c->no_algs = true; break;
        case O_XML:
            if (c->n_xml >= CLI_MAX_XML) return die("too many --xml files", NULL, NULL), KELP_CLI_EXIT;
            c->xml[c->n_xml++] = val;
            break;
        case O_MSG: c->msg = val; break;
        case O_PASS: c->passphrase = val; break;
        case O_LOOKUP: c->lookup = val; break;
        case O_MODEM_ID:
            if (!parse_num(val, &d) || d < 0 || d > 4294967295.0 || d != (double)(unsigned long)d)
                return die("bad --modem-id \"%s\"", val, NULL), KELP_CLI_EXIT;
            c->modem_id = (unsigned)d;
            break;
        case O_NOW:
            if (!parse_num(val, &c->now)) return die("bad --now \"%s\"", val, NULL), KELP_CLI_EXIT;
            c->have_now = true;
            break;
        case O_REPEAT:
            if (!parse_num(val, &d) || d < 1 || d > 1e9) return die("bad --repeat \"%s\"", val, NULL), KELP_CLI_EXIT;
            c->repeat = (unsigned long)d;
            break;
        case O_LAT:
            if (!parse_num(val, &c->lat)) return die("bad --lat-origin \"%s\"", val, NULL), KELP_CLI_EXIT;
            c->have_lat = true;
            break;
        case O_LON:
            if (!parse_num(val, &c->lon)) return die("bad --lon-origin \"%s\"", val, NULL), KELP_CLI_EXIT;
            c->have_lon = true;
            break;
        }
    }
    if (optind >= argc) {
        kelp_cli_usage(&cli_def, stderr);
        *status = kelp_cli_error(&cli_def, "no command (encode, decode, publish, info)");
        return KELP_CLI_EXIT;
    }
    c->cmd = argv[optind++];
    c->pos = argv + optind;
    c->n_pos = argc - optind;
    *status = 0;
    return 0;
}

static int hex_to_bytes(const char *hex, uint8_t *out, size_t cap, size_t *n)
{
    size_t len = strlen(hex), i;
    if (len == 0 || len % 2) return KELP_ERR_TRUNCATED;
    if (len / 2 > cap) return KELP_ERR_RANGE;
    for (i = 0; i < len / 2; i++) {
        int hi, lo;
        char a = hex[2 * i], b = hex[2 * i + 1];
        hi = (a >= '0' && a <= '9') ? a - '0' : (a >= 'a' && a <= 'f') ? a - 'a' + 10 : (a >= 'A' && a <= 'F') ? a - 'A' + 10 : -1;
        lo = (b >= '0' && b <= '9') ? b - '0' : (b >= 'a' && b <= 'f') ? b - 'a' + 10 : (b >= 'A' && b <= 'F') ? b - 'A' + 10 : -1;
        if (hi < 0 || lo < 0) return KELP_ERR_PARSE;
        out[i] = (uint8_t)(hi << 4 | lo);
    }
    *n = len / 2;
    return KELP_OK;
}

static void bytes_to_hex(const uint8_t *b, size_t n, char *out)
{
    static const char H[] = "0123456789abcdef";
    size_t i;
    for (i = 0; i < n; i++) {
        out[2 * i] = H[b[i] >> 4];
        out[2 * i + 1] = H[b[i] & 15];
    }
    out[2 * n] = '\0';
}

static const char *type_name(kelp_dccl_type t)
{
    switch (t) {
    case KELP_DCCL_T_STATIC: return "static";
    case KELP_DCCL_T_INT: return "int";
    case KELP_DCCL_T_FLOAT: return "float";
    case KELP_DCCL_T_BOOL: return "bool";
    case KELP_DCCL_T_STRING: return "string";
    case KELP_DCCL_T_ENUM: return "enum";
    case KELP_DCCL_T_HEX: return "hex";
    default: return "header";
    }
}

static int cmd_info(const kelp_dccl_set *set)
{
    size_t i;
    unsigned f;
    for (i = 0; i < set->n; i++) {
        const kelp_dccl_msgdef *d = set->msgs[i];
        printf("message %s id %u size %u body_bits %u bytes %u repeat %u\n", d->name, (unsigned)d->id,
               (unsigned)d->size, (unsigned)d->body_bits, (unsigned)kelp_dccl_max_len(d), (unsigned)d->repeat);
        for (f = 0; f < d->n_fields; f++) {
            const kelp_dccl_field *x = &d->fields[f];
            printf("  field %s %s %u", x->name, type_name(x->type), (unsigned)x->total_bits);
            if (x->array_length > 1) {
                printf(" array %u element %u", (unsigned)x->array_length, (unsigned)x->bits);
                if (x->has_delta) printf(" delta %u", (unsigned)x->delta_bits);
            }
            putchar('\n');
        }
    }
    return 0;
}

int kelp_dccl_cli_main(int argc, char **argv)
{
    cli c;
    kelp_dccl_loaded ld;
    kelp_dccl_alg_entry alg_store[CLI_MAX_ALGS];
    kelp_dccl_modem_entry modem_store[CLI_MAX_MODEMS];
    kelp_dccl_algs algs;
    kelp_dccl_builtin bi;
    kelp_dccl_mbedtls mb;
    kelp_dccl_codec cx;
    kelp_diag err;
    size_t i;
    int rc, status = 0;
    bool is_encode, is_decode, is_publish, is_info;
    if (parse_args(&c, argc, argv, &status) != 0) return status;
    is_encode = strcmp(c.cmd, "encode") == 0;
    is_decode = strcmp(c.cmd, "decode") == 0;
    is_publish = strcmp(c.cmd, "publish") == 0;
    is_info = strcmp(c.cmd, "info") == 0;
    if (!is_encode && !is_decode && !is_publish && !is_info) {
                return die("unknown command \"%s\" (encode, decode, publish, info)", c.cmd, NULL);
    }
    if (c.n_xml == 0) {
                return die("no --xml file given", NULL, NULL);
    }
    kelp_dccl_algs_init(&algs, alg_store, CLI_MAX_ALGS);
    kelp_dccl_builtin_init(&bi, modem_store, CLI_MAX_MODEMS);
    if (kelp_dccl_algs_add_builtin(&algs, &bi) != 0) {
                return die("cannot register algorithms", NULL, NULL);
    }
    if (c.have_lat != c.have_lon) {
                return die("--lat-origin and --lon-origin go together", NULL, NULL);
    }
    if (c.have_lat) kelp_dccl_builtin_set_origin(&bi, c.lat, c.lon);
    kelp_diag_clear(&err);
    if (c.lookup && kelp_dccl_builtin_load_modems(&bi, c.lookup, &err) != 0) {
                return die("%s", kelp_diag_text(&err), NULL);
    }
    kelp_dccl_loaded_init(&ld);
    for (i = 0; i < c.n_xml; i++) {
        if (kelp_dccl_load_file(&ld, c.xml[i], c.no_algs ? NULL : &algs, &err) != 0) {
            kelp_dccl_loaded_free(&ld);
                        return die("%s", kelp_diag_text(&err), NULL);
        }
    }
    if (is_info) {
        status = cmd_info(&ld.set);
        kelp_dccl_loaded_free(&ld);
                return status;
    }
    if (!c.have_now) c.now = (double)time(NULL);
    if (kelp_dccl_mbedtls_init(&mb, c.passphrase) != 0) {
        kelp_dccl_loaded_free(&ld);
                return die("crypto initialisation failed", NULL, NULL);
    }
    kelp_dccl_codec_init(&cx, c.modem_id, c.plain ? NULL : &mb.ops, c.no_algs ? NULL : &algs);

    if (is_encode) {
        const kelp_dccl_msgdef *def;
        kelp_dccl_val *vals;
        uint16_t *count;
        uint8_t out[KELP_DCCL_MAX_SIZE];
        char hex[2 * KELP_DCCL_MAX_SIZE + 1];
        size_t len = 0;
        unsigned long r;
        int k;
        if (!c.msg) { status = die("encode needs --msg NAME", NULL, NULL); goto done; }
        def = kelp_dccl_set_find_name(&ld.set, c.msg);
        if (!def) { status = die("unknown message \"%s\"", c.msg, NULL); goto done; }
        vals = calloc(def->n_slots, sizeof *vals);
        count = calloc(def->n_fields, sizeof *count);
        if (!vals || !count) {
            free(vals);
            free(count);
            status = die("out of memory", NULL, NULL);
            goto done;
        }
        for (i = 0; i < def->n_slots; i++) kelp_dccl_val_clear(&vals[i]);
        for (k = 0; k < c.n_pos; k++) {
            const char *a = c.pos[k], *eq = strchr(a, '=');
            char name[256];
            size_t nl;
            bool is_dbl = false;
            int fi;
            if (!eq || eq == a) {
                free(vals);
                free(count);
                status = die("expected FIELD=VALUE or FIELD#=NUMBER, got \"%s\"", a, NULL);
                goto done;
            }
            nl = (size_t)(eq - a);
            if (a[nl - 1] == '#') {
                is_dbl = true;
                nl--;
            }
            if (nl >= sizeof name) nl = sizeof name - 1;
            memcpy(name, a, nl);
            name[nl] = '\0';
            fi = kelp_dccl_field_find(def, name);
            if (fi < 0) {
                free(vals);
                free(count);
                status = die("message %s has no field \"%s\"", def->name, name);
                goto done;
            }
            if (count[fi] < def->fields[fi].array_length) {
                kelp_dccl_val *v = &vals[def->fields[fi].slot + count[fi]];
                if (is_dbl) {
                    double d;
                    if (!parse_num(eq + 1, &d)) {
                        free(vals);
                        free(count);
                        status = die("FIELD#=NUMBER: \"%s\" is not a number", eq + 1, NULL);
                        goto done;
                    }
                    kelp_dccl_val_set_double(v, d, KELP_DCCL_MAX_DBL_PRECISION);
                } else {
                    kelp_dccl_val_set_str(v, eq + 1);
                    if (v->cut) {
                        free(vals);
                        free(count);
                        status = die("value of %s longer than KELP_DCCL_MAX_STRLEN", name, NULL);
                        goto done;
                    }
                }
            }
            /* extra elements are dropped, as Goby resizes the vector */
            count[fi]++;
        }
        rc = 0;
        for (r = 0; r < c.repeat && rc == 0; r++) {
            rc = kelp_dccl_encode(&cx, def, vals, def->n_slots, c.now, out, sizeof out, &len);
            if (rc == 0) bytes_to_hex(out, len, hex);
        }
        free(vals);
        free(count);
        if (rc) {
            fprintf(stderr, "kelp-dccl: encode %s failed: %s (%s)\n", def->name, cx.diag.code ? kelp_diag_text(&cx.diag) : "",
                    kelp_err_str(rc));
            status = 1;
            goto done;
        }
        printf("%s\n", hex);
    } else {
        const kelp_dccl_msgdef *def;
        kelp_dccl_val *vals;
        uint8_t bytes[KELP_DCCL_MAX_SIZE];
        size_t n = 0;
        unsigned id = 0;
        unsigned long r;
        if (c.n_pos != 1) { status = die("%s needs exactly one HEX argument", c.cmd, NULL); goto done; }
        rc = hex_to_bytes(c.pos[0], bytes, sizeof bytes, &n);
        if (rc == KELP_ERR_TRUNCATED) { status = die("wrong hex length (need a non-empty even number of digits): \"%s\"", c.pos[0], NULL); goto done; }
        if (rc == KELP_ERR_RANGE) { status = die("message longer than KELP_DCCL_MAX_SIZE bytes", NULL, NULL); goto done; }
        if (rc) { status = die("not a hex string: \"%s\"", c.pos[0], NULL); goto done; }
        if (kelp_dccl_peek_id(bytes, n, &id) != 0) { status = die("empty message", NULL, NULL); goto done; }
        def = kelp_dccl_set_find_id(&ld.set, id);
        if (!def) {
            char ids[16];
            snprintf(ids, sizeof ids, "%u", id);
            status = die("unknown message: no message with id %s loaded", ids, NULL);
            goto done;
        }
        vals = calloc(def->n_slots, sizeof *vals);
        if (!vals) { status = die("out of memory", NULL, NULL); goto done; }
        rc = 0;
        for (r = 0; r < c.repeat && rc == 0; r++) {
            if (r) (void)hex_to_bytes(c.pos[0], bytes, sizeof bytes, &n);
            rc = kelp_dccl_decode(&cx, def, bytes, n, c.now, vals, def->n_slots);
        }
        if (rc) {
            fprintf(stderr, "kelp-dccl: decode %s failed: %s (%s)\n", def->name, cx.diag.code ? kelp_diag_text(&cx.diag) : "",
                    kelp_err_str(rc));
            free(vals);
            status = 1;
            goto done;
        }
        if (is_decode) {
            unsigned f, k;
            char buf[KELP_DCCL_MAX_STRLEN + 512];
            printf("message %s\n", def->name);
            for (f = 0; f < def->n_fields; f++) {
                const kelp_dccl_field *x = &def->fields[f];
                for (k = 0; k < x->array_length; k++) {
                    (void)kelp_dccl_val_to_str(&vals[x->slot + k], buf, sizeof buf, NULL);
                    printf("%s=%s\n", x->name, buf);
                }
            }
        } else {
            size_t cap = kelp_dccl_n_publications(def);
            kelp_dccl_pub *pubs = calloc(cap ? cap : 1, sizeof *pubs);
            size_t np = 0, j;
            if (!pubs) {
                free(vals);
                status = die("out of memory", NULL, NULL);
                goto done;
            }
            rc = kelp_dccl_publish_all(&cx, def, vals, def->n_slots, pubs, cap, &np);
            if (rc) {
                fprintf(stderr, "kelp-dccl: publish %s failed: %s (%s)\n", def->name, cx.diag.code ? kelp_diag_text(&cx.diag) : "",
                        kelp_err_str(rc));
                status = 1;
            } else {
                for (j = 0; j < np; j++) {
                    if (pubs[j].is_double) printf("%s=%.15g\n", pubs[j].var, pubs[j].d);
                    else printf("%s=%s\n", pubs[j].var, pubs[j].s);
                }
            }
            free(pubs);
        }
        free(vals);
    }
done:
    kelp_dccl_mbedtls_free(&mb);
    kelp_dccl_loaded_free(&ld);
        return status;
}
