/* kelp command lines (edge): one convention for every program.
 *
 * Every program parses its options with getopt_long through kelp_cli_next(), which adds
 * --help/-h and --version/-v (-V when the program uses -v itself) to its own options: both print to stdout and end the
 * program with status 0; an unknown option or a missing argument prints
 * "<name>: <reason> (try --help)" to stderr and ends it with status 2.
 *
 *     static const struct option opts[] = { {"xml", required_argument, 0, 'x'}, {0, 0, 0, 0} };
 *     static const kelp_cli cli = { "kelp-tool", "[--xml FILE] INPUT", "What it is for.",
 *                                   "  --xml FILE   message definitions\n", opts, "x:" };
 *     int c, status;
 *     while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
 *         if (c == KELP_CLI_EXIT) return status;
 *         switch (c) { case 'x': ...; }
 *     }
 *     // positional arguments: argv[optind .. argc-1]
 */
#ifndef KELP_EDGE_CLI_H
#define KELP_EDGE_CLI_H

#include <getopt.h>
#include <stdio.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

/** kelp_cli_next() result: the program must return *status now. */
#define KELP_CLI_EXIT (-2)

typedef struct kelp_cli {
    const char *name;              /**< the program's own name, e.g. "kelp-logcheck" */
    const char *synopsis;          /**< usage after the name; several lines are separated by '\n' */
    const char *purpose;           /**< what the program is for (printed by --help) */
    const char *options;           /**< help lines of the program's own options, or NULL */
    const struct option *longopts; /**< the program's own long options ({0} terminated), or NULL */
    const char *shortopts;         /**< the program's own short options (getopt syntax), or NULL */
} kelp_cli;

/** One getopt_long step over argv with the program's options plus --help and --version.
 *  @return the option's value, -1 when the options end (positionals start at optind), or
 *  KELP_CLI_EXIT with *status set (0 after --help/--version, 2 on a usage error). */
int kelp_cli_next(const kelp_cli *cli, int argc, char **argv, int *status);

/** Print "usage: <name> <synopsis>" (every line) to out. */
void kelp_cli_usage(const kelp_cli *cli, FILE *out);

/** Print a usage error ("<name>: <message> (try --help)") to stderr; returns 2. */
int kelp_cli_error(const kelp_cli *cli, const char *fmt, ...) KELP_PRINTF(2, 3);

/** Print "<name> (kelp) <version>" to stdout. */
void kelp_cli_version(const char *name);

#ifdef __cplusplus
}
#endif

#endif
