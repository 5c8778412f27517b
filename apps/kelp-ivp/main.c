/* kelp-ivp: build, inspect and solve IvP functions from the command line.
 *   kelp-ivp eval DOMAIN SPEC
 *   kelp-ivp couple DOMAIN2 CRS_SPEC SPD_SPEC WC WS
 *   kelp-ivp solve FILE [--repeat N]
 *   kelp-ivp cpa CNX CNY CNH CNV OSX OSY OSH OSV [TOL]
 * The logic is in cli.c; parsing and building are in the core (src/ivp). */
#include "cli.h"

int main(int argc, char **argv)
{
    return kelp_ivp_cli(argc, argv);
}
