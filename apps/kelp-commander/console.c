/* kelp-commander: the ncurses console's keys (screens drawn by draw.c). */
#include <stdlib.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "console.h"

static console con;

static void status(console *c, const char *fmt, ...) KELP_PRINTF(2, 3);
static void status(console *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(c->status, sizeof c->status, fmt, ap);
    va_end(ap);
}

static void edit(console *c, int msg)
{
    c->msg = msg;
    c->row = 0;
    c->typing = false;
    c->screen_id = SCR_EDIT;
    c->status[0] = 0;
}

/* the typed text into the selected row (refused when the field does not take it) */
static bool commit(cmdr_app *s, console *c)
{
    kelp_diag why;
    kelp_diag_clear(&why);
    if (!c->typing) return true;
    c->typing = false;
    if (kelp_commander_set(&s->core, (unsigned)c->msg, c->row, c->buf, &why) < 0) {
        status(c, "refused \"%s\": %s", c->buf, kelp_diag_text(&why));
        return false;
    }
    status(c, "%s", "");
    return true;
}

static void insert(cmdr_app *s, console *c, const char *v)
{
    (void)snprintf(c->buf, sizeof c->buf, "%s", v);
    c->typing = true;
    (void)commit(s, c);
    c->screen_id = SCR_EDIT;
}

static void key_edit(cmdr_app *s, console *c, int k)
{
    const kelp_commander_msg *m = &s->core.open[c->msg];
    const kelp_dccl_field *f = kelp_commander_row_field(m, c->row);
    bool num = f->type == KELP_DCCL_T_INT || f->type == KELP_DCCL_T_FLOAT || f->type == KELP_DCCL_T_HEAD_TIME;
    size_t n = strlen(c->buf);
    if (k == KEY_UP || k == KEY_DOWN) {
        (void)commit(s, c);
        if (k == KEY_UP && c->row > 0) c->row--;
        if (k == KEY_DOWN && c->row + 1 < m->n_rows) c->row++;
    } else if (k == '\n' || k == '\r' || k == KEY_ENTER) {
        if (commit(s, c)) c->screen_id = SCR_MENU, c->sel = 0;
    } else if (k == KEY_BACKSPACE || k == 127 || k == 8) {
        if (!c->typing) (void)snprintf(c->buf, sizeof c->buf, "%s", m->val[c->row]), n = strlen(c->buf);
        c->typing = true;
        if (n) c->buf[n - 1] = 0;
    } else if (num && !c->typing && k == 't') {
        insert(s, c, "_time");
    } else if (f->type == KELP_DCCL_T_FLOAT && !c->typing && (k == 'y' || k == 'x')) {
        (void)snprintf(c->buf, sizeof c->buf, "%s%u:", k == 'y' ? "y(lat)" : "x(lon)", kelp_commander_next_xy(m));
        c->typing = true;
    } else if (k >= 32 && k < 127) {
        if (!c->typing) c->buf[0] = 0, n = 0;
        c->typing = true;
        if (n + 1 < sizeof c->buf) c->buf[n] = (char)k, c->buf[n + 1] = 0;
    }
}

static void menu_action(cmdr_app *s, console *c)
{
    char t[64];
    switch (c->sel) {
    case 1:
        if (cmdr_send(s, (unsigned)c->msg, c->text, sizeof c->text) == 0) {
            size_t n = strlen(c->text);
            (void)snprintf(c->text + n, sizeof c->text - n, "\nMessage %s sent.\n", s->core.open[c->msg].def->name);
        }
        c->screen_id = SCR_TEXT;
        break;
    case 2: {
        kelp_commander_pub p[KELP_CMDR_MAX_PUBS];
        size_t n;
        kelp_diag why;
        kelp_diag_clear(&why);
        if (kelp_commander_send(&s->core, (unsigned)c->msg, kelp_app_time(s->app), p, KELP_CMDR_MAX_PUBS, &n, &why) < 0) {
            (void)snprintf(c->text, sizeof c->text, "cannot be sent: %s\n", why.code ? kelp_diag_text(&why) : "too long");
        } else {
            size_t at = 0;
            c->text[0] = 0;
            for (size_t i = 0; i < n; i++) {
                int k = snprintf(c->text + at, sizeof c->text - at, "%s: %s\n", p[i].var, p[i].val);
                if (k < 0 || (size_t)k >= sizeof c->text - at) break;
                at += (size_t)k;
            }
        }
        c->screen_id = SCR_TEXT;
        break;
    }
    case 3: c->screen_id = SCR_QUICK, c->sel = 0; break;
    case 4: insert(s, c, "_time"); break;
    case 5:
        (void)snprintf(t, sizeof t, "y(lat)%u:", kelp_commander_next_xy(&s->core.open[c->msg]));
        (void)snprintf(c->buf, sizeof c->buf, "%s", t);
        c->typing = true;
        c->screen_id = SCR_EDIT;
        break;
    case 6: insert(s, c, s->cfg.community); break;
    case 7: c->screen_id = SCR_MODEM, c->sel = 0; break;
    case 8: kelp_commander_clear(&s->core, (unsigned)c->msg), c->screen_id = SCR_EDIT; break;
    case 9: c->screen_id = SCR_MAIN, c->sel = 0; break;
    default: c->screen_id = SCR_EDIT; break;
    }
}

