/* kelp modemsim: pAcommsPoller core -- poll-slot parsing and the MACUpdate TextFormat. */
#include <kelp/poller.h>
#include <kelp/kv.h>
#include <kelp/mission.h>
#include <kelp/modemsim.h>

#include <string.h>

static bool key_is(const char *k, size_t kl, const char *name)
{
    size_t n = strlen(name);
    if (kl != n) return false;
    for (size_t i = 0; i < n; i++) {
        char a = k[i], b = name[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a + 32);
        if (b >= 'A' && b <= 'Z') b = (char)(b + 32);
        if (a != b) return false;
    }
    return true;
}

static int slot_type(const char *v, size_t vl, kelp_slot_type *out)
{
    static const struct {
        const char *name;
        kelp_slot_type t;
    } T[] = { { "data", KELP_SLOT_DATA },         { "slot_data", KELP_SLOT_DATA }, { "ping", KELP_SLOT_PING },
              { "slot_ping", KELP_SLOT_PING },    { "remus_lbl", KELP_SLOT_REMUS_LBL },
              { "slot_remus_lbl", KELP_SLOT_REMUS_LBL } };
    for (size_t i = 0; i < sizeof T / sizeof T[0]; i++)
        if (key_is(v, vl, T[i].name)) {
            *out = T[i].t;
            return KELP_OK;
        }
    return KELP_ERR_PARSE;
}

int kelp_poller_parse_slot(const char *spec, unsigned default_seconds, kelp_mac_slot *out, kelp_diag *d)
{
    static const char *const KEYS[] = { "src", "dest", "rate", "type", "slot_seconds" };
    if (!spec || !out) return kelp_fail(d, KELP_ERR_ARG, "no slot text");
    kelp_mac_slot_default(out, 0);
    out->slot_seconds = default_seconds;
    bool have_src = false;
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    while ((rc = kelp_kv_next(spec, ',', &pos, &k, &kl, &v, &vl)) == 1) {
        long n = 0;
        size_t which = sizeof KEYS / sizeof KEYS[0];
        for (size_t i = 0; i < sizeof KEYS / sizeof KEYS[0]; i++)
            if (key_is(k, kl, KEYS[i])) which = i;
        if (which == sizeof KEYS / sizeof KEYS[0]) {
            return kelp_fail(d, KELP_ERR_PARSE, "unknown key");
        }
        if (which == 3) {
            if (slot_type(v, vl, &out->type) != KELP_OK) {
                return kelp_fail(d, KELP_ERR_PARSE, "type");
            }
            continue;
        }
        if (kelp_util_parse_long(v, vl, &n) != KELP_OK) {
            return kelp_fail(d, KELP_ERR_PARSE, KEYS[which]);
        }
        switch (which) {
        case 0:
            if (n < 1 || n > 31) goto range;
            out->src = (int)n;
            have_src = true;
            break;
        case 1:
            if (n < -1 || n > 31) goto range;
            out->dest = (int)n;
            break;
        case 2:
            if (n < 0 || n > 5) goto range;
            out->rate = (unsigned)n;
            break;
        default:
            if (n < 1 || n > 86400) goto range;
            out->slot_seconds = (unsigned)n;
            break;
        }
        continue;
    range:
        return kelp_fail(d, KELP_ERR_RANGE, KEYS[which]);
    }
    if (rc < 0) {
        return kelp_fail(d, KELP_ERR_PARSE, "not key=value");
    }
    if (!have_src) {
        return kelp_fail(d, KELP_ERR_PARSE, "src");
    }
    if (out->slot_seconds < 1) {
        return kelp_fail(d, KELP_ERR_RANGE, "slot_seconds");
    }
    return KELP_OK;
}

/* ------------------------------------------------------------------ formatting */

typedef struct sbuf {
    char *p;
    size_t cap, n;
    bool over;
} sbuf;

static void add(sbuf *b, const char *s)
{
    size_t l = strlen(s);
    if (b->over || b->n + l + 1 > b->cap) {
        b->over = true;
        return;
    }
    memcpy(b->p + b->n, s, l);
    b->n += l;
    b->p[b->n] = '\0';
}

static void add_long(sbuf *b, long v)
{
    char t[24];
    size_t n = 0;
    unsigned long u = v < 0 ? (unsigned long)(-(v + 1)) + 1 : (unsigned long)v;
    char rev[24];
    size_t r = 0;
    do {
        rev[r++] = (char)('0' + u % 10);
        u /= 10;
    } while (u);
    if (v < 0) t[n++] = '-';
    while (r) t[n++] = rev[--r];
    t[n] = '\0';
    add(b, t);
}

static const char *type_name(kelp_slot_type t)
{
    switch (t) {
    case KELP_SLOT_PING: return "SLOT_PING";
    case KELP_SLOT_REMUS_LBL: return "SLOT_REMUS_LBL";
    case KELP_SLOT_DATA:
    default: return "SLOT_DATA";
    }
}

static const char *short_type(kelp_slot_type t)
{
    switch (t) {
    case KELP_SLOT_PING: return "ping";
    case KELP_SLOT_REMUS_LBL: return "remus_lbl";
    case KELP_SLOT_DATA:
    default: return "data";
    }
}

