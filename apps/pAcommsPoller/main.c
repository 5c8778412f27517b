/* pAcommsPoller: centralized polling from the topside (seed 002 section 2.10; Goby 1.1 folded it
 * into pAcommsHandler's MAC_POLLED).  This process owns the poll list -- which vehicle sends to
 * whom, at which rate, for how long -- and drives the topside pAcommsHandler (mac_cfg type
 * MAC_POLLED) through ACOMMS_MAC_CYCLE_UPDATE: at start-up, on every change made at run time
 * through POLLER_COMMAND, and (optionally) periodically.  Each update is a full REPLACE in
 * Goby's TextFormat, so a lost or late update never leaves the handler with half a cycle. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kelp/poller.h>
#include <kelp/app.h>
#include <kelp/mac.h>
#include <kelp/modemsim.h>


typedef struct poller {
    int modem_id;
    kelp_poller_list list;
    char update_var[KELP_MAX_NAME], legacy_var[KELP_MAX_NAME], command_var[KELP_MAX_NAME];
    double republish, last_publish, max_range;
    bool dirty;
    unsigned long updates, commands, bad_commands;
    char last_update[4096];
} poller;

static void check_slot(kelp_app *app, const poller *p, const kelp_mac_slot *s)
{
    if (s->type != KELP_SLOT_DATA || p->max_range <= 0) return;
    double need = kelp_modemsim_min_slot_seconds(s->rate, p->max_range, 1.0, 0.5, 0.25, KELP_MODEMSIM_SOUND_SPEED);
    if ((double)s->slot_seconds < need)
        kelp_app_run_warning(app, "slot src=%d dest=%d rate %u: %u s is short for %.0f m (a full packet with its "
                                  "ack needs %.1f s)",
                             s->src, s->dest, s->rate, s->slot_seconds, p->max_range, need);
}

static int publish(kelp_app *app, poller *p)
{
    size_t len;
    int rc = kelp_poller_format_update(p->modem_id, KELP_MAC_UPDATE_REPLACE, p->list.slot, p->list.paused ? 0 : p->list.n,
                                       p->last_update, sizeof p->last_update, &len);
    if (rc < 0) {
        kelp_app_run_warning(app, "update too long: %s", kelp_err_str(rc));
        return rc;
    }
    if (kelp_app_notify_string(app, p->update_var, p->last_update) < 0) return KELP_ERR_IO;
    if (p->legacy_var[0]) KELP_IGNORE(kelp_app_notify_string(app, p->legacy_var, p->last_update));
    char list[2048] = "";
    size_t off = 0;
    for (size_t i = 0; i < p->list.n; i++) {
        char one[128];
        size_t l;
        if (kelp_poller_format_slot(&p->list.slot[i], one, sizeof one, &l) < 0 || off + l + 2 > sizeof list) break;
        if (off) list[off++] = ';';
        memcpy(list + off, one, l + 1);
        off += l;
    }
    KELP_IGNORE(kelp_app_notify_string(app, "POLLER_CYCLE", list));
    KELP_IGNORE(kelp_app_notify_stringf(app, "POLLER_STATUS", "state=%s,slots=%zu,cycle_seconds=%u,updates=%lu",
                                  p->list.paused ? "paused" : "active", p->list.n, kelp_poller_cycle_seconds(&p->list), p->updates + 1));
    p->updates++;
    p->dirty = false;
    p->last_publish = kelp_app_time(app);
    kelp_app_event(app, "%s%s", p->update_var, p->list.paused ? " (paused: no slots)" : "");
    return KELP_OK;
}

/* "src: 2 dest: 1 ..." children of a protobuf-style slot { } block -> "src=2,dest=1,..." */
static int block_to_spec(kelp_app *app, const kelp_mission_node *blk, char *out, size_t cap)
{
    const kelp_mission *m = kelp_app_mission(app);
    int parent = (int)(blk - m->nodes);
    size_t off = 0;
    out[0] = '\0';
    for (int i = kelp_mission_next(m, parent, -1, NULL); i >= 0; i = kelp_mission_next(m, parent, i, NULL)) {
        const kelp_mission_node *c = &m->nodes[i];
        kelp_app_param_used(app, c);
        char val[64];
        if (c->kind != KELP_MN_FIELD || kelp_mission_copy(c, val, sizeof val) < 0) return -1;
        int n = snprintf(out + off, cap - off, "%s%.*s=%s", off ? "," : "", (int)c->klen, c->key, val);
        if (n < 0 || (size_t)n >= cap - off) return -1;
        off += (size_t)n;
    }
    return 0;
}

