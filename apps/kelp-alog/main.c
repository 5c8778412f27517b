/* kelp-alog: convert between an LCM log of a kelp run and MOOS-IvP's .alog text, so MOOS
 * users' alog tools (aloggrep, alogview, their own scripts) read kelp runs, and .alog files
 * replay on kelp's bus (lcm-logplayer, kelp-plot).
 *
 *   kelp-alog to-alog [--precision=N | --exact] [--mark-types] RUN.lcmlog OUT.alog   (OUT "-": stdout)
 *   kelp-alog to-lcm  [--community=NAME] IN.alog OUT.lcmlog
 *
 * to-alog writes pLogger's layout (kelp/alog.h): the banner with LOGSTART = the first
 * posting's time, then a line per bus write with its time since LOGSTART. A posting from a
 * community other than the log's first is written "source@community" (pLogger's
 * MarkExternalCommunityMessages), and the banner names the first ("%% COMMUNITY name").
 * Sync traffic and binary values are skipped and counted. to-lcm writes each posting as a
 * kelp.var_t event on the channel of its variable, stamped with its MOOS time in microseconds;
 * a value that reads as a number becomes a double unless the .alog marks types. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/alog.h>
#include <kelp/bus.h>
#include <kelp/edge/alog.h>
#include <kelp/edge/cli.h>
#include <kelp/lcmlog.h>
#include <kelp/util.h>

typedef struct opts {
    int dp;
    bool mark;
    const char *community;
} opts;

static int to_alog(const char *in, const char *outp, const opts *o)
{
    kelp_diag err = {0};
    kelp_alog_postlog *p = kelp_alog_postlog_open(in, NULL, &err);
    if (!p) return fprintf(stderr, "kelp-alog: %s\n", kelp_diag_text(&err)), 1;
    if (kelp_alog_postlog_is_alog(p)) {
        kelp_alog_postlog_close(p);
        return fprintf(stderr, "kelp-alog: %s is already an .alog\n", in), 1;
    }
    bool std_out = strcmp(outp, "-") == 0;
    FILE *f = std_out ? stdout : fopen(outp, "w");
    if (!f) {
        kelp_alog_postlog_close(p);
        return fprintf(stderr, "kelp-alog: cannot write %s\n", outp), 1;
    }
    static char line[KELP_MAX_SVAL + 512];
    char comm[KELP_MAX_NAME] = "", src[2 * KELP_MAX_NAME + 2];
    kelp_post e;
    long n = 0, bad = 0;
    int rc;
    while ((rc = kelp_alog_postlog_next(p, &e)) > 0) {
        if (n == 0 && bad == 0) {
            time_t now = time(NULL);
            snprintf(comm, sizeof comm, "%s", e.community);
            fprintf(f, "%s\n%%%% LOG FILE:       %s\n%%%% FILE OPENED ON  %s%%%% LOGSTART        %20.16g\n",
                    KELP_ALOG_BANNER, outp, ctime(&now), kelp_alog_postlog_start(p));
            if (o->mark) fprintf(f, "%%%% DATATYPE MARKING ON\n");
            if (comm[0]) fprintf(f, "%%%% COMMUNITY       %s\n", comm);
            fprintf(f, "%s\n", KELP_ALOG_BANNER);
        }
        if (strcmp(e.community, comm) != 0 && e.community[0]) snprintf(src, sizeof src, "%s@%s", e.src, e.community);
        else snprintf(src, sizeof src, "%s", e.src);
        int k = kelp_alog_format_line(line, sizeof line, e.time - kelp_alog_postlog_start(p), e.var, src[0] ? src : "unknown",
                                      e.is_string, e.sval, e.dval, o->dp, o->mark);
        if (k < 0) {
            bad++; /* a value with a line break, a name with white space */
            continue;
        }
        fwrite(line, 1, (size_t)k, f);
        n++;
    }
    kelp_alog_postlog_stats st = kelp_alog_postlog_get_stats(p);
    kelp_alog_postlog_close(p);
    if ((std_out ? fflush(f) : fclose(f)) != 0 || rc < 0) return fprintf(stderr, "kelp-alog: read or write error\n"), 1;
    fprintf(std_out ? stderr : stdout, "kelp-alog: %ld postings written to %s; skipped %zu (sync, binary, other types) and %ld (not "
           "representable on a line)%s\n", n, outp, st.skipped, bad, st.damaged ? "; the log has damaged stretches" : "");
    return n ? 0 : 1;
}

