/* kelp: Goby 1.1 TDMA MAC (libamac mac_manager.cpp behaviour, goby-wire.md section 9). */
#include <kelp/mac.h>
#include <kelp/util.h>

#include <math.h>
#include <string.h>

#define US_PER_S 1000000LL
#define US_PER_DAY (86400LL * US_PER_S)
#define ENTROPY 5u

/* The slot clock runs in whole microseconds (as Goby's): a kelp_time is converted once, here. */
static int64_t mac_us(kelp_time t)
{
    return (int64_t)llround(t * 1e6);
}

static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0))) q--;
    return q;
}

void kelp_mac_cfg_default(kelp_mac_cfg *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->type = KELP_MAC_NONE;
    cfg->rate = 0;
    cfg->slot_seconds = 15;
    cfg->expire_cycles = 30;
}

void kelp_mac_slot_default(kelp_mac_slot *s, int src)
{
    memset(s, 0, sizeof *s);
    s->src = src;
    s->dest = -1;
    s->rate = 0;
    s->type = KELP_SLOT_DATA;
    s->slot_seconds = 15;
}

unsigned kelp_mac_cycle_length(const kelp_mac *mac)
{
    unsigned len = 0;
    for (size_t i = 0; i < mac->n; i++) len += mac->slot[i].slot_seconds;
    return len;
}

kelp_time kelp_mac_aligned_start(kelp_time now, unsigned cycle_seconds, unsigned long *k_out)
{
    if (cycle_seconds == 0) return -1;
    int64_t now_us = mac_us(now);
    int64_t day = floor_div(now_us, US_PER_DAY);
    int64_t midnight = day * US_PER_DAY;
    int64_t tod = (now_us - midnight) / US_PER_S; /* whole seconds since midnight */
    unsigned long k = (unsigned long)(tod / cycle_seconds) + 1;
    if (k_out) *k_out = k;
    return (kelp_time)(midnight + (int64_t)k * cycle_seconds * US_PER_S) / 1e6; /* whole seconds: exact */
}

kelp_time kelp_mac_next_slot_time(const kelp_mac *mac)
{
    return mac->running ? mac->next_slot : -1;
}

static int blank_index(const kelp_mac *mac)
{
    for (size_t i = 0; i < mac->n; i++)
        if (mac->slot[i].src == 0 && mac->slot[i].never_expires) return (int)i;
    return -1;
}

/* MACManager::position_blank (1.1): position counted from the cycle length in SECONDS, walked over
 * a circular std::list whose end sentinel is one more position. */
static void position_blank(kelp_mac *mac)
{
    int bi = blank_index(mac);
    if (bi < 0 || mac->n == 0) return;
    unsigned len = kelp_mac_cycle_length(mac);
    unsigned sum = 0;
    for (size_t i = 0; i < mac->n; i++) sum += (unsigned)mac->slot[i].src;
    unsigned blank_pos = len - ((mac->cycles_since_day_start % ENTROPY) == (sum % ENTROPY) ? 1u : 0u) - 1u;
    kelp_mac_slot blank = mac->slot[bi];
    memmove(&mac->slot[bi], &mac->slot[bi + 1], (mac->n - (size_t)bi - 1) * sizeof blank);
    mac->n--;
    size_t idx = (size_t)(blank_pos % (unsigned)(mac->n + 1));
    memmove(&mac->slot[idx + 1], &mac->slot[idx], (mac->n - idx) * sizeof blank);
    mac->slot[idx] = blank;
    mac->n++;
    mac->current = 0;
}

/* MACManager::process_cycle_size_change: re-align to the next cycle boundary */
static void cycle_size_change(kelp_mac *mac, kelp_time now)
{
    unsigned len = kelp_mac_cycle_length(mac);
    if (mac->n == 0 || len == 0) {
        /* Goby divides by zero here; kelp stops the timer instead */
        mac->running = false;
        mac->current = 0;
        return;
    }
    mac->next_slot = kelp_mac_aligned_start(now, len, &mac->cycles_since_day_start);
    if (mac->type == KELP_MAC_AUTO_DECENTRALIZED && mac->n > 1) position_blank(mac);
    mac->running = true;
}

static void sort_by_src(kelp_mac *mac)
{
    for (size_t i = 1; i < mac->n; i++) { /* stable insertion sort */
        kelp_mac_slot s = mac->slot[i];
        size_t j = i;
        while (j > 0 && mac->slot[j - 1].src > s.src) {
            mac->slot[j] = mac->slot[j - 1];
            j--;
        }
        mac->slot[j] = s;
    }
}

static int add_slot(kelp_mac *mac, const kelp_mac_slot *s, kelp_time now)
{
    if (mac->n >= KELP_MAX_MAC_SLOTS) {
        (void)kelp_fail(&mac->diag, KELP_ERR_NOSPACE, "mac: too many slots (KELP_MAX_MAC_SLOTS)");
        return KELP_ERR_NOSPACE;
    }
    mac->slot[mac->n++] = *s;
    mac->current = 0;
    cycle_size_change(mac, now);
    return KELP_OK;
}

