/* pREMUSCodec's logic (core): see the tool section of include/kelp/remus.h for the behaviour
 * and where it came from (Goby 1.x src/moos/pREMUSCodec/pREMUSCodec.cpp). */
#include <kelp/remus.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <kelp/acomms.h>
#include <kelp/kv.h>
#include <kelp/nodereport.h>
#include <kelp/util.h>

static const char *const KIND_NAME[KELP_REMUS_NVARS] = {"STATUS", "RANGER", "REDIRECT", "ALERT", "ALERT2"};
static const char *const NAV_VAR[KELP_REMUS_NNAV] = {"NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED", "NAV_DEPTH"};

void kelp_remus_codec_cfg_default(kelp_remus_codec_cfg *c)
{
    memset(c, 0, sizeof *c);
    c->status_interval = 10;
    for (int k = 0; k < KELP_REMUS_NVARS; k++) {
        (void)kelp_util_snprintf(c->in_var[k], sizeof c->in_var[k], "IN_REMUS_%s_HEX_30B", KIND_NAME[k]);
        (void)kelp_util_snprintf(c->out_var[k], sizeof c->out_var[k], "OUT_REMUS_%s_HEX_30B", KIND_NAME[k]);
    }
}

int kelp_remus_codec_init(kelp_remus_codec *t, const kelp_remus_codec_cfg *cfg)
{
    if (!t || !cfg || !cfg->geo || !(cfg->status_interval > 0) || !isfinite(cfg->status_interval))
        return KELP_ERR_ARG;
    for (int k = 0; k < KELP_REMUS_NVARS; k++)
        if (!cfg->in_var[k][0] || !cfg->out_var[k][0]) return KELP_ERR_ARG;
    memset(t, 0, sizeof *t);
    t->cfg = *cfg;
    t->last_status = -1;
    return KELP_OK;
}

const char *kelp_remus_codec_subscription(const kelp_remus_codec *t, unsigned i)
{
    if (i < KELP_REMUS_NVARS) return t->cfg.in_var[i];
    i -= KELP_REMUS_NVARS;
    if (i < KELP_REMUS_NVARS) return t->cfg.out_var[i]; /* Goby registers them too (unused) */
    i -= KELP_REMUS_NVARS;
    if (i == 0) return "MODEM_ID";
    i--;
    if (i < KELP_REMUS_NNAV) return NAV_VAR[i];
    return i == KELP_REMUS_NNAV ? "OUTGOING_COMMAND" : NULL;
}

/* formatted in t->warn, not on the stack (the contact path is deep) */
KELP_PRINTF(3, 4) static void warnf(kelp_remus_codec *t, const kelp_field_sink *sink, const char *fmt, ...)
{
    if (!sink->warn) return;
    va_list ap;
    va_start(ap, fmt);
    (void)kelp_util_vsnprintf(t->warn, sizeof t->warn, fmt, ap);
    va_end(ap);
    sink->warn(sink->ctx, t->warn);
}

static void pub_d(const kelp_field_sink *sink, const char *var, double v)
{
    sink->publish(sink->ctx, var, false, NULL, v);
}

/* Goby's as<string>(double): boost::lexical_cast, 17 significant digits */
static int append_kv(char *buf, size_t cap, size_t *off, const char *key, double v)
{
    int n = kelp_util_snprintf(buf + *off, cap - *off, ",%s=%.17g", key, v);
    if (n < 0 || (size_t)n >= cap - *off) return KELP_ERR_NOSPACE;
    *off += (size_t)n;
    return KELP_OK;
}

typedef struct contact {
    int node;
    const char *name, *type;
    double lat, lon, spd, hdg, depth;
} contact;

