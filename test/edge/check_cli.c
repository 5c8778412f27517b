/* The command-line convention (src/app/cli.c): options, --help/--version, usage errors. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <kelp/edge/app.h>

enum { OPT_RAW = 300 };

static const kelp_cli_opt opts[] = {
    { "count", required_argument, 'c', "N", "stop after N" },
    { "raw", no_argument, OPT_RAW, NULL, "raw bytes" },
    { "verbose", no_argument, 'v', NULL, "takes -v: version has no short form" },
    { NULL, 0, 0, NULL, NULL },
};
static const kelp_cli cli = { "kelp-test", "A test program.", "[OPTIONS] FILE", opts, "More text.\n", false };

typedef struct result {
    int opts[8], nopts;
    char optargs[8][32];
    int status;        /* -1: ran to the end (no KELP_CLI_EXIT) */
    int first_pos;     /* optind at the end */
    char out[4096], err[1024];
} result;

static void slurp(FILE *f, char *buf, size_t cap)
{
    rewind(f);
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = 0;
    fclose(f);
}

/* parse argv (NULL-terminated) with stdout and stderr captured */
static void run(const kelp_cli *c, result *r, char **argv)
{
    int argc = 0;
    while (argv[argc]) argc++;
    memset(r, 0, sizeof *r);
    r->status = -1;
    FILE *o = tmpfile(), *e = tmpfile();
    ck_assert_ptr_nonnull(o);
    ck_assert_ptr_nonnull(e);
    fflush(stdout);
    fflush(stderr);
    int so = dup(1), se = dup(2);
    dup2(fileno(o), 1);
    dup2(fileno(e), 2);
    optind = 0; /* GNU: start a new scan */
    int x, st = 0;
    while ((x = kelp_cli_next(c, argc, argv, &st)) != -1) {
        if (x == KELP_CLI_EXIT) {
            r->status = st;
            break;
        }
        if (r->nopts < 8) {
            snprintf(r->optargs[r->nopts], sizeof r->optargs[0], "%s", optarg ? optarg : "");
            r->opts[r->nopts++] = x;
        }
    }
    r->first_pos = optind;
    fflush(stdout);
    fflush(stderr);
    dup2(so, 1);
    dup2(se, 2);
    close(so);
    close(se);
    slurp(o, r->out, sizeof r->out);
    slurp(e, r->err, sizeof r->err);
}

START_TEST(options_and_positionals)
{
    result r;
    char *argv[] = { "kelp-test", "f1", "-c", "5", "--raw", "--count=7", "-v", "f2", NULL };
    run(&cli, &r, argv);
    ck_assert_int_eq(r.status, -1);
    ck_assert_int_eq(r.nopts, 4);
    ck_assert_int_eq(r.opts[0], 'c');
    ck_assert_str_eq(r.optargs[0], "5");
    ck_assert_int_eq(r.opts[1], OPT_RAW);
    ck_assert_int_eq(r.opts[2], 'c');
    ck_assert_str_eq(r.optargs[2], "7");
    ck_assert_int_eq(r.opts[3], 'v'); /* the program's own -v wins over --version's short form */
    /* positionals are moved to the end, in order */
    ck_assert_int_eq(r.first_pos, 6);
    ck_assert_str_eq(argv[6], "f1");
    ck_assert_str_eq(argv[7], "f2");
    ck_assert_str_eq(r.out, "");
    ck_assert_str_eq(r.err, "");
}
END_TEST

