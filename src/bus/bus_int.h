/* kelp bus: private declarations (not installed). */
#ifndef KELP_BUS_INT_H
#define KELP_BUS_INT_H
#include <kelp/bus.h>

/** Encode a var from its parts; `val`/`vlen` is the string or binary value (ignored for
 *  doubles). Lets a publisher encode without building a full kelp_var. */
int kelp_var_encode_parts(double time, const char *name, const char *source, const char *community,
                          kelp_var_kind kind, double dval, const char *val, size_t vlen, uint8_t flags,
                          uint8_t *buf, size_t cap, size_t *len);
#endif