static void publish_contact(kelp_remus_codec *t, const contact *c, const char *kind_extra, kelp_time now,
                            const kelp_field_sink *sink)
{
    double x = 0, y = 0;
    kelp_dccl_geo_latlon2local(t->cfg.geo, c->lat, c->lon, &y, &x);

    enum { STATUS_CAP = 1024 }; /* bytes of a STATUS_REPORT_IN, with NUL */
    char *status = t->work.in.text;
    int n = kelp_util_snprintf(status, STATUS_CAP, "MessageType=CCL_STATUS,Node=%d", c->node);
    size_t off = n > 0 ? (size_t)n : 0;
    int rc = append_kv(status, STATUS_CAP, &off, "Timestamp", now);
    if (!rc) rc = append_kv(status, STATUS_CAP, &off, "Latitude", c->lat);
    if (!rc) rc = append_kv(status, STATUS_CAP, &off, "Longitude", c->lon);
    if (!rc) rc = append_kv(status, STATUS_CAP, &off, "Speed", c->spd);
    if (!rc) rc = append_kv(status, STATUS_CAP, &off, "Heading", c->hdg);
    if (!rc) rc = append_kv(status, STATUS_CAP, &off, "Depth", c->depth);
    if (!rc && kind_extra) {
        n = kelp_util_snprintf(status + off, STATUS_CAP - off, "%s", kind_extra);
        if (n < 0 || (size_t)n >= STATUS_CAP - off) rc = KELP_ERR_NOSPACE;
    }
    if (!rc) sink->publish(sink->ctx, "STATUS_REPORT_IN", true, status, 0);

    /* <NAME>_NAV_* contact variables (the name upper-cased) */
    char *up = t->work.in.up;
    size_t i;
    for (i = 0; i < sizeof t->work.in.up - 1 && c->name[i]; i++)
        up[i] = (char)((c->name[i] >= 'a' && c->name[i] <= 'z') ? c->name[i] - 'a' + 'A' : c->name[i]);
    up[i] = '\0';
    static const char *const suffix[] = {"UTC", "X", "Y", "LAT", "LONG", "SPEED", "DEPTH", "HEADING"};
    const double val[] = {now, x, y, c->lat, c->lon, c->spd, c->depth, c->hdg};
    for (size_t k = 0; k < sizeof suffix / sizeof suffix[0]; k++) {
        char *var = t->work.in.var;
        n = kelp_util_snprintf(var, sizeof t->work.in.var, "%s_NAV_%s", up, suffix[k]);
        if (n > 0 && (size_t)n < sizeof t->work.in.var) pub_d(sink, var, val[k]);
    }

    kelp_nodereport *r = &t->work.in.report;
    kelp_nodereport_init(r);
    (void)kelp_util_snprintf(r->name, sizeof r->name, "%s", c->name);
    (void)kelp_util_snprintf(r->type, sizeof r->type, "%s", c->type);
    (void)kelp_util_snprintf(r->mode, sizeof r->mode, "NOMOOS");
    (void)kelp_util_snprintf(r->allstop, sizeof r->allstop, "NotUsingIvP");
    r->time = now, r->x = x, r->y = y, r->lat = c->lat, r->lon = c->lon;
    r->spd = c->spd, r->hdg = c->hdg, r->depth = c->depth, r->length = 4.0;
    r->fields = KELP_NR_NAME | KELP_NR_TYPE | KELP_NR_TIME | KELP_NR_X | KELP_NR_Y | KELP_NR_LAT | KELP_NR_LON |
               KELP_NR_SPD | KELP_NR_HDG | KELP_NR_DEPTH | KELP_NR_LENGTH | KELP_NR_MODE | KELP_NR_ALLSTOP;
    char *buf = t->work.in.text; /* STATUS_REPORT_IN is out */
    if (kelp_nodereport_format(r, buf, KELP_NODEREPORT_MAX_LEN, NULL) == 0)
        sink->publish(sink->ctx, "NODE_REPORT", true, buf, 0);
    else
        warnf(t, sink, "cannot write a NODE_REPORT for %s", c->name);
}

static const kelp_dccl_modem_entry *lookup(const kelp_dccl_builtin *g, int id)
{
    for (size_t i = 0; i < g->n_modems; i++)
        if (g->modems[i].id == id) return &g->modems[i];
    return NULL;
}

/* ---- the CCL_*_IN texts (Goby's key order; numbers as boost::lexical_cast writes them) ---- */

typedef struct sb {
    char *buf;
    size_t cap, off;
    bool bad;
} sb;

KELP_PRINTF(2, 3) static void sb_add(sb *b, const char *fmt, ...)
{
    if (b->bad) return;
    va_list ap;
    va_start(ap, fmt);
    int n = kelp_util_vsnprintf(b->buf + b->off, b->cap - b->off, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= b->cap - b->off) b->bad = true;
    else b->off += (size_t)n;
}

static double ll_at(const uint8_t *f, size_t i)
{
    /* the decoder reads the low 24 bits as a signed code */
    return kelp_remus_latlon_decode((int32_t)((uint32_t)f[i] | ((uint32_t)f[i + 1] << 8) | ((uint32_t)f[i + 2] << 16)));
}

static unsigned u16_at(const uint8_t *f, size_t i)
{
    return (unsigned)f[i] | ((unsigned)f[i + 1] << 8);
}

