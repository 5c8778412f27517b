/* kelp acomms: the pAcommsHandler ProcessConfig block (seed 002 section 2.3.5).
 *
 * The block body is protobuf TextFormat (the mission parser gives FIELD and MSG nodes); like
 * Goby's protobuf parser, an unknown field, a bad enum name or a malformed number is an error.
 * MOOS-style "Key = Value" lines (AppTick, CommsTick) are left to the app runner.
 * Global MOOS values fill empty fields: Community, LatOrigin, LongOrigin, log, log_path,
 * modem_id_lookup_path (and a global modem_id, which the mm2 example sets: used only when the
 * block has none -- Goby 1.1 reads it from the block only, so kelp warns). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <kelp/acomms.h>
#include <kelp/mission.h>

typedef struct rd {
    const kelp_mission *m;
    kelp_acomms_config *c;
    kelp_diag *d;
    char *warn;
    size_t warncap;
    const char *base;
    kelp_acomms_config_extra_fn extra;
    void *extra_ctx;
    int dccl_modem_id; /* dccl_cfg's modem_id: iCommander's only one (with `extra`) */
} rd;

static void note_fail(rd *r, const kelp_mission_node *n, const char *fmt, ...) KELP_PRINTF(3, 4);
static void note_fail(rd *r, const kelp_mission_node *n, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): va_start above */
    va_end(ap);
    if (n) {
        (void)kelp_failf(r->d, KELP_ERR_PARSE, "line %d: %.*s: %s", n->line, (int)n->klen, n->key, msg);
        (void)kelp_diag_where(r->d, n->line, 0);
    } else {
        (void)kelp_failf(r->d, KELP_ERR_PARSE, "%s", msg);
    }
}

/* a constant status (the analyzer does not follow variadic calls) */
#define fail(...) (note_fail(__VA_ARGS__), KELP_ERR_PARSE)

static void warn(rd *r, const kelp_mission_node *n, const char *fmt, ...) KELP_PRINTF(3, 4);
static void warn(rd *r, const kelp_mission_node *n, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    if (!r->warn || !r->warncap) return;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized): va_start above */
    va_end(ap);
    size_t o = strlen(r->warn);
    if (o + 1 >= r->warncap) return;
    snprintf(r->warn + o, r->warncap - o, "%sline %d: %s", o ? "\n" : "", n ? n->line : 0, msg);
}

static int get_str(rd *r, const kelp_mission_node *n, char *buf, size_t cap)
{
    if (n->kind != KELP_MN_FIELD) return fail(r, n, "expected a value, not a block");
    if (kelp_mission_copy(n, buf, cap) != KELP_OK) return fail(r, n, "value too long (max %zu bytes)", cap - 1);
    return KELP_OK;
}

static int get_long(rd *r, const kelp_mission_node *n, long long lo, long long hi, long long *out)
{
    long long v = 0;
    if (n->kind != KELP_MN_FIELD || n->quoted || kelp_util_parse_llong(n->val, n->vlen, &v) != KELP_OK)
        return fail(r, n, "expected an integer, got \"%.*s\"", (int)n->vlen, n->val ? n->val : "");
    if (v < lo || v > hi) return fail(r, n, "%lld is out of range %lld..%lld", v, lo, hi);
    *out = v;
    return KELP_OK;
}

static int get_double(rd *r, const kelp_mission_node *n, double *out)
{
    if (n->kind != KELP_MN_FIELD || n->quoted || kelp_mission_double(n, out) != KELP_OK)
        return fail(r, n, "expected a number, got \"%.*s\"", (int)n->vlen, n->val ? n->val : "");
    return KELP_OK;
}

static int get_bool(rd *r, const kelp_mission_node *n, bool *out)
{
    if (n->kind != KELP_MN_FIELD || n->quoted || kelp_mission_bool(n, out) != KELP_OK)
        return fail(r, n, "expected true or false, got \"%.*s\"", (int)n->vlen, n->val ? n->val : "");
    return KELP_OK;
}

/* enum by symbolic name (protobuf also accepts the number) */
static int get_enum(rd *r, const kelp_mission_node *n, const char *const *names, const int *values, size_t count, int *out)
{
    if (n->kind != KELP_MN_FIELD) return fail(r, n, "expected an enum value");
    for (size_t i = 0; i < count; i++)
        if (kelp_util_strieq_n(n->val, n->vlen, names[i]) && strlen(names[i]) == n->vlen) {
            *out = values[i];
            return KELP_OK;
        }
    long long v = 0;
    if (!n->quoted && kelp_util_parse_llong(n->val, n->vlen, &v) == KELP_OK)
        for (size_t i = 0; i < count; i++)
            if (values[i] == v) {
                *out = values[i];
                return KELP_OK;
            }
    char list[256] = "";
    for (size_t i = 0; i < count; i++) {
        size_t o = strlen(list);
        snprintf(list + o, sizeof list - o, "%s%s", i ? ", " : "", names[i]);
    }
    return fail(r, n, "unknown value \"%.*s\" (expected %s)", (int)n->vlen, n->val ? n->val : "", list);
}

