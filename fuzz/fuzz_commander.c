/* Fuzz the kelp-commander save-file reader (kelp_commander_load) and, on what loads, save and send.
 * The first half of the input (up to a NUL) is the save file, against a fixed message set. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/commander.h>
#include <kelp/edge/dccl.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char XML[] =
    "<?xml version=\"1.0\"?><message_set><message><name>G</name><id>1</id><trigger>publish</trigger>"
    "<trigger_var mandatory_content=\"C=G\">OUT</trigger_var><size>32</size>"
    "<header><dest_id><name>Destination</name></dest_id><time><name>When</name></time></header><layout>"
    "<static><name>type</name><value>goto</value></static><int><name>x</name><max>100</max><min>0</min></int>"
    "<float><name>Latitude</name><max>90</max><min>-90</min><precision>5</precision></float>"
    "<float><name>Longitude</name><max>180</max><min>-180</min><precision>5</precision></float>"
    "<bool><name>on</name></bool><string><src_var>S</src_var><name>s</name><max_length>6</max_length></string>"
    "<enum><name>e</name><value>a</value><value>b</value></enum>"
    "<int><name>arr</name><max>9</max><min>0</min><array_length>3</array_length></int>"
    "<hex><name>h</name><num_bytes>2</num_bytes></hex></layout></message></message_set>";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_dccl_loaded ld;
    static bool ready;
    static kelp_dccl_builtin geo;
    static kelp_dccl_modem_entry modems[2];
    static kelp_commander c;
    static char text[65536], out[65536];
    static kelp_commander_pub pubs[KELP_CMDR_MAX_PUBS];
    if (!ready) {
        kelp_dccl_loaded_init(&ld);
        if (kelp_dccl_load_buffer(&ld, "f.xml", XML, sizeof XML - 1, NULL, NULL) != 0) abort();
        kelp_dccl_builtin_init(&geo, modems, 2);
        kelp_dccl_builtin_set_origin(&geo, 42.0, -70.0);
        ready = true;
    }
    if (size >= sizeof text) size = sizeof text - 1;
    memcpy(text, data, size);
    text[size] = 0;
    kelp_commander_init(&c, &ld.set, &geo);
    c.force_xy_only = size & 1;
    size_t n;
    (void)kelp_commander_load(&c, text, NULL);
    if (kelp_commander_save(&c, out, sizeof out, &n) == 0 && strlen(out) != n) abort();
    for (unsigned i = 0; i < c.n_open; i++) (void)kelp_commander_send(&c, i, 1.7e9, pubs, KELP_CMDR_MAX_PUBS, &n, NULL);
    (void)kelp_commander_ack_note(&c, true, text, 1.7e9, out, sizeof out);
    return 0;
}