static void alert_text(const uint8_t *f, int node, bool two, sb *b)
{
    double oasis = (double)((uint32_t)f[1] | ((uint32_t)f[2] << 8) | ((uint32_t)f[3] << 16) | ((uint32_t)f[4] << 24));
    sb_add(b, "MessageType=%s,Node=%d,Timestamp=%.17g,Latitude=%.17g,Longitude=%.17g", two ? "CCL_ALERT2" : "CCL_ALERT",
           node, oasis, ll_at(f, 5), ll_at(f, 8));
    if (!two) {
        sb_add(b, ",Heading=%.17g", kelp_remus_heading_decode(f[11]));
        for (int k = 0; k < 3; k++) {
            const uint8_t *c = f + 12 + 6 * k;
            sb_add(b, ",Contact%dId=%u,Contact%dAge=%u,Contact%dBearing=%u,Contact%dSignature1=%u,Contact%dSignature2=%u",
                   k + 1, u16_at(c, 0), k + 1, c[2], k + 1, c[3], k + 1, c[4], k + 1, c[5]);
        }
    } else {
        for (int k = 0; k < 3; k++) {
            const uint8_t *c = f + 11 + 7 * k;
            sb_add(b,
                   ",Contact%dId=%u,Contact%dAge=%u,Contact%dBearing=%u,Contact%dHeadingType=%s,Contact%dHeading=%.17g"
                   ",Contact%dSignature1=%u,Contact%dSignature2=%u",
                   k + 1, u16_at(c, 0), k + 1, c[2], k + 1, c[3], k + 1, (c[2] & 0x80) ? "Absolute" : "Vehicle", k + 1,
                   kelp_remus_heading_decode(c[4]), k + 1, c[5], k + 1, c[6]);
        }
    }
}

static void redirect_text(const uint8_t *f, int node, kelp_time now, sb *b)
{
    sb_add(b, "MessageType=CCL_REDIRECT,DestinationPlatformId=%d,Timestamp=%.17g,Latitude=%.17g,Longitude=%.17g"
              ",SpeedDepthFlags=%02X",
           node, now, ll_at(f, 2), ll_at(f, 5), f[8]);
    sb_add(b, ",TransitSpeed=%.17g,TransitDepth=%.17g,TransitCommand=%u", kelp_remus_speed_decode((int8_t)f[11]),
           kelp_remus_depth_decode((uint16_t)u16_at(f, 9)), f[12]);
    sb_add(b, ",SurveySpeed=%.17g,SurveyDepth=%.17g,SurveyCommand=%u", kelp_remus_speed_decode((int8_t)f[15]),
           kelp_remus_depth_decode((uint16_t)u16_at(f, 13)), f[16]);
    sb_add(b, ",NumberOfRows=%u,RowLength=%u,RowSpacing0=%u,RowSpacing1=%u,RowHeading=%.17g", f[17],
           u16_at(f, 18) & 0x1FFFu, f[20], f[21], kelp_remus_heading_decode(f[22]));
    sb_add(b, ",StartLatitude=%.17g,StartLongitude=%.17g", ll_at(f, 23), ll_at(f, 26));
}