int kelp_poller_format_update(int dest, kelp_mac_update_type type, const kelp_mac_slot *slots, size_t n, char *buf,
                              size_t cap, size_t *len)
{
    if (!buf || cap == 0 || (n && !slots)) return KELP_ERR_ARG;
    sbuf b = { buf, cap, 0, false };
    buf[0] = '\0';
    add(&b, "dest: ");
    add_long(&b, dest);
    add(&b, " update_type: ");
    add(&b, type == KELP_MAC_UPDATE_ADD ? "ADD" : type == KELP_MAC_UPDATE_REMOVE ? "REMOVE" : "REPLACE");
    for (size_t i = 0; i < n; i++) {
        const kelp_mac_slot *s = &slots[i];
        add(&b, " slot { src: ");
        add_long(&b, s->src);
        add(&b, " dest: ");
        add_long(&b, s->dest);
        add(&b, " rate: ");
        add_long(&b, (long)s->rate);
        add(&b, " type: ");
        add(&b, type_name(s->type));
        add(&b, " slot_seconds: ");
        add_long(&b, (long)s->slot_seconds);
        add(&b, " }");
    }
    if (b.over) {
        buf[0] = '\0';
        return KELP_ERR_NOSPACE;
    }
    if (len) *len = b.n;
    return KELP_OK;
}

int kelp_poller_format_slot(const kelp_mac_slot *s, char *buf, size_t cap, size_t *len)
{
    if (!s || !buf || cap == 0) return KELP_ERR_ARG;
    sbuf b = { buf, cap, 0, false };
    buf[0] = '\0';
    add(&b, "src=");
    add_long(&b, s->src);
    add(&b, ",dest=");
    add_long(&b, s->dest);
    add(&b, ",rate=");
    add_long(&b, (long)s->rate);
    add(&b, ",type=");
    add(&b, short_type(s->type));
    add(&b, ",slot_seconds=");
    add_long(&b, (long)s->slot_seconds);
    if (b.over) {
        buf[0] = '\0';
        return KELP_ERR_NOSPACE;
    }
    if (len) *len = b.n;
    return KELP_OK;
}

/* ------------------------------------------------------------------ the poll list */

int kelp_poller_add(kelp_poller_list *l, const char *spec, kelp_diag *d)
{
    kelp_mac_slot s;
    int rc = kelp_poller_parse_slot(spec, l->default_seconds, &s, d);
    if (rc < 0) return rc;
    if (l->n >= KELP_MAX_MSIM_POLL_SLOTS) {
        return kelp_fail(d, KELP_ERR_NOSPACE, "list full (KELP_MAX_MSIM_POLL_SLOTS)");
    }
    l->slot[l->n++] = s;
    return KELP_OK;
}

static bool same_slot(const kelp_mac_slot *a, const kelp_mac_slot *b)
{
    return a->src == b->src && a->dest == b->dest && a->rate == b->rate && a->type == b->type &&
           a->slot_seconds == b->slot_seconds;
}

int kelp_poller_command(kelp_poller_list *l, const char *cmd, kelp_diag *d)
{
    while (*cmd == ' ') cmd++;
    const char *arg = strchr(cmd, ' ');
    size_t vl = arg ? (size_t)(arg - cmd) : strlen(cmd);
    if (arg)
        while (*arg == ' ') arg++;
#define VERB(w) (vl == strlen(w) && strncmp(cmd, w, vl) == 0)
    if (VERB("add") && arg && *arg) return kelp_poller_add(l, arg, d) < 0 ? KELP_ERR_PARSE : 1;
    if (VERB("remove") && arg && *arg) {
        kelp_mac_slot s;
        if (kelp_poller_parse_slot(arg, l->default_seconds, &s, d) < 0) return KELP_ERR_PARSE;
        for (size_t i = 0; i < l->n; i++) {
            if (!same_slot(&l->slot[i], &s)) continue;
            memmove(&l->slot[i], &l->slot[i + 1], (l->n - i - 1) * sizeof l->slot[0]);
            l->n--;
            return 1;
        }
        return kelp_fail(d, KELP_ERR_NOTFOUND, "no such slot");
    }
    if (VERB("replace")) {
        /* replace src=..;src=..;... (empty = no slots): all or nothing, so every slot is
         * checked (as kelp_poller_add would) before the list is touched */
        const char *p0 = arg ? arg : "";
        for (int pass = 0; pass < 2; pass++) {
            size_t count = 0;
            if (pass) l->n = 0;
            for (const char *p = p0; *p;) {
                const char *e = strchr(p, ';');
                size_t len = e ? (size_t)(e - p) : strlen(p);
                char one[256];
                if (len >= sizeof one) {
                    return kelp_fail(d, KELP_ERR_RANGE, "slot too long");
                }
                memcpy(one, p, len);
                one[len] = '\0';
                if (len) {
                    kelp_mac_slot s;
                    if (kelp_poller_parse_slot(one, l->default_seconds, &s, d) < 0) return KELP_ERR_PARSE;
                    if (count >= KELP_MAX_MSIM_POLL_SLOTS) {
                        return kelp_fail(d, KELP_ERR_PARSE, "list full (KELP_MAX_MSIM_POLL_SLOTS)");
                    }
                    if (pass) l->slot[count] = s;
                    count++;
                }
                p += len + (e ? 1 : 0);
            }
            if (pass) l->n = count;
        }
        return 1;
    }
    if (VERB("clear")) l->n = 0;
    else if (VERB("pause")) l->paused = true;
    else if (VERB("resume")) l->paused = false;
    else if (!VERB("publish")) {
        return kelp_fail(d, KELP_ERR_PARSE, "unknown command (add SLOT | remove SLOT | replace SLOT;SLOT | clear | pause | resume | publish)");
    }
#undef VERB
    return 1;
}

unsigned kelp_poller_cycle_seconds(const kelp_poller_list *l)
{
    unsigned s = 0;
    for (size_t i = 0; i < l->n; i++) s += l->slot[i].slot_seconds;
    return s;
}
