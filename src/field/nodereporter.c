/* pNodeReporter's logic: NAV_* and the helm's state in, NODE_REPORT_LOCAL out (see
 * include/kelp/field.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>
#include <kelp/kv.h>
#include <kelp/mission.h>

static const char *const nav_suffix[KELP_NREP_NAV] = { "_X", "_Y", "_LAT", "_LONG", "_SPEED", "_HEADING", "_DEPTH" };
static const char *const helm_vars[] = { "IVPHELM_STATE", "IVPHELM_SUMMARY", "IVPHELM_ALLSTOP" };

static void set_text(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap) n = cap - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

void kelp_field_nrep_cfg_default(kelp_field_nrep_cfg *cfg, const char *community)
{
    memset(cfg, 0, sizeof *cfg);
    set_text(cfg->name, sizeof cfg->name, community ? community : "");
    set_text(cfg->type, sizeof cfg->type, "UUV");
    set_text(cfg->out_var, sizeof cfg->out_var, "NODE_REPORT_LOCAL");
    set_text(cfg->prefix, sizeof cfg->prefix, "NAV");
}

static bool usable(const char *s)
{
    return !strpbrk(s, ",=");
}

int kelp_field_nrep_init(kelp_field_nrep *r, const kelp_field_nrep_cfg *cfg)
{
    memset(r, 0, sizeof *r);
    if (!cfg->name[0] || !usable(cfg->name) || !usable(cfg->type) || !usable(cfg->group) || !cfg->out_var[0] ||
        !cfg->prefix[0] || (cfg->have_length && !(cfg->length >= 0 && isfinite(cfg->length))))
        return KELP_ERR_ARG;
    r->cfg = *cfg;
    for (int i = 0; i < KELP_NREP_NAV; i++) {
        int n = snprintf(r->nav_var[i], sizeof r->nav_var[i], "%s%s", cfg->prefix, nav_suffix[i]);
        if (n < 0 || (size_t)n >= sizeof r->nav_var[i]) return KELP_ERR_RANGE;
    }
    return KELP_OK;
}

const char *kelp_field_nrep_subscription(const kelp_field_nrep *r, unsigned i)
{
    if (i < KELP_NREP_NAV) return r->nav_var[i];
    i -= KELP_NREP_NAV;
    if (i < sizeof helm_vars / sizeof helm_vars[0]) return helm_vars[i];
    i -= (unsigned)(sizeof helm_vars / sizeof helm_vars[0]);
    if (i == 0 && r->cfg.mode_var[0]) return r->cfg.mode_var;
    return NULL;
}

/* helm strings go into a report field: drop separators, bound the length */
static void copy_field(char *dst, const char *src)
{
    size_t j = 0;
    for (size_t i = 0; src[i] && j + 1 < KELP_NODEREPORT_MAX_FIELD; i++)
        if (src[i] != ',' && src[i] != '=') dst[j++] = src[i];
    dst[j] = 0;
}

static void warn(const kelp_field_sink *out, const char *msg)
{
    if (out && out->warn) out->warn(out->ctx, msg);
}