static int incoming(kelp_remus_codec *t, int kind, const char *text, kelp_time now, const kelp_field_sink *sink)
{
    kelp_acomms_msg *m = &t->work.in.msg;
    kelp_diag *why = &t->work.in.diag;
    kelp_diag_clear(why);
    if (!text || kelp_acomms_parse_data(text, strlen(text), m, why) < 0) {
        t->refused++;
        warnf(t, sink, "%s: not a ModemDataTransmission (%s)", t->cfg.in_var[kind], why->code ? kelp_diag_text(why) : "?");
        return KELP_ERR_PARSE;
    }
    /* zero-padded or cut to one 32-byte frame, as Goby does */
    uint8_t f[KELP_REMUS_FRAME_LEN] = {0};
    memcpy(f, m->data, m->len < sizeof f ? m->len : sizeof f);
    static const kelp_remus_kind want[KELP_REMUS_NVARS] = {KELP_REMUS_STATE, KELP_REMUS_RANGER, KELP_REMUS_REDIRECT,
                                                         KELP_REMUS_OASIS, KELP_REMUS_OASIS};
    /* the Alert ids are in no source read: those frames are taken as they come, as Goby does */
    bool alert = kind == KELP_REMUS_ALERT_VAR || kind == KELP_REMUS_ALERT2_VAR;
    if (m->len == 0 || (!alert && kelp_remus_identify(f, sizeof f) != want[kind])) {
        t->refused++;
        warnf(t, sink, "%s: the frame is not a REMUS %s message", t->cfg.in_var[kind], KIND_NAME[kind]);
        return KELP_ERR_PARSE;
    }
    t->received[kind]++;
    const kelp_dccl_modem_entry *e = lookup(t->cfg.geo, m->src);
    char idname[16];
    (void)kelp_util_snprintf(idname, sizeof idname, "%d", m->src);
    contact c = {m->src, e ? e->name : idname, e ? e->type : "unknown_type", 0, 0, 0, 0, 0};
    if (kind == KELP_REMUS_STATE_VAR) {
        kelp_remus_state s;
        if (kelp_remus_state_decode(f, sizeof f, &s) < 0) return KELP_ERR_PARSE; /* cannot happen */
        c.lat = kelp_remus_latlon_decode(s.lat);
        c.lon = kelp_remus_latlon_decode(s.lon);
        c.hdg = kelp_remus_heading_decode(s.heading);
        c.depth = kelp_remus_depth_decode(s.depth);
        c.spd = kelp_remus_velocity_decode(s.est_velocity);
        double g, p, o;
        kelp_remus_gfi_pitch_oil_decode(s.gfi_pitch_oil, &g, &p, &o);
        char *extra = t->work.in.extra;
        int n = kelp_util_snprintf(extra, sizeof t->work.in.extra,
                         ",GoalLatitude=%.17g,GoalLongitude=%.17g,Batterypercent=%u,GFI=%.17g,Pitch=%.17g,Oil=%.17g",
                         kelp_remus_latlon_decode(s.lat_goal), kelp_remus_latlon_decode(s.lon_goal),
                         (unsigned)s.battery_percent, g, p, o);
        publish_contact(t, &c, (n > 0 && (size_t)n < sizeof t->work.in.extra) ? extra : NULL, now, sink);
    } else if (kind == KELP_REMUS_RANGER_VAR) {
        kelp_remus_ranger r;
        if (kelp_remus_ranger_decode(f, sizeof f, &r) < 0) return KELP_ERR_PARSE; /* cannot happen */
        c.lat = r.lat, c.lon = r.lon, c.spd = r.speed, c.hdg = r.heading, c.depth = r.depth;
        publish_contact(t, &c, NULL, now, sink);
    } else {
        static const char *const out[KELP_REMUS_NVARS] = {NULL, NULL, "CCL_REDIRECT_IN", "CCL_ALERT_IN", "CCL_ALERT2_IN"};
        char *txt = t->work.in.text;
        sb b = {txt, sizeof t->work.in.text, 0, false};
        if (kind == KELP_REMUS_REDIRECT_VAR) redirect_text(f, m->src, now, &b);
        else alert_text(f, m->src, kind == KELP_REMUS_ALERT2_VAR, &b);
        if (!b.bad) sink->publish(sink->ctx, out[kind], true, txt, 0);
    }
    return 1;
}

/* a number from key=value text (MOOSValFromString); absent or not a number -> 0 */
static double kv_num(const char *s, const char *key)
{
    char v[64];
    double d = 0;
    if (kelp_kv_get(s, ',', key, v, sizeof v) != 1 || kelp_util_parse_double(v, strlen(v), &d) != KELP_OK || !isfinite(d))
        return 0;
    return d;
}

static uint8_t byte_of(double v)
{
    return (uint8_t)((v > 0 && v < 256) ? (unsigned)v : 0);
}