static int add_slot(kelp_app *app, poller *p, const char *spec, const kelp_mission_node *at)
{
    kelp_diag why;
    kelp_diag_clear(&why);
    if (kelp_poller_add(&p->list, spec, &why) < 0)
        return kelp_app_config_error(app, at, "poll slot '%s': %s", spec, kelp_diag_text(&why));
    check_slot(app, p, &p->list.slot[p->list.n - 1]);
    return 0;
}

static int startup(kelp_app *app, void *st)
{
    poller *p = st;
    double d;
    int rc = kelp_app_param_double(app, "modem_id", &d);
    if (rc <= 0 || d != floor(d) || d < 1 || d > 31)
        return kelp_app_config_error(app, kelp_app_param(app, "modem_id"),
                                     "modem_id (1..31, the polling topside modem) is required");
    p->modem_id = (int)d;
    p->list.default_seconds = 15;
    if ((rc = kelp_app_param_double(app, "slot_seconds", &d)) < 0 || (rc > 0 && (d < 1 || d > 86400 || d != floor(d))))
        return kelp_app_config_error(app, kelp_app_param(app, "slot_seconds"), "slot_seconds must be 1..86400");
    if (rc > 0) p->list.default_seconds = (unsigned)d;
    p->max_range = 2000;
    if (kelp_app_param_double(app, "max_range", &p->max_range) < 0 || p->max_range < 0)
        return kelp_app_config_error(app, kelp_app_param(app, "max_range"), "max_range must be >= 0 (m)");
    snprintf(p->update_var, sizeof p->update_var, "ACOMMS_MAC_CYCLE_UPDATE");
    KELP_IGNORE(kelp_app_param_str(app, "update_var", p->update_var, sizeof p->update_var));
    bool legacy = false;
    if (kelp_app_param_bool(app, "legacy_update", &legacy) < 0) return -1;
    if (legacy) snprintf(p->legacy_var, sizeof p->legacy_var, "ACOMMS_POLLER_UPDATE");
    snprintf(p->command_var, sizeof p->command_var, "POLLER_COMMAND");
    KELP_IGNORE(kelp_app_param_str(app, "command_var", p->command_var, sizeof p->command_var));
    if (kelp_app_param_double(app, "republish_interval", &p->republish) < 0 || p->republish < 0)
        return kelp_app_config_error(app, kelp_app_param(app, "republish_interval"), "republish_interval >= 0");
    bool enabled = true;
    if (kelp_app_param_bool(app, "enabled", &enabled) < 0) return -1;
    p->list.paused = !enabled;
    /* the poll list, in order: MOOS lines "poll = src=2,dest=1,..." and Goby blocks "slot { src: 2 ... }" */
    const kelp_mission *m = kelp_app_mission(app);
    int blk = kelp_app_block(app);
    for (int i = blk >= 0 ? kelp_mission_next(m, blk, -1, NULL) : -1; i >= 0; i = kelp_mission_next(m, blk, i, NULL)) {
        const kelp_mission_node *n = &m->nodes[i];
        char spec[256];
        if (kelp_mission_key_is(n, "poll") || kelp_mission_key_is(n, "pair")) {
            kelp_app_param_used(app, n);
            if (kelp_mission_copy(n, spec, sizeof spec) < 0) return kelp_app_config_error(app, n, "poll line too long");
            if (add_slot(app, p, spec, n) < 0) return -1;
        } else if (kelp_mission_key_is(n, "slot") && n->kind == KELP_MN_MSG) {
            kelp_app_param_used(app, n);
            if (block_to_spec(app, n, spec, sizeof spec) < 0) return kelp_app_config_error(app, n, "bad slot block");
            if (add_slot(app, p, spec, n) < 0) return -1;
        }
    }
    if (p->list.n == 0) kelp_app_config_warning(app, "no poll slots: the cycle is empty until POLLER_COMMAND adds some");
    if (kelp_app_register(app, p->command_var, 0) < 0) return -1;
    p->dirty = true;
    return 0;
}

