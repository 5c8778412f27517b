/* kelp bus: registrations, dispatch, the retained-value cache and the sync protocol.
 *
 * Why a cache in every client: MOOS gives a registrant the current value of a variable
 * at registration. kelp has no MOOSDB, so each client keeps the latest value of every
 * variable it wrote or received (bounded by storage) and answers sync requests from
 * late registrants. A requester takes a sync reply only when it is newer than what it
 * already delivered for that variable, so several answers (or a live write racing the
 * replay) deliver each value at most once.
 */
#include <math.h>
#include <string.h>
#include <kelp/bus.h>
#include <kelp/util.h>
#include "bus_int.h"

static bool has_wildcard(const char *s)
{
    return strchr(s, '*') != NULL || strchr(s, '?') != NULL;
}

/* fingerprint + time + 3 names + kind + dval + sval + nbytes + bval + flags */
#define VAR_MAX_BYTES (8 + 8 + 3 * (4 + KELP_MAX_NAME) + 1 + 8 + (4 + KELP_MAX_SVAL + 1) + 4 + KELP_MAX_SVAL + 1)
#define REQ_MAX_BYTES (8 + 8 + 3 * (4 + KELP_MAX_NAME) + 2 + KELP_MAX_SYNC_PATTERNS * (4 + KELP_MAX_NAME))
_Static_assert(VAR_MAX_BYTES >= REQ_MAX_BYTES, "a sync request must fit the var scratch buffer");

size_t kelp_bus_scratch_size(void)
{
    return VAR_MAX_BYTES;
}

int kelp_bus_init(kelp_bus *b, const char *app, const char *community, const char *reply_channel,
                  const kelp_bus_transport *tr, const kelp_bus_storage *st, kelp_bus_handler handler,
                  void *user)
{
    if (!b || !app || !community || !reply_channel || !tr || !tr->publish || !tr->subscribe || !st)
        return KELP_ERR_ARG;
    if (!st->rx || !st->scratch || st->scratch_cap < kelp_bus_scratch_size()) return KELP_ERR_NOSPACE;
    if ((st->nsubs && !st->subs) || (st->ncache && !st->cache)) return KELP_ERR_ARG;
    memset(b, 0, sizeof *b);
    int rc;
    if ((rc = kelp_bus_name_set(b->app, app)) < 0) return rc;
    if ((rc = kelp_bus_name_set(b->community, community)) < 0) return rc;
    if ((rc = kelp_bus_name_set(b->reply_channel, reply_channel)) < 0) return rc;
    b->tr = *tr;
    b->st = *st;
    b->handler = handler;
    b->user = user;
    kelp_bus_limits_default(&b->lim);
    b->all_tokens = b->lim.sync_burst_all;
    /* Sync requests and our replies: every client answers requests from others. */
    if ((rc = tr->subscribe(tr->ctx, KELP_BUS_SYNC_CHANNEL)) < 0) return rc;
    if ((rc = tr->subscribe(tr->ctx, b->reply_channel)) < 0) return rc;
    return KELP_OK;
}

#if KELP_BUS_CACHE_HASH > 0
static size_t name_hash(const char *s)
{
    return (size_t)kelp_util_hash(s, strlen(s)) & (KELP_BUS_CACHE_HASH - 1);
}

/* the index covers the cache when it holds at most half as many variables as it has slots
 * (so a probe always ends at an empty slot); a larger caller cache is searched linearly */
static bool cache_hashed(const kelp_bus *b)
{
    return b->st.ncache <= KELP_BUS_CACHE_HASH / 2;
}
#endif

static kelp_var *cache_find(const kelp_bus *b, const char *name)
{
#if KELP_BUS_CACHE_HASH > 0
    if (cache_hashed(b)) {
        for (size_t p = name_hash(name);; p = (p + 1) & (KELP_BUS_CACHE_HASH - 1)) {
            uint16_t k = b->cache_hash[p];
            if (k == 0) return NULL;
            if (strcmp(b->st.cache[k - 1].name, name) == 0) return &b->st.cache[k - 1];
        }
    }
#endif
    for (size_t i = 0; i < b->ncache_used; i++)
        if (strcmp(b->st.cache[i].name, name) == 0) return &b->st.cache[i];
    return NULL;
}

/* a new cache slot for `name` (not in the cache), or NULL when the cache is full */
static kelp_var *cache_add(kelp_bus *b, const char *name)
{
    if (b->ncache_used >= b->st.ncache) return NULL;
#if KELP_BUS_CACHE_HASH > 0
    if (cache_hashed(b)) {
        size_t p = name_hash(name);
        while (b->cache_hash[p]) p = (p + 1) & (KELP_BUS_CACHE_HASH - 1);
        b->cache_hash[p] = (uint16_t)(b->ncache_used + 1);
    }
#else
    (void)name;
#endif
    return &b->st.cache[b->ncache_used++];
}

