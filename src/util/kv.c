/* kelp key=value lists. */
#include <string.h>
#include <kelp/kv.h>
#include <kelp/mission.h>

static bool ws(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

int kelp_kv_next(const char *s, char sep, size_t *pos, const char **key, size_t *klen, const char **val, size_t *vlen)
{
    return kelp_kv_next_n(s, strlen(s), sep, pos, key, klen, val, vlen);
}

int kelp_kv_next_n(const char *s, size_t n, char sep, size_t *pos, const char **key, size_t *klen, const char **val,
                   size_t *vlen)
{
    while (*pos < n) {
        size_t a = *pos, e = a;
        while (e < n && s[e] != sep) e++;
        *pos = e < n ? e + 1 : e;
        while (a < e && ws(s[a])) a++;
        size_t z = e;
        while (z > a && ws(s[z - 1])) z--;
        if (z == a) continue; /* empty item */
        const char *eq = memchr(s + a, '=', z - a);
        if (!eq) return KELP_ERR_PARSE;
        size_t k0 = a, k1 = (size_t)(eq - s), v0 = k1 + 1, v1 = z;
        while (k1 > k0 && ws(s[k1 - 1])) k1--;
        while (v0 < v1 && ws(s[v0])) v0++;
        *key = s + k0;
        *klen = k1 - k0;
        *val = s + v0;
        *vlen = v1 - v0;
        return 1;
    }
    return 0;
}

int kelp_kv_get(const char *s, char sep, const char *key, char *out, size_t cap)
{
    size_t pos = 0;
    const char *k, *v;
    size_t kl, vl;
    int rc;
    while ((rc = kelp_kv_next(s, sep, &pos, &k, &kl, &v, &vl)) != 0) {
        if (rc < 0) continue; /* skip malformed items; others may still hold the key */
        if (kelp_util_strieq_n(k, kl, key)) {
            if (vl + 1 > cap) return KELP_ERR_NOSPACE;
            memcpy(out, v, vl);
            out[vl] = 0;
            return 1;
        }
    }
    return 0;
}
