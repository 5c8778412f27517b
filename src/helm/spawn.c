/* kelp helm: spawn templates, spawning on UPDATES, removal of completed instances, and the
 * contact ledger fed by NODE_REPORT (see include/kelp/helm.h, "templates and spawning"). */
#include <string.h>
#include <kelp/nodereport.h>
#include "helm_int.h"

static bool starts_with(const char *s, const char *prefix)
{
    size_t n = strlen(prefix);
    return n && !strncmp(s, prefix, n);
}

bool helm_name_matches(const kelp_bhv *b, const char *val)
{
    if (!strcmp(val, b->name))
        return true;
    if (!b->spawned)
        return false;
    size_t n = strlen(b->spawn_base);
    return !strncmp(b->name, b->spawn_base, n) && !strcmp(b->name + n, val);
}

kelp_bhv *kelp_helm_find_template(kelp_helm *h, const char *name)
{
    for (unsigned i = 0; i < h->ntmpl; i++)
        if (!strcmp(h->tmpl[i].name, name))
            return &h->tmpl[i];
    return NULL;
}

int helm_templates_extract(kelp_helm *h)
{
    unsigned k = 0;
    for (unsigned i = 0; i < h->nbhv; i++) {
        kelp_bhv *b = &h->bhv[i];
        if (hx_ieq(b->templating, "spawn") && !b->spawned) {
            if (h->ntmpl >= KELP_HELM_MAX_TEMPLATES)
                return KELP_ERR_NOSPACE;
            h->tmpl[h->ntmpl++] = *b;
            h->bhv_cnt_ever--; /* a template is not a behaviour */
            continue;
        }
        if (k != i)
            h->bhv[k] = *b;
        k++;
    }
    h->nbhv = k;
    return 0;
}

static void warn(kelp_helm *h, const char *a, const char *b, const char *c)
{
    char *msg = h->ws_upd.msg; /* the update workspace: idle while spawning */
    hx_cat(msg, sizeof h->ws_upd.msg, a, b ? b : "", c ? c : "", HX_END);
    helm_sink(h, "BHV_WARNING", true, msg, 0, NULL);
    helm_sink(h, "IVPHELM_BHVSET_WARNING", true, msg, 0, NULL);
    h->rep.warnings++;
}

static bool name_taken(kelp_helm *h, const char *full, const char *uname)
{
    return kelp_helm_find(h, full) != NULL || kelp_helm_find(h, uname) != NULL;
}

/* Apply the update's pieces other than name= to b; false on the first bad piece. */
static bool apply_pieces(kelp_helm *h, kelp_bhv *b, const char *s)
{
    char param[KELP_MAX_NAME], *val = h->ws_upd.val; /* the update workspace: idle while spawning */
    for (const char *p = s;;) {
        const char *e = strchr(p, '#');
        size_t pn = e ? (size_t)(e - p) : strlen(p);
        if (!helm_update_piece(p, pn, param, sizeof param, val, sizeof h->ws_upd.val))
            return false;
        b->fail = NULL;
        if (strcmp(param, "name") != 0 && kelp_helm_bhv_set_param(b, param, val) < 0)
            return false;
        if (!e)
            return true;
        p = e + 1;
    }
}

/* the value of the request's name= piece into out; false without one */
static bool request_name(kelp_helm *h, const char *s, char *out, size_t cap)
{
    char param[KELP_MAX_NAME], *val = h->ws_upd.val; /* the update workspace: idle while spawning */
    for (const char *p = s;;) {
        const char *e = strchr(p, '#');
        size_t pn = e ? (size_t)(e - p) : strlen(p);
        if (helm_update_piece(p, pn, param, sizeof param, val, sizeof h->ws_upd.val) && !strcmp(param, "name"))
            return val[0] && hx_copy(out, cap, val, strlen(val));
        if (!e)
            return false;
        p = e + 1;
    }
}

static void spawn_one(kelp_helm *h, kelp_bhv *t, const char *req)
{
    char *uname = h->ws_spawn_name[0], *full = h->ws_spawn_name[1];
    const size_t cap = sizeof h->ws_spawn_name[0];
    if (!request_name(h, req, uname, cap))
        return;
    if (starts_with(uname, t->name))
        memcpy(full, uname, cap);
    else if (!hx_copy(full, cap, t->name, strlen(t->name)) ||
             !hx_copy(full + strlen(t->name), cap - strlen(t->name), uname, strlen(uname))) {
        warn(h, "Spawn refused: behaviour name too long: ", t->name, uname);
        return;
    }
    if (name_taken(h, full, uname))
        return; /* an update for a live instance: its own updates check applies it */
    if (t->max_spawnings && t->spawns_made >= t->max_spawnings) {
        warn(h, "Behavior named [", full, "] not spawned: template max_spawnings reached");
        return;
    }
    if (h->nspawned >= KELP_HELM_MAX_SPAWNED || h->nbhv >= KELP_HELM_MAX_BHVS) {
        h->spawn_refused++;
        warn(h, "Spawn of [", full,
             h->nspawned >= KELP_HELM_MAX_SPAWNED ? "] refused: KELP_HELM_MAX_SPAWNED instances alive"
                                                  : "] refused: KELP_HELM_MAX_BHVS behaviours in the helm");
        return;
    }
    t->spawns_tried++;
    kelp_bhv *b = &h->bhv[h->nbhv];
    *b = *t;
    b->spawned = true;
    b->uid = ++h->next_uid;
    memcpy(b->spawn_base, t->name, sizeof b->spawn_base);
    memcpy(b->name, full, sizeof b->name < cap ? sizeof b->name : cap);
    (void)hx_copy(b->templating, sizeof b->templating, "disallowed", 10);
    b->fail = NULL;
    if (!apply_pieces(h, b, req) || (b->ops->params_done && b->ops->params_done(b) < 0)) {
        helm_life_event(h, b->name, b->type, "abort", req);
        warn(h, "Failed to spawn ", full, b->fail ? b->fail : ": bad configuration");
        return;
    }
    h->nbhv++;
    h->nspawned++;
    h->bhv_cnt_ever++;
    t->spawns_made++;
    helm_life_event(h, b->name, b->type, "spawn", req);
    helm_post_flags(b, KELP_FLAG_SPAWN);
    if (b->ops->post_config)
        b->ops->post_config(b);
}