static bool is(const kelp_mission_node *n, const char *key)
{
    return n->klen == strlen(key) && memcmp(n->key, key, n->klen) == 0;
}

#define FOR_CHILDREN(r, parent, var)                                                                       \
    for (int var##_i = kelp_mission_next((r)->m, (parent), -1, NULL); var##_i >= 0;                       \
         var##_i = kelp_mission_next((r)->m, (parent), var##_i, NULL))

static const kelp_mission_node *node(const rd *r, int i)
{
    return &r->m->nodes[i];
}

static int need_block(rd *r, const kelp_mission_node *n)
{
    if (n->kind != KELP_MN_MSG) return fail(r, n, "expected a block { ... }");
    return KELP_OK;
}

/* ------------------------------------------------------------------ common */

static int read_initializer(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    const kelp_mission_node *b = node(r, idx);
    if (c->n_init >= KELP_ACOMMS_MAX_INIT) return fail(r, b, "too many initializers (max %d)", KELP_ACOMMS_MAX_INIT);
    kelp_acomms_initializer *in = &c->init[c->n_init];
    memset(in, 0, sizeof *in);
    in->line = b->line;
    bool has_type = false;
    int rc;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "type")) {
            static const char *const N[] = { "INI_DOUBLE", "INI_STRING" };
            static const int V[] = { 1, 2 };
            int t = 0;
            if ((rc = get_enum(r, n, N, V, 2, &t))) return rc;
            in->is_double = t == 1;
            has_type = true;
        } else if (is(n, "moos_var")) {
            if ((rc = get_str(r, n, in->moos_var, sizeof in->moos_var))) return rc;
        } else if (is(n, "global_cfg_var")) {
            if ((rc = get_str(r, n, in->global_cfg_var, sizeof in->global_cfg_var))) return rc;
        } else if (is(n, "dval")) {
            if ((rc = get_double(r, n, &in->dval))) return rc;
            in->has_dval = true;
        } else if (is(n, "sval")) {
            if ((rc = get_str(r, n, in->sval, sizeof in->sval))) return rc;
            in->has_sval = true;
        } else {
            return fail(r, n, "unknown field in initializer");
        }
    }
    if (!has_type) return fail(r, b, "initializer without type (required: INI_DOUBLE or INI_STRING)");
    if (!in->moos_var[0]) return fail(r, b, "initializer without moos_var (required)");
    c->n_init++;
    return KELP_OK;
}

static int read_common(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    int rc;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "log")) {
            if ((rc = get_bool(r, n, &c->log))) return rc;
        } else if (is(n, "log_path")) {
            if ((rc = get_str(r, n, c->log_path, sizeof c->log_path))) return rc;
        } else if (is(n, "community")) {
            if ((rc = get_str(r, n, c->community, sizeof c->community))) return rc;
        } else if (is(n, "lat_origin")) {
            if ((rc = get_double(r, n, &c->lat_origin))) return rc;
            c->has_lat_origin = true;
        } else if (is(n, "lon_origin")) {
            if ((rc = get_double(r, n, &c->lon_origin))) return rc;
            c->has_lon_origin = true;
        } else if (is(n, "app_tick")) {
            if ((rc = get_double(r, n, &c->app_tick))) return rc;
        } else if (is(n, "comm_tick")) {
            if ((rc = get_double(r, n, &c->comm_tick))) return rc;
        } else if (is(n, "verbosity")) {
            static const char *const N[] = { "VERBOSITY_QUIET", "VERBOSITY_WARN", "VERBOSITY_VERBOSE", "VERBOSITY_DEBUG",
                                             "VERBOSITY_GUI" };
            static const int V[] = { KELP_ACOMMS_VERBOSITY_QUIET, KELP_ACOMMS_VERBOSITY_WARN,
                                     KELP_ACOMMS_VERBOSITY_VERBOSE, KELP_ACOMMS_VERBOSITY_DEBUG,
                                     KELP_ACOMMS_VERBOSITY_GUI };
            int v = 0;
            if ((rc = get_enum(r, n, N, V, 5, &v))) return rc;
            c->verbosity = (kelp_acomms_verbosity)v;
        } else if (is(n, "initializer")) {
            if ((rc = need_block(r, n)) || (rc = read_initializer(r, ch_i))) return rc;
        } else {
            return fail(r, n, "unknown field in common");
        }
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ driver_cfg */