int kelp_mac_add_slot(kelp_mac *mac, const kelp_mac_slot *s, kelp_time now)
{
    if (!mac || !s || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    if (mac->type == KELP_MAC_AUTO_DECENTRALIZED || mac->type == KELP_MAC_NONE) return KELP_ERR_STATE;
    kelp_mac_slot c = *s;
    c.never_expires = false;
    c.last_heard = 0;
    return add_slot(mac, &c, now);
}

static bool slot_eq(const kelp_mac_slot *a, const kelp_mac_slot *b)
{
    return a->src == b->src && a->dest == b->dest && a->rate == b->rate && a->type == b->type &&
           a->slot_seconds == b->slot_seconds;
}

int kelp_mac_remove_slot(kelp_mac *mac, const kelp_mac_slot *s, kelp_time now)
{
    if (!mac || !s || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    if (mac->type == KELP_MAC_AUTO_DECENTRALIZED || mac->type == KELP_MAC_NONE) return KELP_ERR_STATE;
    bool removed = false;
    for (size_t i = 0; i < mac->n; i++) {
        if (slot_eq(&mac->slot[i], s)) {
            memmove(&mac->slot[i], &mac->slot[i + 1], (mac->n - i - 1) * sizeof mac->slot[0]);
            mac->n--;
            removed = true;
            break;
        }
    }
    cycle_size_change(mac, now);
    if (removed) mac->current = 0;
    return removed ? KELP_OK : KELP_ERR_NOTFOUND;
}

void kelp_mac_clear(kelp_mac *mac)
{
    mac->n = 0;
    mac->current = 0;
    mac->running = false;
}

int kelp_mac_init(kelp_mac *mac, const kelp_mac_cfg *cfg, kelp_time now)
{
    if (!mac || !cfg || (cfg->nslots && !cfg->slots) || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    memset(mac, 0, sizeof *mac);
    mac->type = cfg->type;
    mac->modem_id = cfg->modem_id;
    mac->rate = cfg->rate;
    mac->slot_seconds = cfg->slot_seconds;
    mac->expire_cycles = cfg->expire_cycles;
    if (cfg->modem_id < 0) return KELP_ERR_ARG;
    switch (cfg->type) {
    case KELP_MAC_NONE:
        return KELP_OK;
    case KELP_MAC_AUTO_DECENTRALIZED: {
        if (cfg->slot_seconds == 0) return kelp_fail(&mac->diag, KELP_ERR_ARG, "mac: slot_seconds must be > 0");
        kelp_mac_slot s;
        kelp_mac_slot_default(&s, 0);
        s.rate = cfg->rate;
        s.slot_seconds = cfg->slot_seconds;
        s.never_expires = true;
        int rc = add_slot(mac, &s, now); /* the blank */
        if (rc) return rc;
        s.src = cfg->modem_id;
        rc = add_slot(mac, &s, now);     /* ourselves */
        if (rc) return rc;
        sort_by_src(mac);
        mac->next_slot = kelp_mac_aligned_start(now, kelp_mac_cycle_length(mac), &mac->cycles_since_day_start);
        position_blank(mac);
        mac->running = true;
        return KELP_OK;
    }
    case KELP_MAC_FIXED_DECENTRALIZED:
    case KELP_MAC_POLLED:
        for (size_t i = 0; i < cfg->nslots; i++) {
            int rc = kelp_mac_add_slot(mac, &cfg->slots[i], now);
            if (rc) return rc;
        }
        return KELP_OK;
    default:
        return KELP_ERR_ARG;
    }
}

/* expire ids not heard for cycle_length * expire_cycles seconds (own id and the blank never) */
static void expire_ids(kelp_mac *mac, kelp_time now)
{
    int64_t limit = mac_us(now) - (int64_t)kelp_mac_cycle_length(mac) * mac->expire_cycles * US_PER_S;
    bool reset = false;
    size_t i = 0;
    while (i < mac->n) {
        kelp_mac_slot *s = &mac->slot[i];
        if (s->last_heard > now) s->last_heard = now; /* heard "later": the clock stepped back */
        if (!s->never_expires && s->src != mac->modem_id && mac_us(s->last_heard) < limit) {
            memmove(&mac->slot[i], &mac->slot[i + 1], (mac->n - i - 1) * sizeof mac->slot[0]);
            mac->n--;
            if (mac->current > i) mac->current--;
            reset = true;
        } else {
            i++;
        }
    }
    if (reset) cycle_size_change(mac, now);
}

/* The time step rule (docs/ARCHITECTURE.md): the clock stepped when the slot that starts next
 * has ended before `now` (its whole time missed: a tick is never that late otherwise), or lies
 * further ahead than a cycle and the longest slot (the most a re-aligned cycle can be away). */
static bool clock_stepped(const kelp_mac *mac, int64_t now_us)
{
    unsigned longest = 1;
    for (size_t i = 0; i < mac->n; i++)
        if (mac->slot[i].slot_seconds > longest) longest = mac->slot[i].slot_seconds;
    unsigned own = mac->slot[mac->current].slot_seconds;
    int64_t next_us = mac_us(mac->next_slot);
    int64_t ahead_us = ((int64_t)kelp_mac_cycle_length(mac) + longest) * US_PER_S;
    return now_us >= next_us + (int64_t)(own ? own : 1u) * US_PER_S || next_us - now_us > ahead_us;
}

int kelp_mac_tick(kelp_mac *mac, kelp_time now, kelp_mac_action *act)
{
    if (!mac || !act) return KELP_ERR_ARG;
    memset(act, 0, sizeof *act);
    act->kind = KELP_MAC_ACT_NONE;
    if (!kelp_util_time_ok(now)) return KELP_ERR_ARG;
    if (!mac->running || mac->n == 0) return KELP_ERR_EMPTY;
    if (mac->current >= mac->n) mac->current = 0;
    if (clock_stepped(mac, mac_us(now))) {
        /* the time step rule: no burst of missed slots, no wait for a slot an hour away */
        mac->clock_steps++;
        mac->current = 0;
        cycle_size_change(mac, now);
        return KELP_ERR_EMPTY;
    }
    if (mac_us(now) < mac_us(mac->next_slot)) return KELP_ERR_EMPTY;
    const kelp_mac_slot s = mac->slot[mac->current];
    bool send;
    switch (mac->type) {
    case KELP_MAC_FIXED_DECENTRALIZED:
    case KELP_MAC_AUTO_DECENTRALIZED: send = (s.src == mac->modem_id); break;
    case KELP_MAC_POLLED: send = (s.src != 0); break;
    default: send = false; break;
    }
    act->slot_start = mac->next_slot;
    act->slot_index = (unsigned)mac->current;
    act->slot_type = s.type;
    if (send) {
        act->src = s.src;
        act->dest = s.dest;
        act->rate = s.rate;
        if (s.type == KELP_SLOT_DATA) {
            act->kind = KELP_MAC_ACT_TRANSMIT;
        } else {
            act->kind = KELP_MAC_ACT_RANGING;
            act->ranging = s.type == KELP_SLOT_REMUS_LBL ? KELP_RANGING_REMUS_LBL : KELP_RANGING_TWO_WAY_PING;
        }
    }
    mac->slots_fired++;
    mac->current++;
    if (mac->type == KELP_MAC_AUTO_DECENTRALIZED) {
        expire_ids(mac, now);
        if (mac->current >= mac->n) {
            mac->cycles_since_day_start++;
            position_blank(mac);
        }
        /* after an expiry the cycle was re-aligned and Goby still adds one slot: reproduced */
        mac->next_slot += mac->slot_seconds; /* whole seconds: exact */
    } else {
        if (mac->current >= mac->n) mac->current = 0;
        mac->next_slot += s.slot_seconds;
    }
    return KELP_OK;
}

void kelp_mac_heard(kelp_mac *mac, int src, kelp_time now)
{
    if (!mac || mac->type != KELP_MAC_AUTO_DECENTRALIZED || src < 0 || !kelp_util_time_ok(now)) return;
    for (size_t i = 0; i < mac->n; i++) {
        if (mac->slot[i].src == src) {
            if (!mac->slot[i].never_expires) mac->slot[i].last_heard = now;
            return;
        }
    }
    if (mac->n >= KELP_MAX_MAC_SLOTS) {
        /* recorded, the id is not added */
        (void)kelp_fail(&mac->diag, KELP_ERR_NOSPACE, "mac: too many ids heard (KELP_MAX_MAC_SLOTS)");
        return;
    }
    kelp_mac_slot s;
    kelp_mac_slot_default(&s, src);
    s.rate = mac->rate;
    s.slot_seconds = mac->slot_seconds;
    s.last_heard = now;
    mac->slot[mac->n++] = s;
    sort_by_src(mac);
    mac->current = 0;
    cycle_size_change(mac, now);
}

int kelp_mac_update(kelp_mac *mac, int dest, kelp_mac_update_type type, const kelp_mac_slot *slots, size_t n,
                    kelp_time now)
{
    if (!mac || (n && !slots) || !kelp_util_time_ok(now)) return KELP_ERR_ARG;
    if (mac->type != KELP_MAC_FIXED_DECENTRALIZED && mac->type != KELP_MAC_POLLED) return KELP_ERR_STATE;
    if (dest != mac->modem_id) return KELP_ERR_NOTFOUND;
    int rc = KELP_OK;
    switch (type) {
    case KELP_MAC_UPDATE_REPLACE:
        kelp_mac_clear(mac);
        /* fall through */
    case KELP_MAC_UPDATE_ADD:
        for (size_t i = 0; i < n && rc == KELP_OK; i++) rc = kelp_mac_add_slot(mac, &slots[i], now);
        return rc;
    case KELP_MAC_UPDATE_REMOVE:
        for (size_t i = 0; i < n; i++) {
            int r = kelp_mac_remove_slot(mac, &slots[i], now);
            if (r != KELP_OK && rc == KELP_OK) rc = r;
        }
        return rc;
    default:
        return KELP_ERR_ARG;
    }
}