int kelp_field_nrep_mail(kelp_field_nrep *r, const char *var, bool is_string, const char *sval, double dval,
                         const kelp_field_sink *out)
{
    for (int i = 0; i < KELP_NREP_NAV; i++) {
        if (strcmp(var, r->nav_var[i]) != 0) continue;
        double d = dval;
        if (is_string && (!sval || kelp_parse_double(sval, strlen(sval), &d) < 0)) d = NAN;
        if (!isfinite(d)) {
            char msg[KELP_MAX_NAME + 48];
            snprintf(msg, sizeof msg, "%s is not a finite number; ignored", var);
            r->bad_mail++;
            warn(out, msg);
            return KELP_ERR_RANGE;
        }
        r->nav[i] = d;
        r->have[i] = true;
        r->fresh = true;
        r->nav_mail++;
        return 1;
    }
    if (!is_string || !sval) return 0;
    if (strcmp(var, "IVPHELM_STATE") == 0) {
        copy_field(r->helm_state, sval);
    } else if (strcmp(var, "IVPHELM_ALLSTOP") == 0) {
        copy_field(r->allstop, sval);
    } else if (strcmp(var, "IVPHELM_SUMMARY") == 0) {
        /* MOOS-IvP helm modes ("modes=MODE@ACTIVE:LOITERING") when present, else the active
         * behaviours ("active_bhvs=survey") */
        char modes[KELP_NODEREPORT_MAX_FIELD * 2];
        if (kelp_kv_get(sval, ',', "modes", modes, sizeof modes) == 1) {
            copy_field(r->helm_modes, modes);
        } else if (kelp_kv_get(sval, ',', "active_bhvs", modes, sizeof modes) == 1) {
            if (!strcmp(modes, "none")) r->helm_active[0] = 0;
            else copy_field(r->helm_active, modes);
        }
    } else if (r->cfg.mode_var[0] && strcmp(var, r->cfg.mode_var) == 0) {
        copy_field(r->mode, sval);
    } else {
        return 0;
    }
    return 1;
}

int kelp_field_nrep_iterate(kelp_field_nrep *r, double now, const kelp_field_sink *out)
{
    bool xy = r->have[KELP_NREP_X] && r->have[KELP_NREP_Y];
    bool ll = r->have[KELP_NREP_LAT] && r->have[KELP_NREP_LON];
    if (!r->fresh || (!xy && !ll)) return 0;
    kelp_nodereport n;
    kelp_nodereport_init(&n);
    memcpy(n.name, r->cfg.name, sizeof n.name);
    memcpy(n.type, r->cfg.type, sizeof n.type);
    n.fields = KELP_NR_NAME | KELP_NR_TYPE | KELP_NR_TIME;
    n.time = now;
    if (xy) n.x = r->nav[KELP_NREP_X], n.y = r->nav[KELP_NREP_Y], n.fields |= KELP_NR_X | KELP_NR_Y;
    if (ll) n.lat = r->nav[KELP_NREP_LAT], n.lon = r->nav[KELP_NREP_LON], n.fields |= KELP_NR_LAT | KELP_NR_LON;
    if (r->cfg.have_geo && kelp_nodereport_complete(&n, &r->cfg.geo) < 0) warn(out, "datum conversion failed");
    n.spd = r->nav[KELP_NREP_SPD];
    n.hdg = r->nav[KELP_NREP_HDG];
    n.depth = r->nav[KELP_NREP_DEP];
    n.fields |= KELP_NR_SPD | KELP_NR_HDG | KELP_NR_DEPTH;
    if (r->cfg.have_length) n.length = r->cfg.length, n.fields |= KELP_NR_LENGTH;
    /* MODE: MODE_VAR if configured, else the helm summary's modes, else the helm state with its
     * active behaviours ("DRIVE@survey") */
    char hm[KELP_NODEREPORT_MAX_FIELD * 2 + 2];
    snprintf(hm, sizeof hm, "%s%s%s", r->helm_state, r->helm_state[0] && r->helm_active[0] ? "@" : "",
             r->helm_active);
    const char *mode = r->mode[0] ? r->mode : r->helm_modes[0] ? r->helm_modes : hm;
    if (mode[0]) {
        set_text(n.mode, sizeof n.mode, mode); /* bounded: a long behaviour list is cut */
        n.fields |= KELP_NR_MODE;
    }
    if (r->allstop[0]) memcpy(n.allstop, r->allstop, sizeof n.allstop), n.fields |= KELP_NR_ALLSTOP;
    if (r->cfg.group[0]) memcpy(n.group, r->cfg.group, sizeof n.group), n.fields |= KELP_NR_GROUP;
    size_t len;
    int rc = kelp_nodereport_format(&n, r->last, sizeof r->last, &len);
    if (rc < 0) {
        warn(out, "cannot format the report");
        return rc;
    }
    out->publish(out->ctx, r->cfg.out_var, true, r->last, 0);
    r->posted++;
    r->fresh = false;
    return 1;
}