static int read_modem_id(rd *r, const kelp_mission_node *n)
{
    long long v = 0;
    int rc = get_long(r, n, 0, 31, &v);
    if (rc) return rc;
    if (r->c->modem_id && v != r->c->modem_id)
        warn(r, n, "modem_id %lld differs from the top-level modem_id %d (the top level wins)", v, r->c->modem_id);
    if (!r->c->modem_id) r->dccl_modem_id = (int)v;
    return KELP_OK;
}

static int read_driver(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    int rc;
    long long v = 0;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "modem_id")) {
            if ((rc = read_modem_id(r, n))) return rc;
        } else if (is(n, "connection_type")) {
            static const char *const N[] = { "CONNECTION_SERIAL", "CONNECTION_TCP_AS_CLIENT", "CONNECTION_TCP_AS_SERVER",
                                             "CONNECTION_DUAL_UDP_BROADCAST" };
            static const int V[] = { KELP_ACOMMS_CONN_SERIAL, KELP_ACOMMS_CONN_TCP_AS_CLIENT,
                                     KELP_ACOMMS_CONN_TCP_AS_SERVER, KELP_ACOMMS_CONN_DUAL_UDP_BROADCAST };
            int t = 0;
            if ((rc = get_enum(r, n, N, V, 4, &t))) return rc;
            c->connection = (kelp_acomms_connection)t;
        } else if (is(n, "line_delimiter")) {
            if ((rc = get_str(r, n, c->line_delimiter, sizeof c->line_delimiter))) return rc;
            if (!c->line_delimiter[0]) return fail(r, n, "empty line_delimiter");
        } else if (is(n, "serial_port")) {
            if ((rc = get_str(r, n, c->serial_port, sizeof c->serial_port))) return rc;
        } else if (is(n, "serial_baud")) {
            if ((rc = get_long(r, n, 1, 4000000, &v))) return rc;
            c->serial_baud = (unsigned)v;
        } else if (is(n, "tcp_server")) {
            if ((rc = get_str(r, n, c->tcp_server, sizeof c->tcp_server))) return rc;
        } else if (is(n, "tcp_port")) {
            if ((rc = get_long(r, n, 0, 65535, &v))) return rc;
            c->tcp_port = (unsigned)v;
        } else if (is(n, "[MicroModemConfig.reset_nvram]")) {
            if ((rc = get_bool(r, n, &c->reset_nvram))) return rc;
        } else if (is(n, "[MicroModemConfig.nvram_cfg]")) {
            if (c->n_nvram >= KELP_MAX_MM_NVRAM) return fail(r, n, "too many nvram_cfg entries (max %d)", KELP_MAX_MM_NVRAM);
            if ((rc = get_str(r, n, c->nvram[c->n_nvram], sizeof c->nvram[0]))) return rc;
            const char *s = c->nvram[c->n_nvram];
            if (!s[0] || strpbrk(s, "*$\r\n") || !strchr(s, ','))
                return fail(r, n, "nvram_cfg must look like \"KEY,VALUE\" (e.g. \"CST,1\")");
            c->n_nvram++;
        } else if (is(n, "[MicroModemConfig.hydroid_gateway_id]")) {
            if ((rc = get_long(r, n, 0, 99, &v))) return rc;
            c->hydroid_gateway_id = (int)v;
        } else {
            return fail(r, n, "unknown field in driver_cfg");
        }
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ mac_cfg */

static int read_slot(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    const kelp_mission_node *b = node(r, idx);
    if (c->nslots >= KELP_MAX_MAC_SLOTS) return fail(r, b, "too many slots (max %d)", KELP_MAX_MAC_SLOTS);
    kelp_mac_slot *s = &c->slots[c->nslots];
    kelp_mac_slot_default(s, 0);
    bool has_src = false;
    int rc;
    long long v = 0;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "src")) {
            if ((rc = get_long(r, n, 0, 31, &v))) return rc;
            s->src = (int)v;
            has_src = true;
        } else if (is(n, "dest")) {
            if ((rc = get_long(r, n, -1, 31, &v))) return rc;
            s->dest = (int)v;
        } else if (is(n, "rate")) {
            if ((rc = get_long(r, n, 0, 5, &v))) return rc;
            s->rate = (unsigned)v;
        } else if (is(n, "type")) {
            static const char *const N[] = { "SLOT_DATA", "SLOT_PING", "SLOT_REMUS_LBL" };
            static const int V[] = { KELP_SLOT_DATA, KELP_SLOT_PING, KELP_SLOT_REMUS_LBL };
            int t = 0;
            if ((rc = get_enum(r, n, N, V, 3, &t))) return rc;
            s->type = (kelp_slot_type)t;
        } else if (is(n, "slot_seconds")) {
            if ((rc = get_long(r, n, 1, 86400, &v))) return rc;
            s->slot_seconds = (unsigned)v;
        } else if (is(n, "last_heard_time")) {
            char tmp[64];
            if ((rc = get_str(r, n, tmp, sizeof tmp))) return rc;
        } else {
            return fail(r, n, "unknown field in slot");
        }
    }
    if (!has_src) return fail(r, b, "slot without src (required)");
    c->nslots++;
    return KELP_OK;
}