/* OUTGOING_COMMAND: MessageType=CCL_REDIRECT,... -> a Redirect on mdat_redirect_out */
static int outgoing_command(kelp_remus_codec *t, const char *s, const kelp_field_sink *sink)
{
    char v[64];
    if (!s || kelp_kv_get(s, ',', "MessageType", v, sizeof v) != 1 || !kelp_util_strieq(v, "CCL_REDIRECT")) return 0;
    kelp_remus_redirect *r = &t->work.out.redirect;
    memset(r, 0, sizeof *r);
    r->lat = kv_num(s, "Latitude");
    r->lon = kv_num(s, "Longitude");
    if (kelp_kv_get(s, ',', "SpeedDepthFlags", v, sizeof v) == 1) {
        const char *h = (v[0] == '0' && (v[1] == 'x' || v[1] == 'X')) ? v + 2 : v;
        unsigned x = 0;
        for (size_t i = 0; h[i] && kelp_util_hex_digit(h[i]) >= 0; i++) x = (x << 4 | (unsigned)kelp_util_hex_digit(h[i])) & 0xFFu;
        r->speed_depth_flags = (uint8_t)x;
    }
    r->transit_depth = kv_num(s, "TransitDepth");
    r->transit_speed = kv_num(s, "TransitSpeed");
    r->transit_command = byte_of(kv_num(s, "TransitCommand"));
    r->survey_depth = kv_num(s, "SurveyDepth");
    r->survey_speed = kv_num(s, "SurveySpeed");
    r->survey_command = byte_of(kv_num(s, "SurveyCommand"));
    r->rows = byte_of(kv_num(s, "NumberOfRows"));
    r->row_length = kv_num(s, "RowLength");
    r->row_spacing_0 = kv_num(s, "RowSpacing0");
    r->row_spacing_1 = kv_num(s, "RowSpacing1");
    r->row_heading = kv_num(s, "RowHeading");
    r->start_lat = kv_num(s, "StartLatitude");
    r->start_lon = kv_num(s, "StartLongitude");
    double dest = kv_num(s, "DestinationPlatformId");
    kelp_acomms_msg *m = &t->work.out.msg;
    memset(m, 0, sizeof *m);
    m->src = t->my_id;
    m->dest = (dest >= 0 && dest <= 31) ? (int)dest : 0;
    if (kelp_remus_redirect_encode(r, m->data, sizeof m->data, &m->len) < 0) return 0; /* cannot happen */
    char *buf = t->work.out.text;
    if (kelp_acomms_print_data_bare(m, buf, sizeof t->work.out.text, NULL) < 0) return 0;
    sink->publish(sink->ctx, t->cfg.out_var[KELP_REMUS_REDIRECT_VAR], true, buf, 0);
    return 1;
}

int kelp_remus_codec_mail(kelp_remus_codec *t, const char *var, bool is_string, const char *sval, double dval,
                          kelp_time now, const kelp_field_sink *sink)
{
    if (kelp_util_strieq(var, "OUTGOING_COMMAND")) return is_string ? outgoing_command(t, sval, sink) : 0;
    for (int k = 0; k < KELP_REMUS_NVARS; k++)
        if (kelp_util_strieq(var, t->cfg.in_var[k])) return is_string ? incoming(t, k, sval, now, sink) : 0;
    if (kelp_util_strieq(var, "MODEM_ID")) {
        double v = dval;
        if (is_string && (!sval || kelp_util_parse_double(sval, strlen(sval), &v) != KELP_OK)) v = NAN;
        if (!isfinite(v) || v < 0 || v > 31) return 0;
        t->my_id = (int)v;
        return 1;
    }
    for (int k = 0; k < KELP_REMUS_NNAV; k++)
        if (kelp_util_strieq(var, NAV_VAR[k])) {
            if (is_string || !isfinite(dval)) return 0;
            t->nav[k] = dval;
            t->have[k] = true;
            return 1;
        }
    return 0;
}

int kelp_remus_codec_iterate(kelp_remus_codec *t, kelp_time now, const kelp_field_sink *sink)
{
    if (!t->cfg.create_status) return 0;
    for (int k = 0; k < KELP_REMUS_NNAV; k++)
        if (!t->have[k]) return 0;
    if (t->last_status >= 0 && now - t->last_status < t->cfg.status_interval) return 0;
    double lat = 0, lon = 0;
    kelp_dccl_geo_local2latlon(t->cfg.geo, t->nav[KELP_REMUS_NAV_X], t->nav[KELP_REMUS_NAV_Y], &lat, &lon);
    kelp_remus_state s;
    kelp_remus_state_from_nav(&s, lat, lon, (int64_t)floor(now), t->nav[KELP_REMUS_NAV_HEADING],
                              t->nav[KELP_REMUS_NAV_DEPTH], t->nav[KELP_REMUS_NAV_SPEED]);
    kelp_acomms_msg *m = &t->work.out.msg;
    memset(m, 0, sizeof *m);
    m->src = t->my_id;
    m->dest = 0;
    m->len = KELP_REMUS_FRAME_LEN;
    if (kelp_remus_state_encode(&s, m->data, sizeof m->data, NULL) < 0) return 0; /* cannot happen */
    char *buf = t->work.out.text;
    if (kelp_acomms_print_data_bare(m, buf, sizeof t->work.out.text, NULL) < 0) return 0;
    sink->publish(sink->ctx, t->cfg.out_var[KELP_REMUS_STATE_VAR], true, buf, 0);
    t->last_status = now;
    t->sent++;
    return 1;
}
