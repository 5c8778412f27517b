/* One command-line convention for every kelp program: getopt_long plus --help/--version. */
#include <stdarg.h>
#include <string.h>

#include <kelp/edge/cli.h>

#ifndef KELP_VERSION
#define KELP_VERSION "unknown"
#endif

enum { CLI_MAX_OPTS = 48, CLI_HELP = 0x7f01, CLI_VERSION = 0x7f02 };

void kelp_cli_version(const char *name)
{
    printf("%s (kelp) %s\n", name, KELP_VERSION);
}

void kelp_cli_usage(const kelp_cli *cli, FILE *out)
{
    const char *s = cli->synopsis ? cli->synopsis : "";
    const char *lead = "usage:";
    for (;;) {
        const char *nl = strchr(s, '\n');
        int len = nl ? (int)(nl - s) : (int)strlen(s);
        fprintf(out, "%-6s %s %.*s\n", lead, cli->name, len, s);
        lead = "";
        if (!nl || !nl[1]) break;
        s = nl + 1;
    }
}

static char version_short(const kelp_cli *cli)
{
    return (cli->shortopts && strchr(cli->shortopts, 'v')) ? 'V' : 'v';
}

static void help(const kelp_cli *cli)
{
    kelp_cli_usage(cli, stdout);
    if (cli->purpose && cli->purpose[0]) printf("\n%s\n", cli->purpose);
    printf("\nOptions:\n");
    if (cli->options) fputs(cli->options, stdout);
    printf("  -h, --help       print this text and exit\n"
           "  -%c, --version    print the version and exit\n", version_short(cli));
}

int kelp_cli_error(const kelp_cli *cli, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", cli->name);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, " (try --help)\n");
    return 2;
}

int kelp_cli_next(const kelp_cli *cli, int argc, char **argv, int *status)
{
    struct option all[CLI_MAX_OPTS];
    size_t n = 0;
    for (const struct option *o = cli->longopts; o && o->name && n < CLI_MAX_OPTS - 3; o++) all[n++] = *o;
    all[n++] = (struct option){ "help", no_argument, NULL, CLI_HELP };
    all[n++] = (struct option){ "version", no_argument, NULL, CLI_VERSION };
    all[n] = (struct option){ NULL, 0, NULL, 0 };
    char shorts[96];
    /* leading ':' reports a missing argument as ':' so the message can name the option */
    char vs = version_short(cli);
    snprintf(shorts, sizeof shorts, ":%sh%c", cli->shortopts ? cli->shortopts : "", vs);
    opterr = 0;
    int c = getopt_long(argc, argv, shorts, all, NULL);
    if (c == vs) c = CLI_VERSION;
    switch (c) {
    case 'h':
    case CLI_HELP:
        help(cli);
        *status = 0;
        return KELP_CLI_EXIT;
    case CLI_VERSION:
        kelp_cli_version(cli->name);
        *status = 0;
        return KELP_CLI_EXIT;
    case ':':
        *status = kelp_cli_error(cli, "option '%s' needs an argument", argv[optind - 1]);
        return KELP_CLI_EXIT;
    case '?':
        if (optopt) *status = kelp_cli_error(cli, "unknown option '-%c'", optopt);
        else *status = kelp_cli_error(cli, "unknown option '%s'", argv[optind - 1]);
        return KELP_CLI_EXIT;
    default: return c;
    }
}
