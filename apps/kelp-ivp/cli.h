#ifndef KELP_IVP_CLI_H
#define KELP_IVP_CLI_H
#include <kelp/ivp.h>
int kelp_ivp_cli(int argc, char **argv);
/* shared by the commands (cli.c, solve.c) */
int kivp_usage(void);
int kivp_fail(const char *where, const kelp_diag *d, int rc);
void *kivp_xcalloc(size_t n, size_t sz);
int kivp_build_spec(const kelp_ivp_spec *sp, const kelp_ivp_domain *dom, const char *var, kelp_ivp_func *f,
                   kelp_diag *d);
int kivp_print_points(const kelp_ivp_func *f);
int kivp_build_couple(const kelp_ivp_domain *dom, const kelp_ivp_spec *a, const kelp_ivp_spec *b, double wc, double ws,
                     kelp_ivp_func *out, kelp_diag *d);
int kivp_cmd_solve(int argc, char **argv, long repeat);
int kivp_cmd_cpa(int argc, char **argv);
#endif
