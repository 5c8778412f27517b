/* kelp: status code text. */
#include <stdarg.h>
#include <stddef.h>
#include <kelp/err.h>
#include <kelp/util.h>

const char *kelp_err_str(int code)
{
    switch (code) {
    case KELP_OK: return "ok";
    case KELP_ERR_ARG: return "invalid argument";
    case KELP_ERR_NOSPACE: return "storage too small";
    case KELP_ERR_PARSE: return "parse error";
    case KELP_ERR_RANGE: return "value out of range";
    case KELP_ERR_NOTFOUND: return "not found";
    case KELP_ERR_PARTIAL: return "more input needed";
    case KELP_ERR_CHECKSUM: return "checksum mismatch";
    case KELP_ERR_DEFMISMATCH: return "definition fingerprint mismatch";
    case KELP_ERR_IO: return "I/O error";
    case KELP_ERR_TIMEOUT: return "timed out";
    case KELP_ERR_STATE: return "invalid state";
    case KELP_ERR_UNSUPPORTED: return "unsupported";
    case KELP_ERR_TRUNCATED: return "input truncated";
    case KELP_ERR_EXISTS: return "already exists";
    case KELP_ERR_CRYPTO: return "crypto failure";
    case KELP_ERR_AUTH: return "authentication failed";
    case KELP_ERR_EMPTY: return "empty";
    case KELP_ERR_INFEASIBLE: return "infeasible";
    case KELP_ERR_REPLAY: return "replayed or stale";
    case KELP_ERR_DENIED: return "not allowed";
    default: return "unknown error";
    }
}

void kelp_diag_clear(kelp_diag *d)
{
    if (!d) return;
    d->code = KELP_OK;
    d->line = 0;
    d->col = 0;
#ifndef KELP_NO_ERRMSG
    d->msg[0] = '\0';
#endif
}

int kelp_diag_set(kelp_diag *d, int code, const char *msg)
{
    if (!d || d->code != KELP_OK || code == KELP_OK) return code;
    d->code = code;
#ifndef KELP_NO_ERRMSG
    size_t i = 0;
    if (msg)
        for (; msg[i] && i + 1 < sizeof d->msg; i++) d->msg[i] = msg[i];
    d->msg[i] = '\0';
#else
    (void)msg;
#endif
    return code;
}

int kelp_diag_setf(kelp_diag *d, int code, const char *fmt, ...)
{
    if (!d || d->code != KELP_OK || code == KELP_OK) return code;
    d->code = code;
#ifndef KELP_NO_ERRMSG
    va_list ap;
    va_start(ap, fmt);
    (void)kelp_util_vsnprintf(d->msg, sizeof d->msg, fmt, ap);
    va_end(ap);
#else
    (void)fmt;
#endif
    return code;
}

int kelp_diag_where(kelp_diag *d, int line, int col)
{
    if (!d || d->code == KELP_OK) return KELP_OK;
    if (d->line == 0) d->line = line;
    if (d->col == 0) d->col = col;
    return d->code;
}

const char *kelp_diag_text(const kelp_diag *d)
{
    if (!d || d->code == KELP_OK) return "";
#ifndef KELP_NO_ERRMSG
    if (d->msg[0]) return d->msg;
#endif
    return kelp_err_str(d->code);
}
