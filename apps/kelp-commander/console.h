/* kelp-commander console state (console.c keys, draw.c drawing). */
#ifndef KELP_COMMANDER_CONSOLE_H
#define KELP_COMMANDER_CONSOLE_H

#include <curses.h>

#include "cmdr.h"

typedef enum scr { SCR_MAIN, SCR_SELECT, SCR_EDIT, SCR_MENU, SCR_QUICK, SCR_MODEM, SCR_PROMPT, SCR_TEXT } scr;
typedef enum prompt { P_LOAD, P_SAVE, P_IMPORT } prompt;

typedef struct console {
    SCREEN *screen;
    FILE *term;
    scr screen_id;
    prompt prompt_id;
    int sel;                     /* highlighted item of a menu or list */
    int msg;                     /* open message being edited, or -1 */
    unsigned row;                /* its selected row */
    char buf[KELP_CMDR_VAL];     /* text being typed */
    bool typing;
    char status[256];            /* one line under the info box */
    char text[8192];             /* SCR_TEXT: preview or what was sent */
} console;

extern const char *const CMDR_MENU[10];
void cmdr_draw(cmdr_app *s, console *c);
int cmdr_main_items(const cmdr_app *s, const char **items, int cap);

#endif
