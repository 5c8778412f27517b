/* kelp LCM log events: parse and resynchronise (core, see kelp/lcmlog.h). */
#include <string.h>
#include <kelp/lcmlog.h>

static uint64_t be(const uint8_t *p, unsigned n)
{
    uint64_t v = 0;
    for (unsigned i = 0; i < n; i++) v = v << 8 | p[i];
    return v;
}

static void put_be(uint8_t *p, uint64_t v, unsigned n)
{
    for (unsigned i = n; i-- > 0; v >>= 8) p[i] = (uint8_t)v;
}

int kelp_lcmlog_parse(const uint8_t *buf, size_t len, size_t max_data, kelp_lcmlog_event *ev, size_t *used)
{
    if (!buf || !ev || !used) return KELP_ERR_ARG;
    if (len < 4) {
        *used = KELP_LCMLOG_HDR_LEN;
        return KELP_ERR_PARTIAL;
    }
    if (be(buf, 4) != KELP_LCMLOG_SYNC) return KELP_ERR_PARSE;
    if (len < KELP_LCMLOG_HDR_LEN) {
        *used = KELP_LCMLOG_HDR_LEN;
        return KELP_ERR_PARTIAL;
    }
    uint64_t cl = be(buf + 20, 4), dl = be(buf + 24, 4);
    if (cl > KELP_LCMLOG_MAX_CHANNEL || dl > max_data) return KELP_ERR_PARSE;
    size_t need = KELP_LCMLOG_HDR_LEN + (size_t)cl + (size_t)dl;
    if (len < need) {
        *used = need;
        return KELP_ERR_PARTIAL;
    }
    ev->eventnum = be(buf + 4, 8);
    ev->timestamp = (int64_t)be(buf + 12, 8);
    ev->channel = buf + KELP_LCMLOG_HDR_LEN;
    ev->channel_len = (size_t)cl;
    ev->data = buf + KELP_LCMLOG_HDR_LEN + cl;
    ev->data_len = (size_t)dl;
    *used = need;
    return KELP_OK;
}

size_t kelp_lcmlog_resync(const uint8_t *buf, size_t len, size_t from)
{
    static const uint8_t sync[4] = { 0xED, 0xA1, 0xDA, 0x01 };
    if (!buf || len < 4) return from < len ? from : len;
    for (size_t i = from; i + 4 <= len; i++)
        if (buf[i] == sync[0] && memcmp(buf + i, sync, 4) == 0) return i;
    size_t tail = len - 3;
    return tail > from ? tail : from;
}

void kelp_lcmlog_header(uint64_t eventnum, int64_t timestamp, size_t channel_len, size_t data_len,
                        uint8_t out[KELP_LCMLOG_HDR_LEN])
{
    put_be(out, KELP_LCMLOG_SYNC, 4);
    put_be(out + 4, eventnum, 8);
    put_be(out + 12, (uint64_t)timestamp, 8);
    put_be(out + 20, channel_len, 4);
    put_be(out + 24, data_len, 4);
}
