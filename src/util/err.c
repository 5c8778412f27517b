/* kelp: status code text. */
#include <kelp/err.h>

const char *kelp_strerror(int code)
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