static int read_mac(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    int rc;
    long long v = 0;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "modem_id")) {
            if ((rc = read_modem_id(r, n))) return rc;
        } else if (is(n, "type")) {
            static const char *const N[] = { "MAC_NONE", "MAC_FIXED_DECENTRALIZED", "MAC_AUTO_DECENTRALIZED",
                                             "MAC_POLLED" };
            static const int V[] = { KELP_MAC_NONE, KELP_MAC_FIXED_DECENTRALIZED, KELP_MAC_AUTO_DECENTRALIZED,
                                     KELP_MAC_POLLED };
            int t = 0;
            if ((rc = get_enum(r, n, N, V, 4, &t))) return rc;
            c->mac_type = (kelp_mac_type)t;
        } else if (is(n, "slot")) {
            if ((rc = need_block(r, n)) || (rc = read_slot(r, ch_i))) return rc;
        } else if (is(n, "rate")) {
            if ((rc = get_long(r, n, 0, 5, &v))) return rc;
            c->mac_rate = (unsigned)v;
        } else if (is(n, "slot_seconds")) {
            if ((rc = get_long(r, n, 1, 86400, &v))) return rc;
            c->mac_slot_seconds = (unsigned)v;
        } else if (is(n, "expire_cycles")) {
            if ((rc = get_long(r, n, 1, 1000000, &v))) return rc;
            c->mac_expire_cycles = (unsigned)v;
        } else {
            return fail(r, n, "unknown field in mac_cfg");
        }
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ queue_cfg / dccl_cfg */

static int add_file(rd *r, const kelp_mission_node *n, const char *path, unsigned manip)
{
    kelp_acomms_config *c = r->c;
    char full[KELP_ACOMMS_MAX_PATH];
    snprintf(full, sizeof full, "%s", path);
    /* relative paths: as MOOS apps, from the working directory; failing that, from the
     * mission file's directory (kelp-launch may run apps elsewhere) */
    if (path[0] != '/' && r->base && r->base[0] && access(path, R_OK) != 0) {
        int w = snprintf(full, sizeof full, "%s/%s", r->base, path);
        if (w < 0 || (size_t)w >= sizeof full) return fail(r, n, "path too long");
    }
    for (size_t i = 0; i < c->nfiles; i++)
        if (strcmp(c->files[i].path, full) == 0) {
            c->files[i].manip |= manip;
            return KELP_OK;
        }
    if (c->nfiles >= KELP_ACOMMS_MAX_FILES) return fail(r, n, "too many message files (max %d)", KELP_ACOMMS_MAX_FILES);
    snprintf(c->files[c->nfiles].path, sizeof c->files[0].path, "%s", full);
    c->files[c->nfiles].manip = manip;
    c->nfiles++;
    return KELP_OK;
}

static int read_message_file(rd *r, int idx)
{
    const kelp_mission_node *b = node(r, idx);
    char path[KELP_ACOMMS_MAX_PATH] = "";
    unsigned manip = 0;
    int rc;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "path")) {
            if ((rc = get_str(r, n, path, sizeof path))) return rc;
        } else if (is(n, "manipulator")) {
            if (n->kind != KELP_MN_FIELD) return fail(r, n, "expected a manipulator name");
            long bit = kelp_acomms_manip_from_name(n->val, n->vlen);
            if (bit < 0)
                return fail(r, n,
                            "unknown manipulator \"%.*s\" (NO_MANIP, NO_ENCODE, NO_DECODE, NO_QUEUE, LOOPBACK, "
                            "ON_DEMAND, TCP_SHARE_IN)",
                            (int)n->vlen, n->val);
            manip |= (unsigned)bit;
            if (bit == KELP_ACOMMS_MANIP_TCP_SHARE_IN) warn(r, n, "TCP_SHARE_IN: tcp sharing is not implemented");
        } else {
            return fail(r, n, "unknown field in message_file");
        }
    }
    if (!path[0]) return fail(r, b, "message_file without path (required)");
    return add_file(r, b, path, manip);
}

