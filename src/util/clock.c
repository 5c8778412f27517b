/* The time step rule's helpers (docs/ARCHITECTURE.md, "When the clock steps"): a core state
 * machine never reads a clock, so a step of the caller's clock reaches it as a `now` that
 * jumps.  A jump back is told by remembering the previous `now`; a jump forward cannot be told
 * from elapsed time, except by a machine that knows its largest sensible step. */
#include <kelp/util.h>

double kelp_util_clock_step(kelp_clock *c, double now, double max_fwd)
{
    double d = c->seen ? now - c->last : 0.0;
    c->last = now;
    c->seen = true;
    return (d < 0.0 || d > max_fwd) ? d : 0.0;
}

double kelp_util_clock_back(kelp_clock *c, double now)
{
    double d = kelp_util_clock_step(c, now, KELP_TIME_LIMIT * 2);
    return d < 0.0 ? -d : 0.0;
}
