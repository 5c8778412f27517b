/* kelp bus: private declarations (not installed). */
#ifndef KELP_BUS_INT_H
#define KELP_BUS_INT_H
#include <kelp/bus.h>

/** Encode a var from its parts; `val`/`vlen` is the string or binary value (ignored for
 *  doubles). Lets a publisher encode without building a full kelp_var. */
int kelp_var_encode_parts(double time, const char *name, const char *source, const char *source_aux,
                          const char *community, kelp_var_kind kind, double dval, const char *val, size_t vlen,
                          uint8_t flags, uint8_t *buf, size_t cap, size_t *len);

/** A sync request for one pattern, encoded from its parts (as kelp_bus_sync_req_encode of a
 *  kelp_sync_req holding them, without building one). */
int kelp_sync_req_encode_one(double time, const char *requester, const char *community, const char *reply_channel,
                             const char *pattern, uint8_t *buf, size_t cap, size_t *len);

/** A renaming list (kelp_bridge_parse_rename syntax) read into caller storage: the i-th
 *  variable name at src + i * stride, its alias at alias + i * stride (written only when the
 *  line has aliases); src and alias NULL: check and count only. *ns names, *na aliases (0 or
 *  *ns), *glob set when a name is a glob. @return 0, or KELP_ERR_PARSE with the reason in d. */
int kelp_bridge_rename_list(const char *line, char *src, char *alias, size_t stride, int *ns, int *na, bool *glob,
                            kelp_diag *d);
#endif