static int read_key(rd *r, int idx, kelp_queue_key *key, bool *has_id)
{
    int rc;
    long long v = 0;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "type")) {
            static const char *const N[] = { "QUEUE_DCCL", "QUEUE_CCL" };
            static const int V[] = { KELP_QUEUE_DCCL, KELP_QUEUE_CCL };
            int t = 0;
            if ((rc = get_enum(r, n, N, V, 2, &t))) return rc;
            key->type = (uint8_t)t;
        } else if (is(n, "id")) {
            if ((rc = get_long(r, n, 0, 512, &v))) return rc;
            key->id = (uint32_t)v;
            *has_id = true;
        } else {
            return fail(r, n, "unknown field in key");
        }
    }
    return KELP_OK;
}

static int read_queue(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    const kelp_mission_node *b = node(r, idx);
    if (c->nccl >= KELP_ACOMMS_MAX_CCL) return fail(r, b, "too many queues (max %d)", KELP_ACOMMS_MAX_CCL);
    kelp_acomms_ccl_queue *q = &c->ccl[c->nccl];
    memset(q, 0, sizeof *q);
    kelp_queue_cfg_default(&q->cfg, KELP_QUEUE_DCCL, 0);
    bool has_id = false, has_key = false;
    int rc;
    long long v = 0;
    double d;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "ack")) {
            if ((rc = get_bool(r, n, &q->cfg.ack))) return rc;
        } else if (is(n, "blackout_time")) {
            if ((rc = get_long(r, n, 0, 4294967295LL, &v))) return rc;
            q->cfg.blackout_time = (uint32_t)v;
        } else if (is(n, "max_queue")) {
            if ((rc = get_long(r, n, 0, 4294967295LL, &v))) return rc;
            q->cfg.max_queue = (uint32_t)v;
        } else if (is(n, "newest_first")) {
            if ((rc = get_bool(r, n, &q->cfg.newest_first))) return rc;
        } else if (is(n, "value_base")) {
            if ((rc = get_double(r, n, &d))) return rc;
            q->cfg.value_base = d;
        } else if (is(n, "ttl")) {
            if ((rc = get_long(r, n, 0, 4294967295LL, &v))) return rc;
            q->cfg.ttl = (uint32_t)v;
        } else if (is(n, "key")) {
            if ((rc = need_block(r, n)) || (rc = read_key(r, ch_i, &q->cfg.key, &has_id))) return rc;
            has_key = true;
        } else if (is(n, "name")) {
            if ((rc = get_str(r, n, q->name, sizeof q->name))) return rc;
        } else if (is(n, "in_pubsub_var")) {
            if ((rc = get_str(r, n, q->in_var, sizeof q->in_var))) return rc;
        } else if (is(n, "out_pubsub_var")) {
            if ((rc = get_str(r, n, q->out_var, sizeof q->out_var))) return rc;
        } else {
            return fail(r, n, "unknown field in queue");
        }
    }
    if (!has_key || !has_id) return fail(r, b, "queue without key { id } (required)");
    if (!q->name[0]) return fail(r, b, "queue without name (required)");
    if (q->cfg.key.type == KELP_QUEUE_DCCL)
        return fail(r, b, "queue { } is for CCL queues (key { type: QUEUE_CCL }); DCCL queues come from <queuing>");
    if (q->cfg.key.id > 255) return fail(r, b, "a CCL queue id is the first byte of the message (0..255)");
    if (q->cfg.key.id == 32) warn(r, b, "CCL id 32 (0x20) is DCCL's: this queue never receives");
    for (size_t i = 0; i < c->nccl; i++)
        if (c->ccl[i].cfg.key.id == q->cfg.key.id) return fail(r, b, "duplicate CCL queue id %u", q->cfg.key.id);
    c->nccl++;
    return KELP_OK;
}

static int read_queue_cfg(rd *r, int idx)
{
    int rc;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "modem_id")) {
            if ((rc = read_modem_id(r, n))) return rc;
        } else if (is(n, "message_file")) {
            if ((rc = need_block(r, n)) || (rc = read_message_file(r, ch_i))) return rc;
        } else if (is(n, "queue")) {
            if ((rc = need_block(r, n)) || (rc = read_queue(r, ch_i))) return rc;
        } else {
            return fail(r, n, "unknown field in queue_cfg");
        }
    }
    return KELP_OK;
}

