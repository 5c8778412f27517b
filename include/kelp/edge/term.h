/* kelp terminal tables (edge): how a scope app (uFldScope, kelp-scope) shows its frames.
 *
 * On a terminal, frames are redrawn in place with ncurses and keys act at once; stdout (the
 * runner's status report) is pointed at /dev/null until kelp_term_stop, which gives it back
 * for the last report. Otherwise each frame is printed as plain lines after a blank line, and
 * keys may still be written to stdin (a pipe or FIFO), one character each. */
#ifndef KELP_EDGE_TERM_H
#define KELP_EDGE_TERM_H

#include <stdbool.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define KELP_TERM_RESIZE (-2) /**< kelp_term_keys: the terminal changed size (redraw) */

typedef struct kelp_term {
    bool curses;   /**< drawing with ncurses */
    int fd;        /**< the terminal, while stdout points at /dev/null */
    FILE *out;
    void *screen;
} kelp_term;

/** Start: ncurses when stdout is a terminal (and it can be set up), else plain lines.
 *  @return t->curses. */
bool kelp_term_start(kelp_term *t);
/** Show one frame (lines end in '\n'; the first is drawn bold) with a key hint on the last
 *  terminal line (curses only; NULL for none). */
void kelp_term_draw(kelp_term *t, const char *frame, const char *hint);
/** Read the keys waiting on fd (stdin): up to max into keys (KELP_TERM_RESIZE for a resize).
 *  At the end of a non-terminal stdin, a quiet pipe takes its place.
 *  @return how many. */
int kelp_term_keys(kelp_term *t, int fd, int *keys, int max);
/** End curses and give stdout back (no-op in plain mode). */
void kelp_term_stop(kelp_term *t);

#ifdef __cplusplus
}
#endif

#endif