START_TEST(help_and_version)
{
    result r;
    char *a1[] = { "kelp-test", "--help", NULL };
    run(&cli, &r, a1);
    ck_assert_int_eq(r.status, 0);
    ck_assert_ptr_nonnull(strstr(r.out, "usage: kelp-test [OPTIONS] FILE\n"));
    ck_assert_ptr_nonnull(strstr(r.out, "A test program."));
    ck_assert_ptr_nonnull(strstr(r.out, "-c, --count=N"));
    ck_assert_ptr_nonnull(strstr(r.out, "    --raw"));
    ck_assert_ptr_nonnull(strstr(r.out, "-h, --help"));
    ck_assert_ptr_nonnull(strstr(r.out, "    --version")); /* no -v: the program uses it */
    ck_assert_ptr_null(strstr(r.out, "-v, --version"));
    ck_assert_ptr_nonnull(strstr(r.out, "More text.\n"));
    ck_assert_str_eq(r.err, "");
    char *a2[] = { "kelp-test", "-h", NULL };
    run(&cli, &r, a2);
    ck_assert_int_eq(r.status, 0);
    ck_assert_ptr_nonnull(strstr(r.out, "usage: kelp-test"));
    char *a3[] = { "kelp-test", "x", "--version", NULL };
    run(&cli, &r, a3);
    ck_assert_int_eq(r.status, 0);
    ck_assert_str_eq(r.out, "kelp-test (kelp) " KELP_VERSION "\n");
    /* a program that does not use -v gets it for --version */
    static const kelp_cli bare = { "kelp-bare", NULL, "", NULL, NULL, false };
    char *a4[] = { "kelp-bare", "-v", NULL };
    run(&bare, &r, a4);
    ck_assert_int_eq(r.status, 0);
    ck_assert_str_eq(r.out, "kelp-bare (kelp) " KELP_VERSION "\n");
}
END_TEST

START_TEST(usage_errors)
{
    result r;
    char *a1[] = { "kelp-test", "--nope", NULL };
    run(&cli, &r, a1);
    ck_assert_int_eq(r.status, 2);
    ck_assert_str_eq(r.err, "kelp-test: unknown option '--nope' (try --help)\n");
    ck_assert_str_eq(r.out, "");
    char *a2[] = { "kelp-test", "-x", NULL };
    run(&cli, &r, a2);
    ck_assert_int_eq(r.status, 2);
    ck_assert_str_eq(r.err, "kelp-test: unknown option '-x' (try --help)\n");
    char *a3[] = { "kelp-test", "--count", NULL };
    run(&cli, &r, a3);
    ck_assert_int_eq(r.status, 2);
    ck_assert_str_eq(r.err, "kelp-test: option '--count' needs an argument (try --help)\n");
    char *a4[] = { "kelp-test", "-c", NULL };
    run(&cli, &r, a4);
    ck_assert_int_eq(r.status, 2);
    ck_assert_str_eq(r.err, "kelp-test: option '-c' needs an argument (try --help)\n");
}
END_TEST

START_TEST(in_order_stops_at_the_command)
{
    static const kelp_cli sub = { "kelp-sub", NULL, "CMD ARGS...", opts, NULL, true };
    result r;
    char *argv[] = { "kelp-sub", "--raw", "run", "-c", "3", NULL };
    run(&sub, &r, argv);
    ck_assert_int_eq(r.status, -1);
    ck_assert_int_eq(r.nopts, 1);
    ck_assert_int_eq(r.opts[0], OPT_RAW);
    ck_assert_int_eq(r.first_pos, 2);
    ck_assert_str_eq(argv[2], "run");
    ck_assert_str_eq(argv[3], "-c");
}
END_TEST

START_TEST(usage_continuation_lines)
{
    static const kelp_cli two = { "kelp-two", NULL, "a B\n c D\nother", NULL, NULL, false };
    FILE *f = tmpfile();
    char buf[256];
    kelp_cli_usage(&two, f);
    slurp(f, buf, sizeof buf);
    ck_assert_str_eq(buf, "usage: kelp-two a B\n                c D\n       kelp-two other\n");
}
END_TEST

Suite *kelp_cli_suite(void)
{
    Suite *s = suite_create("cli");
    TCase *t = tcase_create("cli");
    tcase_add_test(t, options_and_positionals);
    tcase_add_test(t, help_and_version);
    tcase_add_test(t, usage_errors);
    tcase_add_test(t, in_order_stops_at_the_command);
    tcase_add_test(t, usage_continuation_lines);
    suite_add_tcase(s, t);
    return s;
}
