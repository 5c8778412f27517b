#ifndef KELP_IVP_CLI_H
#define KELP_IVP_CLI_H
int kelp_ivp_cli(int argc, char **argv);
#endif
