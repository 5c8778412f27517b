/* The command-line programs kelp-dccl and kelp-dccl-gen (not part of the library's API: the
 * symbols are hidden from the shared library; the apps link the static archive). */
#ifndef KELP_DCCL_PROGRAMS_H
#define KELP_DCCL_PROGRAMS_H

#define KELP_PROGRAM_ENTRY __attribute__((visibility("hidden")))

/** kelp-dccl. Returns the process exit status. */
KELP_PROGRAM_ENTRY int kelp_dccl_cli_main(int argc, char **argv);
/** kelp-dccl-gen FILE.xml [-o DIR] [--prefix NAME]. Returns the exit status. */
KELP_PROGRAM_ENTRY int kelp_dccl_gen_main(int argc, char **argv);

#endif
