/* Fixture for test/integration/stack_report.sh: calls through a const table of behaviour-like
 * ops (designated), through an algorithm registry filled from a positional table, and through
 * a sink the caller passes in. Compiled with -fcallgraph-info=su into table.ci. */
#include <stddef.h>

typedef struct t_obj t_obj;
typedef struct t_ops {
    const char *type;
    int (*on_run)(t_obj *o, int x);
    void (*on_idle)(t_obj *o);
} t_ops;
struct t_obj {
    const t_ops *ops;
    int v;
};
typedef void (*t_alg_fn)(double *v, void *user);
typedef struct t_alg_entry {
    const char *name;
    t_alg_fn fn;
} t_alg_entry;
typedef struct t_sink {
    void *ctx;
    void (*publish)(void *ctx, const char *var, double d);
} t_sink;

static volatile int sink_hole;

static int big_run(t_obj *o, int x)
{
    volatile char buf[2000];
    for (int i = 0; i < 2000; i++) buf[i] = (char)(x + i);
    o->v = buf[x & 1023];
    return o->v;
}
static void small_idle(t_obj *o) { o->v = 0; }

const t_ops t_big_ops = { .type = "BIG", .on_run = big_run, .on_idle = small_idle };

int kelp_t_run(t_obj *o, int x)
{
    return o->ops->on_run(o, x);
}

static void alg_big(double *v, void *user)
{
    double w[300];
    (void)user;
    for (int i = 0; i < 300; i++) w[i] = *v * i;
    *v = w[(int)*v % 300];
}

void kelp_t_alg_add(t_alg_entry *e, const char *name, t_alg_fn fn)
{
    e->name = name;
    e->fn = fn;
}

void kelp_t_alg_builtin(t_alg_entry *e)
{
    static const struct {
        const char *name;
        t_alg_fn fn;
    } T[] = {{"big", alg_big}};
    kelp_t_alg_add(e, T[0].name, T[0].fn);
}

void kelp_t_alg_apply(const t_alg_entry *a, double *v)
{
    a->fn(v, NULL);
}

void kelp_t_publish(const t_sink *out, double d)
{
    out->publish(out->ctx, "X", d);
    sink_hole = 1;
}