const kelp_var *kelp_bus_cached(const kelp_bus *b, const char *name)
{
    return b ? cache_find(b, name) : NULL;
}

static void cache_put(kelp_bus *b, const kelp_var *v)
{
    kelp_var *slot = cache_find(b, v->name);
    if (!slot) {
        if (!(slot = cache_add(b, v->name))) {
            b->stats.cache_full++;
            return;
        }
    } else if (slot->time > v->time) {
        return; /* keep the newer one */
    }
    /* copy only the used part of the value */
    memcpy(slot, v, offsetof(kelp_var, sval));
    memcpy(slot->sval, v->sval, v->slen);
    slot->sval[v->slen] = 0;
    slot->flags = (uint8_t)(v->flags & ~KELP_VAR_FLAG_SYNC);
}

static int send_var(kelp_bus *b, const kelp_var *v, const char *channel)
{
    size_t n = 0;
    int rc = kelp_var_encode(v, b->st.scratch, b->st.scratch_cap, &n);
    if (rc < 0) return rc;
    rc = b->tr.publish(b->tr.ctx, channel, b->st.scratch, n);
    if (rc < 0) return rc;
    b->stats.published++;
    return KELP_OK;
}

int kelp_bus_forward(kelp_bus *b, const kelp_var *v)
{
    if (!b || !v || v->name[0] == 0) return KELP_ERR_ARG;
    cache_put(b, v);
    return send_var(b, v, v->name);
}

/* The MOOSDB fixes a variable's type at its first write and refuses a write of another
 * type (a double to a variable that holds strings, or the reverse). There is no DB here: each
 * client applies the rule with the type of the value it retains for that name. */
static bool type_clash(const kelp_bus *b, const char *name, kelp_var_kind kind)
{
    const kelp_var *have = cache_find(b, name);
    return have && have->kind != kind;
}

static int notify(kelp_bus *b, const char *name, kelp_var_kind kind, double d, const char *data,
                  size_t len, const char *aux, kelp_time now)
{
    if (!b || !name || !*name) return KELP_ERR_ARG;
    if (strlen(name) >= KELP_MAX_NAME) return KELP_ERR_RANGE;
    if (len > KELP_MAX_SVAL) return KELP_ERR_RANGE;
    if (!aux) aux = "";
    if (strlen(aux) >= KELP_MAX_NAME) return KELP_ERR_RANGE;
    if (type_clash(b, name, kind)) {
        /* the MOOSDB would refuse it: nobody receives it (MOOS's Notify still says yes) */
        b->stats.type_refused++;
        return KELP_OK;
    }
    size_t n = 0;
    int rc = kelp_var_encode_parts(now, name, b->app, aux, b->community, kind, d, data, len, 0,
                                   b->st.scratch, b->st.scratch_cap, &n);
    if (rc < 0) return rc;
    /* retain it: we answer late registrants for what we wrote */
    kelp_var *slot = cache_find(b, name);
    if (!slot) slot = cache_add(b, name);
    if (slot) {
        memset(slot, 0, offsetof(kelp_var, sval));
        memcpy(slot->name, name, strlen(name) + 1);
        memcpy(slot->source, b->app, sizeof b->app);
        memcpy(slot->source_aux, aux, strlen(aux) + 1);
        memcpy(slot->community, b->community, sizeof b->community);
        slot->time = now;
        slot->kind = kind;
        slot->dval = kind == KELP_VAR_DOUBLE ? d : 0.0;
        slot->slen = len;
        if (len) memcpy(slot->sval, data, len);
        slot->sval[len] = 0;
    } else {
        b->stats.cache_full++;
    }
    rc = b->tr.publish(b->tr.ctx, name, b->st.scratch, n);
    if (rc < 0) return rc;
    b->stats.published++;
    return KELP_OK;
}

int kelp_bus_notify_double(kelp_bus *b, const char *name, double value, kelp_time now)
{
    return notify(b, name, KELP_VAR_DOUBLE, value, NULL, 0, NULL, now);
}

int kelp_bus_notify_string(kelp_bus *b, const char *name, const char *value, kelp_time now)
{
    if (!value) return KELP_ERR_ARG;
    return notify(b, name, KELP_VAR_STRING, 0.0, value, strlen(value), NULL, now);
}

int kelp_bus_notify_binary(kelp_bus *b, const char *name, const void *data, size_t len, kelp_time now)
{
    if (!data && len) return KELP_ERR_ARG;
    return notify(b, name, KELP_VAR_BINARY, 0.0, data, len, NULL, now);
}