static void command(kelp_app *app, poller *p, const char *cmd)
{
    kelp_diag why;
    kelp_diag_clear(&why);
    size_t before = p->list.n;
    p->commands++;
    if (kelp_poller_command(&p->list, cmd, &why) < 0) {
        p->bad_commands++;
        kelp_app_run_warning(app, "%s '%s' refused (%s)", p->command_var, cmd, kelp_diag_text(&why));
        return;
    }
    for (size_t i = before; i < p->list.n; i++) check_slot(app, p, &p->list.slot[i]);
    p->dirty = true;
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    poller *p = st;
    if (strcmp(v->name, p->command_var) != 0) return;
    if (v->flags & KELP_VAR_FLAG_SYNC) return; /* an old command replayed on registration */
    if (v->kind != KELP_VAR_STRING) {
        p->bad_commands++;
        kelp_app_run_warning(app, "%s must be a string", p->command_var);
        return;
    }
    command(app, p, v->sval);
}

static int iterate(kelp_app *app, void *st, double now)
{
    poller *p = st;
    if (p->dirty || (p->republish > 0 && now - p->last_publish >= p->republish)) (void)publish(app, p);
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    poller *p = st;
    (void)app;
    fprintf(out, "polling modem %d: %s, %zu slots, cycle %u s; %lu updates, %lu commands (%lu bad)\n", p->modem_id,
            p->list.paused ? "PAUSED" : "active", p->list.n, kelp_poller_cycle_seconds(&p->list), p->updates, p->commands, p->bad_commands);
    for (size_t i = 0; i < p->list.n; i++) {
        char one[128];
        size_t l;
        if (kelp_poller_format_slot(&p->list.slot[i], one, sizeof one, &l) == 0) fprintf(out, "  %2zu  %s\n", i + 1, one);
    }
}

static const kelp_app_def def = {
    .name = "pAcommsPoller",
    .purpose = "Centralized polling from the topside: owns the poll list and drives the topside pAcommsHandler "
               "(MAC_POLLED) through ACOMMS_MAC_CYCLE_UPDATE.",
    .params = (const kelp_app_param_info[]){
        { "modem_id", "1", "required: the topside modem (its pAcommsHandler runs MAC_POLLED), 1..31", NULL },
        { "slot_seconds", "15", "default slot length, s, 1..86400", NULL },
        { "max_range", "2000", "m: warn about slots too short for a packet and its ack", NULL },
        { "poll", "src=2,dest=1,rate=0,type=data,slot_seconds=15", "repeatable: one slot, in cycle order", NULL },
        { "pair", "src=1,dest=2,rate=0", "repeatable: same as poll", NULL },
        { "slot", "{ src: 3 dest: 1 rate: 0 type: SLOT_DATA slot_seconds: 15 }", "repeatable: a slot, Goby style", NULL },
        { "update_var", "ACOMMS_MAC_CYCLE_UPDATE", "where the cycle is posted", NULL },
        { "legacy_update", "false", "true: also post ACOMMS_POLLER_UPDATE", NULL },
        { "republish_interval", "0", "s; re-send the full cycle periodically (0 = only on change)", NULL },
        { "command_var", "POLLER_COMMAND", "the variable commands arrive on", NULL },
        { "enabled", "true", "false: start paused (an empty cycle)", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "POLLER_COMMAND", "add src=2,dest=1,rate=0,type=data,slot_seconds=15",
          "add SLOT | remove SLOT | replace SLOT;SLOT... | clear | pause | resume | publish (<command_var>)" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "ACOMMS_MAC_CYCLE_UPDATE", "dest: 1 update_type: REPLACE slot { src: 2 dest: 1 rate: 0 type: SLOT_DATA "
          "slot_seconds: 15 }", "MACUpdate TextFormat (<update_var>)" },
        { "ACOMMS_POLLER_UPDATE", "(as ACOMMS_MAC_CYCLE_UPDATE)", "with legacy_update = true" },
        { "POLLER_CYCLE", "src=2,dest=1,rate=0,type=data,slot_seconds=15;src=1,dest=2,rate=0,type=data,slot_seconds=15",
          "the slot list" },
        { "POLLER_STATUS", "state=running,slots=2,cycle_seconds=30,updates=1", NULL },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static poller p;
    return kelp_app_run(argc, argv, &def, &p);
}
