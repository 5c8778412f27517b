/* A byte string as a JSON string literal. */
#include <kelp/util.h>

size_t kelp_util_json_quote(char *buf, size_t cap, const char *s, size_t n)
{
    static const char hex[] = "0123456789abcdef";
    size_t o = 0;
#define PUT(ch)                                                                                                        \
    do {                                                                                                               \
        if (o + 1 < cap) buf[o] = (ch);                                                                                \
        o++;                                                                                                           \
    } while (0)
    PUT('"');
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"' || c == '\\') {
            PUT('\\');
            PUT((char)c);
        } else if (c < 0x20 || c >= 0x7f) {
            PUT('\\');
            PUT('u');
            PUT('0');
            PUT('0');
            PUT(hex[c >> 4]);
            PUT(hex[c & 15]);
        } else {
            PUT((char)c);
        }
    }
    PUT('"');
#undef PUT
    if (cap) buf[o < cap ? o : cap - 1] = 0;
    return o;
}