int kelp_bus_notify_aux(kelp_bus *b, const char *name, bool is_string, const char *sval, double dval,
                        const char *aux, kelp_time now)
{
    if (is_string && !sval) return KELP_ERR_ARG;
    return is_string ? notify(b, name, KELP_VAR_STRING, 0.0, sval, strlen(sval), aux, now)
                     : notify(b, name, KELP_VAR_DOUBLE, dval, NULL, 0, aux, now);
}

static int send_sync_request(kelp_bus *b, const char *pattern, kelp_time now)
{
    size_t n = 0;
    int rc = kelp_sync_req_encode_one(now, b->app, b->community, b->reply_channel, pattern, b->st.scratch,
                                      b->st.scratch_cap, &n);
    if (rc < 0) return rc;
    return b->tr.publish(b->tr.ctx, KELP_BUS_SYNC_CHANNEL, b->st.scratch, n);
}

int kelp_bus_register(kelp_bus *b, const char *pattern, double min_interval, kelp_time now)
{
    if (!b || !pattern || !*pattern || min_interval < 0) return KELP_ERR_ARG;
    if (strlen(pattern) >= KELP_MAX_NAME) return KELP_ERR_RANGE;
    for (size_t i = 0; i < b->nsubs_used; i++) {
        if (strcmp(b->st.subs[i].pattern, pattern) == 0) {
            b->st.subs[i].min_interval = min_interval;
            return KELP_OK;
        }
    }
    if (b->nsubs_used >= b->st.nsubs) return KELP_ERR_NOSPACE;
    kelp_bus_sub *s = &b->st.subs[b->nsubs_used];
    memset(s, 0, sizeof *s);
    memcpy(s->pattern, pattern, strlen(pattern) + 1);
    s->wildcard = has_wildcard(pattern);
    s->min_interval = min_interval;
    s->last_delivered = -1e300;
    int rc = b->tr.subscribe(b->tr.ctx, pattern);
    if (rc < 0) return rc;
    b->nsubs_used++;
    /* Values we already hold (we wrote them, or another registration brought them) are
     * delivered now; others come from the peers' answers to the sync request. */
    for (size_t i = 0; i < b->ncache_used; i++) {
        const kelp_var *c = &b->st.cache[i];
        if (kelp_bus_match(pattern, c->name) && b->handler) {
            b->stats.delivered++;
            b->handler(c, b->user);
        }
    }
    return send_sync_request(b, pattern, now);
}

int kelp_bus_retain_all(kelp_bus *b, kelp_time now)
{
    (void)now;
    if (!b) return KELP_ERR_ARG;
    if (b->nsubs_used >= b->st.nsubs) return KELP_ERR_NOSPACE;
    kelp_bus_sub *s = &b->st.subs[b->nsubs_used];
    memset(s, 0, sizeof *s);
    s->pattern[0] = '*';
    s->wildcard = true;
    s->last_delivered = -1e300;
    int rc = b->tr.subscribe(b->tr.ctx, "*");
    if (rc < 0) return rc;
    b->nsubs_used++;
    return KELP_OK;
}

static bool exact_sub(const kelp_bus *b, const char *channel)
{
    for (size_t i = 0; i < b->nsubs_used; i++)
        if (!b->st.subs[i].wildcard && strcmp(b->st.subs[i].pattern, channel) == 0) return true;
    return false;
}

/* Which subscription (if any) wants this name; honour its rate limit. */
static bool wanted(kelp_bus *b, const kelp_var *v, bool *rate_limited)
{
    bool match = false;
    *rate_limited = false;
    for (size_t i = 0; i < b->nsubs_used; i++) {
        kelp_bus_sub *s = &b->st.subs[i];
        if (s->wildcard ? !kelp_bus_match(s->pattern, v->name) : strcmp(s->pattern, v->name) != 0)
            continue;
        /* the time step rule: a write more than an interval older than the last delivered one
         * means the writer's clock stepped back; the interval restarts from it (no stall) */
        if (v->time < s->last_delivered - s->min_interval) s->last_delivered = -1e300;
        if (s->min_interval > 0 && v->time - s->last_delivered < s->min_interval) {
            *rate_limited = true;
            continue;
        }
        s->last_delivered = v->time;
        match = true;
    }
    return match;
}

void kelp_bus_limits_default(kelp_bus_limits *l)
{
    l->time_margin = 0;
    l->sync_burst = KELP_BUS_SYNC_BURST;
    l->sync_rate = KELP_BUS_SYNC_RATE;
    l->sync_burst_all = KELP_BUS_SYNC_BURST_ALL;
    l->sync_rate_all = KELP_BUS_SYNC_RATE_ALL;
}

