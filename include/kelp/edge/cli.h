/* kelp command lines (edge): one convention for every program.
 *
 * Every program describes itself in a kelp_cli and reads its options with kelp_cli_next(),
 * which adds --help/-h and --version/-v (the short forms only where the program does not
 * use h or v itself): both print to stdout and end the program with status 0. A usage error
 * prints "<name>: <what> (try --help)" to stderr and ends it with status 2.
 *
 *   static const kelp_cli_opt opts[] = {
 *       { "count", required_argument, 'c', "N", "stop after N messages" },
 *       { "raw", no_argument, 1000, NULL, "print raw bytes" },     // long only: val >= 256
 *       { NULL, 0, 0, NULL, NULL },
 *   };
 *   static const kelp_cli cli = { .name = "kelp-foo", .purpose = "What it is for.",
 *                                 .synopsis = "[OPTIONS] FILE", .opts = opts };
 *   int c, status;
 *   while ((c = kelp_cli_next(&cli, argc, argv, &status)) != -1) switch (c) {
 *   case KELP_CLI_EXIT: return status;
 *   case 'c': ... optarg ...; break;
 *   }
 *   // argv[optind..argc-1] are the positional arguments
 *
 * --help is generated from the same table the options are parsed with, so the two cannot
 * drift. MOOS-role apps do not call this directly: kelp_app_run() (kelp/edge/app.h) does, adding
 * --example/-e, --interface/-i, --alias=NAME and --verbose.
 */
#ifndef KELP_EDGE_CLI_H
#define KELP_EDGE_CLI_H

#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>
#include <kelp/err.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kelp_cli_opt {
    const char *name;   /**< long name without "--" */
    int has_arg;        /**< no_argument, required_argument or optional_argument */
    int val;            /**< returned by kelp_cli_next; a letter also gives the short form -<val> */
    const char *arg;    /**< name of the argument in --help ("URL"), NULL if none */
    const char *help;   /**< one line for --help */
} kelp_cli_opt;

typedef struct kelp_cli {
    const char *name;          /**< the program's own name, e.g. "kelp-scope" */
    const char *purpose;       /**< one line: what the program is for */
    const char *synopsis;      /**< what follows the name in "usage:"; one form per line ('\n'),
                                    a line starting with ' ' continues the one before */
    const kelp_cli_opt *opts;  /**< terminated by a NULL name; NULL for none */
    const char *more;          /**< more text at the end of --help (arguments, environment), or NULL */
    bool in_order;             /**< stop at the first positional argument (it starts a sub-command) */
} kelp_cli;

#define KELP_CLI_EXIT (-2) /**< kelp_cli_next: help/version printed or a usage error; return *status */

/** The next option (its val), -1 when only positional arguments remain (from argv[optind]),
 *  or KELP_CLI_EXIT with *status set (0 after --help/--version, 2 after a usage error, whose
 *  message is already on stderr). Uses getopt_long's global state: parse one argv at a time. */
KELP_MUST_CHECK int kelp_cli_next(const kelp_cli *cli, int argc, char **argv, int *status);
/** Print "<name>: <message> (try --help)" to stderr; returns 2, the usage-error exit status. */
KELP_MUST_CHECK int kelp_cli_error(const kelp_cli *cli, const char *fmt, ...) KELP_PRINTF(2, 3);
/** Print the usage lines ("usage: <name> <synopsis>") to out. */
void kelp_cli_usage(const kelp_cli *cli, FILE *out);
/** Print "<name> (kelp) <version>" to stdout. */
void kelp_cli_version(const char *name);
/** A program that runs until stopped: handler is called on SIGINT and SIGTERM (it should only
 *  set a flag), and SIGPIPE is ignored (a closed pipe or socket is an error return instead). */
void kelp_cli_on_stop(void (*handler)(int));

#ifdef __cplusplus
}
#endif

#endif