static void main_action(cmdr_app *s, console *c)
{
    const char *items[6];
    int n = cmdr_main_items(s, items, 6);
    const char *it = c->sel < n ? items[c->sel] : "";
    c->status[0] = 0;
    if (strcmp(it, "Return to active message") == 0) edit(c, s->core.active);
    else if (strcmp(it, "Select Message") == 0) c->screen_id = SCR_SELECT, c->sel = 0;
    else if (strcmp(it, "Exit") == 0) kelp_app_quit(s->app);
    else {
        c->prompt_id = strcmp(it, "Load") == 0 ? P_LOAD : strcmp(it, "Save") == 0 ? P_SAVE : P_IMPORT;
        c->buf[0] = 0;
        c->screen_id = SCR_PROMPT;
    }
}

static void prompt_done(cmdr_app *s, console *c)
{
    kelp_diag err;
    kelp_diag_clear(&err);
    int rc = c->prompt_id == P_LOAD   ? cmdr_load_file(s, c->buf, &err)
             : c->prompt_id == P_SAVE ? cmdr_save_file(s, c->buf, &err)
                                      : cmdr_import(s, c->buf, &err);
    if (rc < 0) status(c, "%s", kelp_diag_text(&err));
    else status(c, "%s: done", c->buf);
    c->screen_id = SCR_MAIN;
    c->sel = 0;
}

static int count(cmdr_app *s, console *c)
{
    const char *items[6];
    switch (c->screen_id) {
    case SCR_MAIN: return cmdr_main_items(s, items, 6);
    case SCR_SELECT: return (int)s->ld.set.n;
    case SCR_QUICK: return (int)s->core.n_open;
    case SCR_MODEM: return (int)s->geo.n_modems;
    case SCR_MENU: return 10;
    default: return 0;
    }
}

static void key(cmdr_app *s, console *c, int k)
{
    bool enter = k == '\n' || k == '\r' || k == KEY_ENTER;
    int n = count(s, c);
    if (c->screen_id == SCR_EDIT) return key_edit(s, c, k);
    if (c->screen_id == SCR_TEXT) { c->screen_id = c->msg >= 0 ? SCR_EDIT : SCR_MAIN; return; }
    if (c->screen_id == SCR_PROMPT) {
        size_t len = strlen(c->buf);
        if (k == 27) c->screen_id = SCR_MAIN;
        else if (enter) prompt_done(s, c);
        else if ((k == KEY_BACKSPACE || k == 127 || k == 8) && len) c->buf[len - 1] = 0;
        else if (k >= 32 && k < 127 && len + 1 < sizeof c->buf) c->buf[len] = (char)k, c->buf[len + 1] = 0;
        return;
    }
    if (k == KEY_UP && c->sel > 0) c->sel--;
    if (k == KEY_DOWN && c->sel + 1 < n) c->sel++;
    if (!enter || c->sel >= n) return;
    switch (c->screen_id) {
    case SCR_MAIN: main_action(s, c); break;
    case SCR_SELECT: {
        int m = kelp_commander_open(&s->core, s->ld.set.msgs[c->sel]->name);
        if (m >= 0) edit(c, m);
        break;
    }
    case SCR_QUICK: edit(c, c->sel); break;
    case SCR_MODEM: {
        char id[16];
        (void)snprintf(id, sizeof id, "%d", s->geo.modems[c->sel].id);
        insert(s, c, id);
        break;
    }
    case SCR_MENU: menu_action(s, c); break;
    default: break;
    }
}

static void on_key(kelp_app *app, void *st, int fd)
{
    cmdr_app *s = st;
    int k;
    (void)app;
    (void)fd;
    while ((k = getch()) != ERR) key(s, &con, k);
    cmdr_draw(s, &con);
}

bool cmdr_console_start(cmdr_app *s)
{
    console *c = &con;
    memset(c, 0, sizeof *c);
    c->msg = -1;
    c->term = s->out;
    c->screen = newterm(NULL, c->term, stdin);
    if (!c->screen) return false;
    set_term(c->screen);
    cbreak();
    noecho();
    nodelay(stdscr, TRUE);
    keypad(stdscr, TRUE);
    curs_set(0);
    s->console = c;
    if (kelp_app_watch_fd(s->app, STDIN_FILENO, on_key) < 0) kelp_app_run_warning(s->app, "keys cannot be read");
    cmdr_draw(s, c);
    return true;
}

void cmdr_console_note(cmdr_app *s)
{
    cmdr_draw(s, s->console);
}

void cmdr_console_stop(cmdr_app *s)
{
    console *c = s->console;
    endwin();
    delscreen(c->screen);
    s->console = NULL;
}
