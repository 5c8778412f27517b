/* The time-step rule's two helpers (docs/ARCHITECTURE.md, "When the clock steps"): a core
 * state machine never reads a clock, so a step of the caller's clock reaches it as a `now`
 * that jumps.  A jump back is told by remembering the newest `now`; a jump forward cannot be
 * told from elapsed time, except by an integrator that knows its largest sensible step. */
#include <kelp/util.h>

double kelp_clock_back(kelp_clock *c, double now)
{
    double back = 0.0;
    if (c->seen && now < c->last) back = c->last - now;
    c->last = now;
    c->seen = true;
    return back;
}

double kelp_clock_dt(kelp_clock *c, double now, double max_dt)
{
    double dt = c->seen ? now - c->last : 0.0;
    c->last = now;
    c->seen = true;
    return (dt > 0.0 && dt <= max_dt) ? dt : 0.0;
}