static int to_lcm(const char *in, const char *outp, const opts *o)
{
    kelp_diag err = {0};
    kelp_alog_postlog *p = kelp_alog_postlog_open(in, o->community, &err);
    if (!p) return fprintf(stderr, "kelp-alog: %s\n", kelp_diag_text(&err)), 1;
    if (!kelp_alog_postlog_is_alog(p)) {
        kelp_alog_postlog_close(p);
        return fprintf(stderr, "kelp-alog: %s is an LCM log already\n", in), 1;
    }
    FILE *f = fopen(outp, "wb");
    if (!f) {
        kelp_alog_postlog_close(p);
        return fprintf(stderr, "kelp-alog: cannot write %s\n", outp), 1;
    }
    static kelp_var v;
    static uint8_t buf[KELP_MAX_SVAL + 1024];
    kelp_post e;
    long n = 0, bad = 0;
    int rc;
    bool werr = false;
    while ((rc = kelp_alog_postlog_next(p, &e)) > 0) {
        memset(&v, 0, sizeof v);
        v.time = e.time;
        snprintf(v.name, sizeof v.name, "%s", e.var);
        snprintf(v.source, sizeof v.source, "%s", e.src);
        snprintf(v.community, sizeof v.community, "%s", e.community);
        v.kind = e.is_string ? KELP_VAR_STRING : KELP_VAR_DOUBLE;
        v.dval = e.dval;
        if (e.is_string) {
            v.slen = strlen(e.sval);
            memcpy(v.sval, e.sval, v.slen + 1);
        }
        size_t len = 0;
        if (kelp_var_encode(&v, buf, sizeof buf, &len) < 0) {
            bad++;
            continue;
        }
        uint8_t hdr[KELP_LCMLOG_HDR_LEN];
        size_t cl = strlen(v.name);
        kelp_lcmlog_header((uint64_t)n, e.log_us, cl, len, hdr);
        werr = werr || fwrite(hdr, 1, sizeof hdr, f) != sizeof hdr || fwrite(v.name, 1, cl, f) != cl ||
               fwrite(buf, 1, len, f) != len;
        n++;
    }
    kelp_alog_postlog_stats st = kelp_alog_postlog_get_stats(p);
    kelp_alog_postlog_close(p);
    if (fclose(f) != 0 || werr || rc < 0) return fprintf(stderr, "kelp-alog: read or write error\n"), 1;
    printf("kelp-alog: %ld postings written to %s; skipped %zu bad line(s), %ld not encodable\n", n, outp, st.skipped, bad);
    return n ? 0 : 1;
}

int main(int argc, char **argv)
{
    const kelp_cli cli = {
        .name = "kelp-alog",
        .purpose = "Convert an LCM log of a kelp run to MOOS-IvP's .alog text, and an .alog to an LCM log.",
        .synopsis = "to-alog [--precision=N | --exact] [--mark-types] RUN.lcmlog OUT.alog|-\n"
                    "to-lcm [--community=NAME] IN.alog OUT.lcmlog",
        .opts = (const kelp_cli_opt[]){
            { "precision", required_argument, 'p', "N", "decimals of double values, 0..9 (default 5, as pLogger)" },
            { "exact", no_argument, 'x', NULL, "doubles and times with 17 significant digits (they read back exactly)" },
            { "mark-types", no_argument, 'm', NULL, "\"D:\"/\"S:\" before each value (pLogger's MarkDataType)" },
            { "community", required_argument, 'c', "NAME", "to-lcm: community of postings without @community" },
            { NULL, 0, 0, NULL, NULL } },
    };
    opts o = { KELP_ALOG_DEFAULT_DP, false, "" };
    int c, status;
    long dp;
    while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        switch (c) {
        case KELP_CLI_EXIT: return status;
        case 'p':
            if (kelp_util_parse_long(optarg, strlen(optarg), &dp) < 0 || dp < 0 || dp > 9)
                return kelp_cli_error(&cli, "--precision takes 0..9");
            o.dp = (int)dp;
            break;
        case 'x': o.dp = -1; break;
        case 'm': o.mark = true; break;
        case 'c': o.community = optarg; break;
        default: break;
        }
    }
    if (argc - optind != 3) return kelp_cli_error(&cli, "expected a command (to-alog or to-lcm), an input and an output");
    const char *cmd = argv[optind], *in = argv[optind + 1], *out = argv[optind + 2];
    if (strcmp(cmd, "to-alog") == 0) return to_alog(in, out, &o);
    if (strcmp(cmd, "to-lcm") == 0) return to_lcm(in, out, &o);
    return kelp_cli_error(&cli, "unknown command '%s' (to-alog or to-lcm)", cmd);
}
