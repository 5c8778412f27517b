/* One command-line convention for every kelp program: getopt_long, plus --help and --version
 * answered the same way everywhere, and one form for usage errors. */
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>

#ifndef KELP_VERSION
#define KELP_VERSION "unknown"
#endif

enum {
    MAX_OPTS = 40,                /* a program's own options, plus help and version */
    OPT_HELP = 0x10001,           /* vals no program uses */
    OPT_VERSION = 0x10002,
};

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
        if (s[0] == ' ') /* a continuation of the line before */
            fprintf(out, "%-6s %*s%.*s\n", "", (int)strlen(cli->name), "", len, s);
        else
            fprintf(out, "%-6s %s %.*s\n", lead, cli->name, len, s);
        lead = "";
        if (!nl || !nl[1]) break;
        s = nl + 1;
    }
}

static bool is_short(int val)
{
    return val > ' ' && val < 127 && val != ':' && val != '?' && val != '-';
}

static bool uses_short(const kelp_cli *cli, int c)
{
    for (const kelp_cli_opt *o = cli->opts; o && o->name; o++)
        if (o->val == c) return true;
    return false;
}

static void help_line(const char *shortform, const char *name, const char *arg, int has_arg, const char *help)
{
    char left[64];
    if (!arg || has_arg == no_argument)
        snprintf(left, sizeof left, "%s--%s", shortform, name);
    else if (has_arg == optional_argument)
        snprintf(left, sizeof left, "%s--%s[=%s]", shortform, name, arg);
    else
        snprintf(left, sizeof left, "%s--%s=%s", shortform, name, arg);
    printf("  %-26s %s\n", left, help ? help : "");
}

static void help(const kelp_cli *cli)
{
    kelp_cli_usage(cli, stdout);
    if (cli->purpose && cli->purpose[0]) printf("\n%s\n", cli->purpose);
    printf("\nOptions:\n");
    for (const kelp_cli_opt *o = cli->opts; o && o->name; o++) {
        char sf[8] = "    ";
        if (is_short(o->val)) snprintf(sf, sizeof sf, "-%c, ", o->val);
        help_line(sf, o->name, o->arg, o->has_arg, o->help);
    }
    help_line(uses_short(cli, 'h') ? "    " : "-h, ", "help", NULL, no_argument, "print this text and exit");
    help_line(uses_short(cli, 'v') ? "    " : "-v, ", "version", NULL, no_argument, "print the version and exit");
    if (cli->more && cli->more[0]) printf("\n%s%s", cli->more, cli->more[strlen(cli->more) - 1] == '\n' ? "" : "\n");
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
    struct option all[MAX_OPTS + 3];
    char shorts[3 * MAX_OPTS + 8];
    size_t n = 0, ns = 0;
    shorts[ns++] = cli->in_order ? '+' : ':';
    if (cli->in_order) shorts[ns++] = ':'; /* ':' first: a missing argument is reported as ':' */
    for (const kelp_cli_opt *o = cli->opts; o && o->name && n < MAX_OPTS; o++) {
        all[n++] = (struct option){ o->name, o->has_arg, NULL, o->val };
        if (is_short(o->val)) {
            shorts[ns++] = (char)o->val;
            if (o->has_arg != no_argument) shorts[ns++] = ':';
            if (o->has_arg == optional_argument) shorts[ns++] = ':';
        }
    }
    all[n++] = (struct option){ "help", no_argument, NULL, OPT_HELP };
    all[n++] = (struct option){ "version", no_argument, NULL, OPT_VERSION };
    all[n] = (struct option){ NULL, 0, NULL, 0 };
    if (!uses_short(cli, 'h')) shorts[ns++] = 'h';
    if (!uses_short(cli, 'v')) shorts[ns++] = 'v';
    shorts[ns] = 0;

    opterr = 0;
    int c = getopt_long(argc, argv, shorts, all, NULL);
    if (c == 'h' && !uses_short(cli, 'h')) c = OPT_HELP;
    if (c == 'v' && !uses_short(cli, 'v')) c = OPT_VERSION;
    /* the argument getopt just looked at, for messages about long options */
    const char *arg = (optind > 0 && optind <= argc) ? argv[optind - 1] : "?";
    switch (c) {
    case OPT_HELP:
        help(cli);
        *status = 0;
        return KELP_CLI_EXIT;
    case OPT_VERSION:
        kelp_cli_version(cli->name);
        *status = 0;
        return KELP_CLI_EXIT;
    case '?':
        if (optopt && is_short(optopt)) *status = kelp_cli_error(cli, "unknown option '-%c'", optopt);
        else *status = kelp_cli_error(cli, "unknown option '%s'", arg);
        return KELP_CLI_EXIT;
    case ':':
        if (optopt && is_short(optopt) && !(arg[0] == '-' && arg[1] == '-'))
            *status = kelp_cli_error(cli, "option '-%c' needs an argument", optopt);
        else *status = kelp_cli_error(cli, "option '%s' needs an argument", arg);
        return KELP_CLI_EXIT;
    default:
        return c;
    }
}

void kelp_cli_on_stop(void (*handler)(int))
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = handler;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
}
