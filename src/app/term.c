/* kelp terminal tables: see include/kelp/edge/term.h */
#include <curses.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <kelp/edge/term.h>

/* stdin reached its end: put a pipe nobody writes in its place so poll stays quiet */
static void quiet_stdin(void)
{
    int p[2];
    if (pipe(p) == 0) {
        (void)dup2(p[0], STDIN_FILENO);
        close(p[0]); /* p[1] stays open (never written) */
    }
}

bool kelp_term_start(kelp_term *t)
{
    memset(t, 0, sizeof *t);
    t->fd = -1;
    if (!isatty(STDOUT_FILENO)) return false;
    t->fd = dup(STDOUT_FILENO);
    t->out = t->fd >= 0 ? fdopen(t->fd, "w") : NULL;
    SCREEN *screen = t->out ? newterm(NULL, t->out, stdin) : NULL;
    if (!screen) {
        if (t->out) fclose(t->out);
        else if (t->fd >= 0) close(t->fd);
        t->out = NULL;
        t->fd = -1;
        return false;
    }
    t->screen = screen;
    set_term(screen);
    cbreak();
    noecho();
    nodelay(stdscr, TRUE);
    keypad(stdscr, TRUE);
    curs_set(0);
    fflush(stdout);
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
        (void)dup2(null, STDOUT_FILENO);
        close(null);
    }
    t->curses = true;
    return true;
}

void kelp_term_draw(kelp_term *t, const char *frame, const char *hint)
{
    if (!t->curses) {
        fputc('\n', stdout);
        fputs(frame, stdout);
        fflush(stdout);
        return;
    }
    erase();
    int y = 0, last = hint ? LINES - 1 : LINES;
    for (const char *p = frame; *p && y < last; y++) {
        size_t len = strcspn(p, "\n");
        if (y == 0) attron(A_BOLD);
        mvaddnstr(y, 0, p, (int)(len < (size_t)COLS ? len : (size_t)COLS));
        if (y == 0) attroff(A_BOLD);
        p += len + (p[len] == '\n');
    }
    if (hint) mvaddnstr(LINES - 1, 0, hint, COLS);
    refresh();
}

int kelp_term_keys(kelp_term *t, int fd, int *keys, int max)
{
    int n = 0;
    if (t->curses && isatty(fd)) {
        int c;
        while (n < max && (c = getch()) != ERR) keys[n++] = c == KEY_RESIZE ? KELP_TERM_RESIZE : c;
        return n;
    }
    unsigned char buf[64];
    ssize_t got = read(fd, buf, (size_t)max < sizeof buf ? (size_t)max : sizeof buf);
    if (got <= 0) {
        quiet_stdin();
        return 0;
    }
    for (ssize_t i = 0; i < got; i++) keys[n++] = buf[i];
    return n;
}

void kelp_term_stop(kelp_term *t)
{
    if (!t->curses) return;
    endwin();
    delscreen((SCREEN *)t->screen);
    fflush(t->out);
    (void)dup2(t->fd, STDOUT_FILENO); /* the runner's last status report goes to the terminal */
    fclose(t->out);
    t->curses = false;
}
