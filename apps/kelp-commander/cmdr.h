/* kelp-commander (the iCommander role): state shared by main.c (configuration, bus, the
 * scripted --send mode) and console.c (the ncurses console). The model is the core
 * kelp_commander (include/kelp/commander.h). */
#ifndef KELP_COMMANDER_APP_H
#define KELP_COMMANDER_APP_H

#include <stdio.h>

#include <kelp/acomms.h>
#include <kelp/app.h>
#include <kelp/commander.h>
#include <kelp/edge/dccl.h>

#define CMDR_MAX_LOAD 8
#define CMDR_MAX_SHOW 8
#define CMDR_NOTE 512

typedef struct cmdr_app {
    kelp_app *app;
    kelp_acomms_config cfg;
    kelp_dccl_loaded ld;
    kelp_dccl_builtin geo;
    kelp_dccl_modem_entry modems[64];
    kelp_commander core;
    char base_dir[512];
    char load[CMDR_MAX_LOAD][KELP_ACOMMS_MAX_PATH];
    unsigned n_load;
    char show[CMDR_MAX_SHOW][KELP_MAX_NAME];
    char show_val[CMDR_MAX_SHOW][128];
    unsigned n_show;
    char note[CMDR_NOTE];       /* the last ack / expiry note */
    /* scripted mode: --send NAME field=value ... [--wait S] */
    const char *send_name;
    char **send_args;
    int n_send_args;
    double wait;
    bool sent;
    double sent_at;
    int exit_code;
    FILE *out;                  /* the terminal (stdout is quiet while we run) */
    int out_fd;
    void *console;              /* console.c's state, or NULL */
} cmdr_app;

/* main.c */
int cmdr_send(cmdr_app *s, unsigned msg, char *text, size_t cap);
int cmdr_import(cmdr_app *s, const char *path, kelp_diag *d);
int cmdr_load_file(cmdr_app *s, const char *path, kelp_diag *d);
int cmdr_save_file(cmdr_app *s, const char *path, kelp_diag *d);

/* console.c */
bool cmdr_console_start(cmdr_app *s);
void cmdr_console_note(cmdr_app *s);
void cmdr_console_stop(cmdr_app *s);

#endif
