/* Fuzz: the mission-file parser (count pass, store pass, lookups, value copies), the
 * key=value list reader and the bridge route parsers. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <kelp/mission.h>
#include <kelp/kv.h>
#include <kelp/bridge.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size ? size : 1);
    memcpy(text, data, size);
    kelp_mission m;
    static kelp_mission_node nodes[512];
    int rc0 = kelp_mission_parse(&m, text, size, NULL, 0);
    if (rc0 == 0) {
        size_t need = m.nnodes;
        int rc = kelp_mission_parse(&m, text, size, nodes, need < 512 ? need : 512);
        if (need <= 512 && rc != 0) abort(); /* measuring and storing must agree */
        if (rc == 0) {
            char buf[256];
            double d;
            bool b;
            for (size_t i = 0; i < m.nnodes; i++) {
                if (nodes[i].val + nodes[i].vlen > text + size || nodes[i].key + nodes[i].klen > text + size) abort();
                (void)kelp_mission_copy(&nodes[i], buf, sizeof buf);
                (void)kelp_mission_double(&nodes[i], &d);
                (void)kelp_mission_bool(&nodes[i], &b);
            }
            (void)kelp_mission_block(&m, "ProcessConfig", "ANTLER");
            for (int i = kelp_mission_next(&m, -1, -1, NULL); i >= 0; i = kelp_mission_next(&m, -1, i, NULL)) {
            }
        }
    } else if (rc0 == KELP_ERR_PARSE && (m.diag.code != KELP_ERR_PARSE || m.diag.line < 1 || !kelp_diag_text(&m.diag)[0])) {
        abort(); /* every parse error has a line and a reason */
    }
    /* NUL-terminated copies for the string APIs */
    char *z = malloc(size + 1);
    memcpy(z, data, size);
    z[size] = 0;
    char out[64];
    (void)kelp_kv_get(z, ',', "src_var", out, sizeof out);
    kelp_bridge_route r[16];
    size_t nr;
    kelp_diag why;
    kelp_diag_clear(&why);
    (void)kelp_bridge_parse_share(z, r, 16, &nr, &why);
    (void)kelp_bridge_parse_register(z, r, &why);
    free(z);
    free(text);
    return 0;
}
