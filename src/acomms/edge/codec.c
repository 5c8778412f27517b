/* kelp acomms: a DCCL glue handle as the handler's codec (edge: the glue allocates). */
#include <kelp/acomms.h>

static size_t count(void *ctx)
{
    return kelp_acomms_dccl_count(ctx);
}

static int info(void *ctx, size_t i, kelp_acomms_dccl_info *out)
{
    return kelp_acomms_dccl_info_get(ctx, i, out);
}

static long find_id(void *ctx, unsigned id)
{
    return kelp_acomms_dccl_find_id(ctx, id);
}

static size_t nvars(void *ctx)
{
    return kelp_acomms_dccl_nvars(ctx);
}

static const char *var_name(void *ctx, size_t i)
{
    return kelp_acomms_dccl_var_name(ctx, i);
}

static size_t triggered(void *ctx, const char *name, size_t *idx, size_t cap)
{
    return kelp_acomms_dccl_triggered(ctx, name, idx, cap);
}

static int encode(void *ctx, size_t i, double now, uint8_t *out, size_t cap, size_t *len, kelp_diag *d)
{
    return kelp_acomms_dccl_encode_vars(ctx, i, now, out, cap, len, d);
}

static void set_var(void *ctx, const char *name, bool is_double, double dval, const char *sval)
{
    kelp_acomms_dccl_set_var(ctx, name, is_double, dval, sval);
}

static void start(void *ctx, double now)
{
    kelp_acomms_dccl_start(ctx, now);
}

static size_t due(void *ctx, double now, size_t *idx, size_t cap)
{
    return kelp_acomms_dccl_due(ctx, now, idx, cap);
}

static int decode(void *ctx, const uint8_t *in, size_t n, double now, kelp_acomms_pub_fn fn, void *user,
                  kelp_diag *d)
{
    return kelp_acomms_dccl_decode(ctx, in, n, now, fn, user, d);
}

static int describe(void *ctx, const uint8_t *in, size_t n, double now, char *buf, size_t cap)
{
    return kelp_acomms_dccl_describe(ctx, in, n, now, buf, cap);
}

void kelp_acomms_dccl_codec(kelp_acomms_dccl *d, kelp_acomms_codec *out)
{
    out->ctx = d;
    out->count = count;
    out->info = info;
    out->find_id = find_id;
    out->nvars = nvars;
    out->var_name = var_name;
    out->set_var = set_var;
    out->triggered = triggered;
    out->start = start;
    out->due = due;
    out->encode = encode;
    out->decode = decode;
    out->describe = describe;
}