int kelp_bus_set_limits(kelp_bus *b, const kelp_bus_limits *l)
{
    if (!b || !l) return KELP_ERR_ARG;
    const double v[5] = { l->time_margin, l->sync_burst, l->sync_rate, l->sync_burst_all, l->sync_rate_all };
    for (int i = 0; i < 5; i++)
        if (!isfinite(v[i]) || v[i] < 0) return KELP_ERR_ARG;
    b->lim = *l;
    if (b->all_tokens > l->sync_burst_all) b->all_tokens = l->sync_burst_all;
    return KELP_OK;
}

void kelp_bus_set_bridge(kelp_bus *b, bool bridge)
{
    if (b) b->bridge = bridge;
}

int kelp_bus_reply_channel(const char *app, uint32_t nonce, char out[KELP_MAX_NAME])
{
    static const char hex[] = "0123456789abcdef";
    static const char pre[] = KELP_BUS_SYNC_REPLY_PREFIX;
    if (!app || !*app || !out) return KELP_ERR_ARG;
    size_t al = 0, o = sizeof pre - 1;
    while (al < KELP_BUS_REPLY_APP_LEN && app[al]) al++;
    _Static_assert(sizeof pre - 1 + KELP_BUS_REPLY_APP_LEN + 1 + 8 < KELP_MAX_NAME, "reply channel fits a name");
    memcpy(out, pre, o);
    memcpy(out + o, app, al);
    o += al;
    out[o++] = '_';
    for (int i = 7; i >= 0; i--) out[o++] = hex[(nonce >> (4 * i)) & 0xf];
    out[o] = 0;
    return KELP_OK;
}

/* A reply channel the requester may use: its own, "KELP_SYNC_<name, first 24 bytes>" with
 * an optional "_<1..8 hex digits>", so replies cannot be aimed at any other channel. */
static bool reply_ok(const char *requester, const char *reply)
{
    static const char pre[] = KELP_BUS_SYNC_REPLY_PREFIX;
    size_t pl = sizeof pre - 1, al = 0;
    while (al < KELP_BUS_REPLY_APP_LEN && requester[al]) al++;
    if (al == 0 || strncmp(reply, pre, pl) != 0 || strncmp(reply + pl, requester, al) != 0) return false;
    const char *t = reply + pl + al;
    if (*t == 0) return true;
    if (*t++ != '_') return false;
    size_t h = 0;
    for (; *t; t++, h++)
        if (!((*t >= '0' && *t <= '9') || (*t >= 'a' && *t <= 'f') || (*t >= 'A' && *t <= 'F'))) return false;
    return h >= 1 && h <= 8;
}

static void refill(double *tokens, double *last, double burst, double rate, kelp_time now)
{
    if (isfinite(now) && now > *last) {
        *tokens += (now - *last) * rate;
        if (*tokens > burst) *tokens = burst;
    }
    if (isfinite(now)) *last = now;
}

/* The requester's budget: its slot in the table, or the least recently used slot. */
static kelp_bus_sync_peer *peer_for(kelp_bus *b, const char *reply, kelp_time now)
{
    kelp_bus_sync_peer *lru = &b->peers[0];
    for (size_t i = 0; i < KELP_BUS_SYNC_PEERS; i++) {
        kelp_bus_sync_peer *p = &b->peers[i];
        if (p->reply[0] && strcmp(p->reply, reply) == 0) return p;
        if (!p->reply[0] || (lru->reply[0] && p->last < lru->last)) lru = p;
    }
    memcpy(lru->reply, reply, strlen(reply) + 1);
    lru->tokens = b->lim.sync_burst;
    lru->last = isfinite(now) ? now : 0;
    return lru;
}

static void answer_sync(kelp_bus *b, const kelp_sync_req *q, kelp_time now)
{
    if (strcmp(q->reply_channel, b->reply_channel) == 0) return; /* our own request */
    if (!reply_ok(q->requester, q->reply_channel)) {
        b->stats.sync_bad_reply++;
        return;
    }
    kelp_bus_sync_peer *p = peer_for(b, q->reply_channel, now);
    refill(&p->tokens, &p->last, b->lim.sync_burst, b->lim.sync_rate, now);
    refill(&b->all_tokens, &b->all_last, b->lim.sync_burst_all, b->lim.sync_rate_all, now);
    for (size_t i = 0; i < b->ncache_used; i++) {
        kelp_var *c = &b->st.cache[i];
        for (uint16_t k = 0; k < q->npatterns; k++) {
            if (kelp_bus_match(q->patterns[k], c->name)) {
                if (p->tokens < 1 || b->all_tokens < 1) {
                    b->stats.sync_limited++;
                    break;
                }
                p->tokens -= 1;
                b->all_tokens -= 1;
                uint8_t keep = c->flags;
                c->flags |= KELP_VAR_FLAG_SYNC;
                if (send_var(b, c, q->reply_channel) == 0) b->stats.sync_sent++;
                c->flags = keep;
                break;
            }
        }
    }
}