void helm_spawn(kelp_helm *h)
{
    for (unsigned i = 0; i < h->ntmpl; i++) {
        kelp_bhv *t = &h->tmpl[i];
        if (!t->updates[0])
            continue;
        unsigned n = kelp_helm_ib_ndeltas(&h->ib, t->updates);
        for (unsigned k = 0; k < n; k++) {
            const char *s = NULL;
            if (kelp_helm_ib_delta(&h->ib, t->updates, k, NULL, &s) && s && *s)
                spawn_one(h, t, s);
        }
    }
}

void helm_reap(kelp_helm *h)
{
    unsigned k = 0;
    unsigned long removed = 0;
    for (unsigned i = 0; i < h->nbhv; i++) {
        kelp_bhv *b = &h->bhv[i];
        /* 24.8 removes every completed behaviour with a death event; kelp keeps a configured
         * one in its table (completed, never run again) and removes the spawned ones */
        if (b->completed && !b->spawned && !b->death_posted) {
            b->death_posted = true;
            helm_life_event(h, b->name, b->type, "death", NULL);
        }
        if (b->spawned && b->completed) {
            helm_life_event(h, b->name, b->type, "death", NULL);
            unsigned f = 0; /* forget its duplicate-filter entries */
            for (unsigned j = 0; j < h->nfilter; j++)
                if (h->filter[j].owner != b->uid)
                    h->filter[f++] = h->filter[j];
            h->nfilter = f;
            h->nspawned--;
            removed++;
            continue;
        }
        if (k != i)
            h->bhv[k] = *b;
        k++;
    }
    h->nbhv = k;
    if (removed) { /* (their IVPHELM_COMPLETED_COUNT went out with the iteration's report) */
        h->completed_removed += removed;
        h->ncompleted_seen = h->ncompleted_seen > removed ? h->ncompleted_seen - (unsigned)removed : 0;
    }
}

/* ---------------------------------------------------------------- contact ledger */

const kelp_helm_contact *kelp_helm_contact_get(const kelp_helm *h, const char *name)
{
    for (unsigned i = 0; i < h->ncontacts; i++)
        if (kelp_util_strieq_n(name, strlen(name), h->ledger[i].name) && strlen(h->ledger[i].name) == strlen(name))
            return &h->ledger[i];
    return NULL;
}

int kelp_helm_ledger_report(kelp_helm *h, const char *report)
{
    kelp_nodereport r;
    if (kelp_nodereport_parse(report, strlen(report), &r, NULL) != 0 || !(r.fields & KELP_NR_X) ||
        !(r.fields & KELP_NR_Y))
        return KELP_ERR_PARSE;
    if (h->cfg.us[0] && hx_ieq(r.name, h->cfg.us))
        return 0;
    kelp_helm_contact *c = (kelp_helm_contact *)kelp_helm_contact_get(h, r.name);
    if (!c) {
        if (h->ncontacts < KELP_HELM_MAX_CONTACTS) {
            c = &h->ledger[h->ncontacts++];
        } else { /* replace the one heard from longest ago */
            c = &h->ledger[0];
            for (unsigned i = 1; i < h->ncontacts; i++)
                if (h->ledger[i].seen < c->seen)
                    c = &h->ledger[i];
        }
        memset(c, 0, sizeof *c);
        if (!hx_copy(c->name, sizeof c->name, r.name, strlen(r.name)))
            return KELP_ERR_NOSPACE;
    }
    (void)hx_copy(c->type, sizeof c->type, r.type, strlen(r.type) < sizeof c->type ? strlen(r.type) : 0);
    (void)hx_copy(c->group, sizeof c->group, r.group, strlen(r.group) < sizeof c->group ? strlen(r.group) : 0);
    c->x = r.x;
    c->y = r.y;
    c->hdg = (r.fields & KELP_NR_HDG) ? r.hdg : 0;
    c->spd = (r.fields & KELP_NR_SPD) ? r.spd : 0;
    c->utc = (r.fields & KELP_NR_TIME) ? r.time : -1;
    c->seen = h->ib.curr_time;
    h->ledger_reports++;
    return 0;
}

void helm_ledger_update(kelp_helm *h)
{
    unsigned n = kelp_helm_ib_ndeltas(&h->ib, "NODE_REPORT");
    for (unsigned k = 0; k < n; k++) {
        const char *s = NULL;
        if (kelp_helm_ib_delta(&h->ib, "NODE_REPORT", k, NULL, &s) && s && kelp_helm_ledger_report(h, s) < 0)
            h->ib.dropped++; /* a malformed report: counted, the rest still read */
    }
}
