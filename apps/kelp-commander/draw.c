/* kelp-commander: drawing the console (the screens of seed 002 section 2.4). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "console.h"

const char *const CMDR_MENU[10] = {"Return to message", "Send", "Preview", "Quick switch to another open message",
                                   "Insert special: current time", "Insert special: local X,Y to longitude,latitude",
                                   "Insert special: community", "Insert special: modem id", "Clear message",
                                   "Main Menu"};

int cmdr_main_items(const cmdr_app *s, const char **items, int cap)
{
    static const char *const ALL[] = {"Return to active message", "Select Message", "Load", "Save",
                                      "Import Message File", "Exit"};
    int n = 0;
    for (int i = s->core.active >= 0 ? 0 : 1; i < 6 && n < cap; i++) items[n++] = ALL[i];
    return n;
}

static int line(int y, const char *text)
{
    if (y < LINES) mvaddnstr(y, 0, text, COLS);
    return y + 1;
}

static int linef(int y, const char *fmt, ...) KELP_PRINTF(2, 3);
static int linef(int y, const char *fmt, ...)
{
    char b[512];
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(b, sizeof b, fmt, ap);
    va_end(ap);
    return line(y, b);
}

static int list(int y, const char *const *items, int n, int sel)
{
    for (int i = 0; i < n; i++) {
        if (i == sel) attron(A_REVERSE);
        y = linef(y, "  > %s", items[i]);
        if (i == sel) attroff(A_REVERSE);
    }
    return y;
}

static int note_box(cmdr_app *s, int y)
{
    if (!s->note[0] && !s->n_show) return y;
    for (const char *p = s->note; *p;) {
        size_t n = strcspn(p, "\n");
        y = linef(y, "|%.*s", (int)n, p);
        p += n + (p[n] == '\n');
    }
    for (unsigned i = 0; i < s->n_show; i++) y = linef(y, "%s: %s", s->show[i], s->show_val[i]);
    return line(y, "|----------------------------------------------------------------|") + 1;
}

static void draw_edit(cmdr_app *s, console *c, int y)
{
    const kelp_commander_msg *m = &s->core.open[c->msg];
    const kelp_dccl_field *f = kelp_commander_row_field(m, c->row);
    char d[512];
    kelp_commander_describe(f, d, sizeof d);
    y = linef(y, "|Editing message variable %u of %u: %s", c->row + 1, m->n_rows, f->name);
    y = linef(y, "|%s", d);
    y = linef(y, "|%s", c->status);
    y = line(y, "|----------------------------------------------------------------|") + 1;
    y = linef(y, "|Message (Type: %s)", m->def->name);
    y = linef(y, "|%u entries total", m->n_rows);
    y = line(y, "|   {Enter} for options");
    y = line(y, "|   {Up/Down} for more message variables");
    y = line(y, "|----------------------------------------------------------------|");
    int room = LINES - y, first = (int)c->row - room + 1;
    if (first < 0) first = 0;
    for (unsigned r = (unsigned)first; r < m->n_rows && y < LINES; r++) {
        const kelp_dccl_field *rf = kelp_commander_row_field(m, r);
        const char *v = (r == c->row && c->typing) ? c->buf : m->val[r];
        if (r == c->row) attron(A_REVERSE);
        y = linef(y, "|%u. %s (%s) |%s|", r + 1, rf->name, kelp_commander_type_name(rf), v);
        if (r == c->row) attroff(A_REVERSE);
    }
}

void cmdr_draw(cmdr_app *s, console *c)
{
    const char *items[64];
    int y = 0, n;
    erase();
    y = note_box(s, y);
    switch (c->screen_id) {
    case SCR_MAIN:
        y = line(y, "|----------------------------------------------------------------|");
        y = line(y, "|           iCommander: Vehicle Command Message Sender           |");
        y = linef(y, "|                   %zu messages loaded.", s->ld.set.n);
        y = line(y, "|   Main Menu:");
        n = cmdr_main_items(s, items, 6);
        y = list(y, items, n, c->sel);
        y = line(y, "|----------------------------------------------------------------|");
        (void)linef(y, "%s", c->status);
        break;
    case SCR_SELECT:
        y = line(y, "Select Message:");
        for (n = 0; n < (int)s->ld.set.n && n < 64; n++) items[n] = s->ld.set.msgs[n]->name;
        (void)list(y, items, n, c->sel);
        break;
    case SCR_QUICK:
        y = line(y, "Quick switch to another open message:");
        for (n = 0; n < (int)s->core.n_open && n < KELP_CMDR_MAX_OPEN; n++) items[n] = s->core.open[n].def->name;
        (void)list(y, items, n, c->sel);
        break;
    case SCR_MODEM:
        y = line(y, "Insert special: modem id");
        for (n = 0; n < (int)s->geo.n_modems && n < 64; n++) items[n] = s->geo.modems[n].name;
        (void)list(y, items, n, c->sel);
        break;
    case SCR_MENU:
        y = line(y, "|----------------------------------------------------------------|");
        y = line(y, "|           Choose an action");
        y = list(y, CMDR_MENU, 10, c->sel);
        (void)line(y, "|----------------------------------------------------------------|");
        break;
    case SCR_PROMPT:
        y = linef(y, "%s file path, then {Enter} ({Esc} cancels):",
                  c->prompt_id == P_LOAD ? "Load" : c->prompt_id == P_SAVE ? "Save to" : "Import DCCL XML");
        (void)linef(y, "> %s", c->buf);
        break;
    case SCR_TEXT:
        for (const char *p = c->text; *p && y < LINES - 1;) {
            size_t k = strcspn(p, "\n");
            y = linef(y, "%.*s", (int)k, p);
            p += k + (p[k] == '\n');
        }
        (void)line(y, "(any key returns)");
        break;
    case SCR_EDIT: draw_edit(s, c, y); break;
    }
    refresh();
}