/* Another community's traffic, unless a bridge of ours brought it or we are a bridge. */
static bool foreign(const kelp_bus *b, const char *community, uint8_t flags)
{
    return !b->bridge && !(flags & KELP_VAR_FLAG_BRIDGED) && strcmp(community, b->community) != 0;
}

int kelp_bus_receive(kelp_bus *b, const char *channel, const uint8_t *data, size_t len, kelp_time now)
{
    if (!b || !channel) return KELP_ERR_ARG;
    b->stats.received++;
    if (b->depth >= KELP_BUS_MAX_DEPTH) return KELP_ERR_STATE;
    int rc;
    if (strcmp(channel, KELP_BUS_SYNC_CHANNEL) == 0) {
        kelp_sync_req *q = &b->sync_rx;
        rc = kelp_bus_sync_req_decode(data, len, q);
        if (rc < 0) {
            b->stats.bad++;
            b->stats.last_bad_err = rc;
            return rc;
        }
        if (foreign(b, q->community, 0)) {
            b->stats.foreign_community++;
            return KELP_OK;
        }
        b->depth++;
        answer_sync(b, q, now);
        b->depth--;
        return KELP_OK;
    }
    bool is_sync = strcmp(channel, b->reply_channel) == 0;
    /* sync replies addressed to other clients are none of our business (a "*" retainer
     * sees them) */
    if (strcmp(channel, "LCM_SELF_TEST") == 0) return KELP_OK; /* liblcm's own start-up probe */
    if (!is_sync && strncmp(channel, KELP_BUS_SYNC_REPLY_PREFIX, sizeof KELP_BUS_SYNC_REPLY_PREFIX - 1) == 0)
        return KELP_OK;
    kelp_var *v = b->st.rx;
    rc = kelp_var_decode(data, len, v);
    if (rc == KELP_ERR_DEFMISMATCH && !exact_sub(b, channel)) {
        /* another LCM type on a channel only a wildcard reached (structured acomms types,
         * other programs' traffic): not ours to judge */
        b->stats.foreign++;
        return KELP_OK;
    }
    if (rc < 0) {
        b->stats.bad++;
        b->stats.last_bad_err = rc;
        return rc;
    }
    if (!is_sync && strcmp(channel, v->name) != 0) {
        /* a var must travel on the channel of its own name */
        b->stats.bad++;
        b->stats.last_bad_err = KELP_ERR_PARSE;
        return KELP_ERR_PARSE;
    }
    if (foreign(b, v->community, v->flags)) {
        b->stats.foreign_community++;
        return KELP_OK;
    }
    /* a poisoned time would win every later "newer than" comparison in every cache.  The time
     * step rule: "ahead" is judged against the newest `now` seen, so after our own clock steps
     * back the peers' writes (on the clock we had) are not refused for the length of the step */
    if (isfinite(now) && now > b->newest) b->newest = now;
    if (!isfinite(v->time) || (b->lim.time_margin > 0 && v->time > b->newest + b->lim.time_margin)) {
        b->stats.time_rejected++;
        return KELP_ERR_RANGE;
    }
    if (is_sync) {
        const kelp_var *have = cache_find(b, v->name);
        if (have && have->time >= v->time) {
            b->stats.sync_stale++;
            return KELP_OK;
        }
    }
    if (!is_sync && type_clash(b, v->name, v->kind)) {
        /* the MOOSDB refuses a write of another type than the variable's: nobody gets it */
        b->stats.type_refused++;
        return KELP_OK;
    }
    bool limited = false;
    bool want = wanted(b, v, &limited);
    if (limited && !want) b->stats.rate_limited++;
    /* retain what we see (wanted or answered for others) */
    if (want || is_sync) cache_put(b, v);
    if (!want) return KELP_OK;
    if (is_sync) b->stats.sync_delivered++;
    b->stats.delivered++;
    if (b->handler) {
        b->depth++;
        b->handler(v, b->user);
        b->depth--;
    }
    return KELP_OK;
}

const kelp_bus_stats *kelp_bus_get_stats(const kelp_bus *b)
{
    return b ? &b->stats : NULL;
}