static int read_dccl_cfg(rd *r, int idx)
{
    kelp_acomms_config *c = r->c;
    int rc;
    FOR_CHILDREN(r, idx, ch)
    {
        const kelp_mission_node *n = node(r, ch_i);
        if (is(n, "modem_id")) {
            if ((rc = read_modem_id(r, n))) return rc;
        } else if (is(n, "message_file")) {
            if ((rc = need_block(r, n)) || (rc = read_message_file(r, ch_i))) return rc;
        } else if (is(n, "crypto_passphrase") || is(n, "crypto_password")) {
            if ((rc = get_str(r, n, c->crypto_passphrase, sizeof c->crypto_passphrase))) return rc;
            c->has_passphrase = true;
        } else {
            return fail(r, n, "unknown field in dccl_cfg");
        }
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ top level */

void kelp_acomms_config_default(kelp_acomms_config *c)
{
    memset(c, 0, sizeof *c);
    c->log = true;
    snprintf(c->log_path, sizeof c->log_path, "./");
    c->app_tick = 10;
    c->comm_tick = 10;
    c->verbosity = KELP_ACOMMS_VERBOSITY_VERBOSE;
    c->driver_type = KELP_ACOMMS_DRIVER_NONE;
    c->connection = KELP_ACOMMS_CONN_SERIAL;
    snprintf(c->line_delimiter, sizeof c->line_delimiter, "\r\n");
    c->serial_baud = 19200;
    c->mac_type = KELP_MAC_NONE;
    c->mac_rate = 0;
    c->mac_slot_seconds = 15;
    c->mac_expire_cycles = 30;
    c->tcp_share_port = 11000;
}

static const kelp_mission_node *global(const kelp_mission *m, const char *key)
{
    int i = kelp_mission_next(m, -1, -1, key);
    return i >= 0 ? &m->nodes[i] : NULL;
}

int kelp_acomms_config_read(const struct kelp_mission *m, int block, const char *base_dir, kelp_acomms_config *c,
                            kelp_diag *d, char *warnbuf, size_t warncap)
{
    return kelp_acomms_config_read_extra(m, block, base_dir, c, d, warnbuf, warncap, NULL, NULL);
}

int kelp_acomms_config_read_extra(const struct kelp_mission *m, int block, const char *base_dir, kelp_acomms_config *c,
                                  kelp_diag *d, char *warnbuf, size_t warncap,
                                  kelp_acomms_config_extra_fn extra, void *extra_ctx)
{
    rd r = { m, c, d, warnbuf, warncap, base_dir, extra, extra_ctx, 0 };
    if (warnbuf && warncap) warnbuf[0] = '\0';
    if (!m || !c) return kelp_fail(d, KELP_ERR_ARG, "no mission or no configuration");
    kelp_acomms_config_default(c);
    if (block < 0) return fail(&r, NULL, "no pAcommsHandler configuration block");
    bool has_log = false, has_log_path = false, has_lookup = false;
    int rc;
    long long v = 0;
    const kelp_mission_node *modem_id_node = NULL, *driver_node = NULL;
    /* modem_id first, so sub-block modem_ids can be compared with it */
    FOR_CHILDREN(&r, block, pre)
    {
        const kelp_mission_node *n = node(&r, pre_i);
        if (n->kind == KELP_MN_FIELD && is(n, "modem_id")) {
            if ((rc = get_long(&r, n, 0, 31, &v))) return rc;
            c->modem_id = (int)v;
            modem_id_node = n;
        }
    }
    FOR_CHILDREN(&r, block, ch)
    {
        const kelp_mission_node *n = node(&r, ch_i);
        if (n->kind == KELP_MN_PARAM || n->kind == KELP_MN_BLOCK) continue; /* MOOS-style: the app runner's */
        if (is(n, "common")) {
            if ((rc = need_block(&r, n))) return rc;
            int li = kelp_mission_next(m, ch_i, -1, "log");
            int lpi = kelp_mission_next(m, ch_i, -1, "log_path");
            if (li >= 0) has_log = true;
            if (lpi >= 0) has_log_path = true;
            if ((rc = read_common(&r, ch_i))) return rc;
        } else if (is(n, "modem_id")) {
            /* read above */
        } else if (is(n, "driver_type")) {
            static const char *const N[] = { "DRIVER_NONE", "DRIVER_WHOI_MICROMODEM", "DRIVER_ABC_EXAMPLE_MODEM" };
            static const int V[] = { KELP_ACOMMS_DRIVER_NONE, KELP_ACOMMS_DRIVER_WHOI_MICROMODEM, 99 };
            int t = 0;
            if ((rc = get_enum(&r, n, N, V, 3, &t))) return rc;
            if (t == 99) return fail(&r, n, "DRIVER_ABC_EXAMPLE_MODEM (Goby's toy modem) is not provided by kelp");
            c->driver_type = (kelp_acomms_driver_type)t;
            driver_node = n;
        } else if (is(n, "driver_cfg")) {
            if ((rc = need_block(&r, n)) || (rc = read_driver(&r, ch_i))) return rc;
        } else if (is(n, "mac_cfg")) {
            if ((rc = need_block(&r, n)) || (rc = read_mac(&r, ch_i))) return rc;
        } else if (is(n, "queue_cfg")) {
            if ((rc = need_block(&r, n)) || (rc = read_queue_cfg(&r, ch_i))) return rc;
        } else if (is(n, "dccl_cfg")) {
            if ((rc = need_block(&r, n)) || (rc = read_dccl_cfg(&r, ch_i))) return rc;
        } else if (is(n, "modem_id_lookup_path")) {
            if ((rc = get_str(&r, n, c->modem_id_lookup_path, sizeof c->modem_id_lookup_path))) return rc;
            has_lookup = true;
        } else if (is(n, "tcp_share_enable")) {
            if ((rc = get_bool(&r, n, &c->tcp_share_enable))) return rc;
            if (c->tcp_share_enable) warn(&r, n, "tcp_share_enable: tcp sharing (experimental in Goby) is not implemented");
        } else if (is(n, "tcp_share_port")) {
            if ((rc = get_long(&r, n, 0, 65535, &v))) return rc;
            c->tcp_share_port = (unsigned)v;
        } else if (is(n, "tcp_share_to_ip")) {
            if (c->n_tcp_share >= 4) return fail(&r, n, "too many tcp_share_to_ip (max 4)");
            if ((rc = get_str(&r, n, c->tcp_share_to_ip[c->n_tcp_share], sizeof c->tcp_share_to_ip[0]))) return rc;
            c->n_tcp_share++;
        } else {
            kelp_diag xd; /* the extra reader's reason, put into this line's message */
            kelp_diag_clear(&xd);
            int x = r.extra ? r.extra(r.extra_ctx, n, &xd) : 0;
            if (x <= 0) return fail(&r, n, "%s", x < 0 ? kelp_diag_text(&xd) : "unknown field");
        }
    }
    /* global fallbacks */
    const kelp_mission_node *g;
    if (!c->community[0] && (g = global(m, "Community")) && kelp_mission_copy(g, c->community, sizeof c->community)) {
        return fail(&r, g, "Community too long");
    }
    if (!c->has_lat_origin && (g = global(m, "LatOrigin"))) {
        if (kelp_mission_double(g, &c->lat_origin) != KELP_OK) return fail(&r, g, "LatOrigin is not a number");
        c->has_lat_origin = true;
    }
    if (!c->has_lon_origin && (g = global(m, "LongOrigin"))) {
        if (kelp_mission_double(g, &c->lon_origin) != KELP_OK) return fail(&r, g, "LongOrigin is not a number");
        c->has_lon_origin = true;
    }
    if (!has_log && (g = global(m, "log"))) {
        if (kelp_mission_bool(g, &c->log) != KELP_OK) return fail(&r, g, "log must be true or false");
    }
    if (!has_log_path && (g = global(m, "log_path")) && kelp_mission_copy(g, c->log_path, sizeof c->log_path))
        return fail(&r, g, "log_path too long");
    if (!has_lookup && (g = global(m, "modem_id_lookup_path")) &&
        kelp_mission_copy(g, c->modem_id_lookup_path, sizeof c->modem_id_lookup_path))
        return fail(&r, g, "modem_id_lookup_path too long");
    if (c->modem_id_lookup_path[0] && c->modem_id_lookup_path[0] != '/' && base_dir && base_dir[0] &&
        access(c->modem_id_lookup_path, R_OK) != 0) {
        char full[KELP_ACOMMS_MAX_PATH];
        int w = snprintf(full, sizeof full, "%s/%s", base_dir, c->modem_id_lookup_path);
        if (w > 0 && (size_t)w < sizeof full) snprintf(c->modem_id_lookup_path, sizeof c->modem_id_lookup_path, "%s", full);
    }
    if (!modem_id_node && r.extra && r.dccl_modem_id > 0) {
        c->modem_id = r.dccl_modem_id;
    } else if (!modem_id_node) {
        long long gv;
        if ((g = global(m, "modem_id")) && kelp_util_parse_llong(g->val, g->vlen, &gv) == KELP_OK && gv >= 1 && gv <= 31) {
            c->modem_id = (int)gv;
            warn(&r, g, "modem_id taken from the global modem_id = %lld (Goby 1.1 requires it in the block)", gv);
        } else {
            return fail(&r, node(&r, block), "modem_id (required) missing");
        }
    }
    if (c->modem_id == 0) return fail(&r, modem_id_node, "modem_id 0 is reserved for broadcast (use 1..31)");
    /* driver checks */
    if (c->driver_type == KELP_ACOMMS_DRIVER_WHOI_MICROMODEM) {
        if (c->connection == KELP_ACOMMS_CONN_SERIAL && !c->serial_port[0])
            return fail(&r, driver_node, "CONNECTION_SERIAL needs driver_cfg { serial_port: \"...\" }");
        if (c->connection == KELP_ACOMMS_CONN_TCP_AS_CLIENT && (!c->tcp_server[0] || !c->tcp_port))
            return fail(&r, driver_node, "CONNECTION_TCP_AS_CLIENT needs driver_cfg { tcp_server tcp_port }");
        if (c->connection == KELP_ACOMMS_CONN_TCP_AS_SERVER && !c->tcp_port)
            return fail(&r, driver_node, "CONNECTION_TCP_AS_SERVER needs driver_cfg { tcp_port }");
        if (c->connection == KELP_ACOMMS_CONN_DUAL_UDP_BROADCAST)
            return fail(&r, driver_node, "CONNECTION_DUAL_UDP_BROADCAST is unimplemented (as in Goby 1.1)");
    }
    if ((c->mac_type == KELP_MAC_FIXED_DECENTRALIZED || c->mac_type == KELP_MAC_POLLED) && c->nslots == 0)
        warn(&r, NULL, "mac_cfg: a FIXED/POLLED MAC without slots never transmits");
    if (c->mac_type == KELP_MAC_AUTO_DECENTRALIZED && c->nslots)
        warn(&r, NULL, "mac_cfg: slots are ignored by MAC_AUTO_DECENTRALIZED");
    return KELP_OK;
}

void kelp_acomms_config_node(const kelp_acomms_config *c, kelp_acomms_node_cfg *out)
{
    kelp_acomms_node_cfg_default(out);
    out->modem_id = c->modem_id;
    out->driver = c->driver_type;
    out->mm.modem_id = c->modem_id;
    out->mm.reset_nvram = c->reset_nvram;
    for (size_t i = 0; i < c->n_nvram && i < KELP_MAX_MM_NVRAM; i++) out->mm.nvram_cfg[i] = c->nvram[i];
    out->mm.n_nvram = c->n_nvram;
    out->mm.hydroid_gateway_id = c->hydroid_gateway_id;
    /* Goby's MM driver reads with "\r" unless the field is set; the delimiter's first char */
    out->mm.line_delimiter = c->line_delimiter[0] == '\r' ? '\r' : c->line_delimiter[0];
    out->mac.type = c->mac_type;
    out->mac.modem_id = c->modem_id;
    out->mac.rate = c->mac_rate;
    out->mac.slot_seconds = c->mac_slot_seconds;
    out->mac.expire_cycles = c->mac_expire_cycles;
    out->mac.slots = c->slots;
    out->mac.nslots = c->nslots;
    out->loopback_channel = c->driver_type == KELP_ACOMMS_DRIVER_NONE;
}

kelp_acomms_dccl *kelp_acomms_dccl_open_config(const kelp_acomms_config *cfg, bool plaintext, kelp_diag *d)
{
    const char *files[KELP_ACOMMS_MAX_FILES];
    unsigned manips[KELP_ACOMMS_MAX_FILES];
    for (size_t i = 0; i < cfg->nfiles; i++) {
        files[i] = cfg->files[i].path;
        manips[i] = cfg->files[i].manip;
    }
    kelp_acomms_dccl_cfg dc;
    memset(&dc, 0, sizeof dc);
    dc.modem_id = (unsigned)cfg->modem_id;
    dc.passphrase = cfg->has_passphrase ? cfg->crypto_passphrase : NULL;
    dc.plaintext = plaintext;
    dc.lookup_path = cfg->modem_id_lookup_path;
    dc.have_origin = cfg->has_lat_origin && cfg->has_lon_origin;
    dc.lat_origin = cfg->lat_origin;
    dc.lon_origin = cfg->lon_origin;
    dc.files = files;
    dc.manips = manips;
    dc.nfiles = cfg->nfiles;
    return kelp_acomms_dccl_open(&dc, d);
}
