/* Hexadecimal digits, byte strings, big-endian integers and the name hash. */
#include <kelp/util.h>

uint32_t kelp_util_hash(const char *s, size_t n)
{
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < n; i++) h = (h ^ (uint8_t)s[i]) * 16777619u;
    return h;
}

int kelp_util_hex_digit(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

int kelp_util_hex_decode(const char *hex, size_t n, uint8_t *out, size_t cap, size_t *len)
{
    if (n % 2) return KELP_ERR_PARSE;
    if (n / 2 > cap) return KELP_ERR_NOSPACE;
    for (size_t i = 0; i < n; i += 2) {
        int a = kelp_util_hex_digit(hex[i]), b = kelp_util_hex_digit(hex[i + 1]);
        if (a < 0 || b < 0) return KELP_ERR_PARSE;
        out[i / 2] = (uint8_t)(a * 16 + b);
    }
    *len = n / 2;
    return KELP_OK;
}

void kelp_util_be_put32(uint8_t *p, uint32_t v)
{
    for (int i = 3; i >= 0; i--, v >>= 8) p[i] = (uint8_t)v;
}

void kelp_util_be_put64(uint8_t *p, uint64_t v)
{
    for (int i = 7; i >= 0; i--, v >>= 8) p[i] = (uint8_t)v;
}

uint32_t kelp_util_be_get32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v = v << 8 | p[i];
    return v;
}

uint64_t kelp_util_be_get64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v = v << 8 | p[i];
    return v;
}
