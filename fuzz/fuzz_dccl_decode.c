/* Fuzz the DCCL decoder: arbitrary bytes against every message of a set, with
 * and without crypto, then publish the decoded values. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <kelp/edge/dccl.h>

static const char XML[] =
    "<message_set>"
    "<message><name>GoToCommand</name><id>1</id><size>32</size><header><dest_id><name>Destination</name></dest_id></header>"
    "<layout><static><name>type</name><value>goto</value></static><int><name>goto_x</name><max>10000</max><min>0</min></int>"
    "<int><name>goto_y</name><max>10000</max><min>0</min></int><bool><name>lights_on</name></bool>"
    "<string><name>new_instructions</name><max_length>10</max_length></string>"
    "<float><name>goto_speed</name><max>3</max><min>0</min><precision>2</precision></float></layout>"
    "<on_receipt><publish><publish_var>IN</publish_var><all/></publish>"
    "<publish><publish_var>S</publish_var><format>a=%1%,b=%2$-5.2s</format><message_var algorithm=\"to_upper\">new_instructions</message_var>"
    "<message_var>lights_on</message_var></publish></on_receipt></message>"
    "<message><name>ALL</name><size>64</size><header><id>30</id><time><name>when</name></time>"
    "<src_id><name>Node</name></src_id></header><layout>"
    "<int><name>i</name><max>100</max><min>-100</min><array_length>3</array_length><max_delta>2</max_delta></int>"
    "<float><name>f</name><max>100</max><min>-1000</min><max_delta>2</max_delta><precision>3</precision><array_length>2</array_length></float>"
    "<float><name>big</name><max>1e30</max><min>-1e30</min><precision>3</precision></float>"
    "<enum><name>e</name><value>a</value><value>b</value><value>c</value></enum>"
    "<hex><name>h</name><num_bytes>3</num_bytes></hex><bool><name>b</name><array_length>2</array_length></bool>"
    "<string><name>s</name><max_length>7</max_length></string></layout>"
    "<on_receipt><publish><publish_var>ALL</publish_var><all/></publish>"
    "<publish><publish_var>GEO</publish_var><message_var algorithm=\"utm_y2lat:i,modem_id2name,name2modem_id\">f</message_var>"
    "<message_var algorithm=\"angle_-180_180,lat2nmea_lat\">big</message_var><message_var algorithm=\"unix_time2nmea_time\">when</message_var>"
    "<message_var algorithm=\"TSD_to_soundspeed:f:big\">i</message_var></publish></on_receipt></message>"
    "<message><name>REP</name><id>7</id><size>40</size><repeat/><layout>"
    "<int><name>x</name><max>50</max><min>-50</min><max_delta>3</max_delta></int><bool><name>y</name></bool></layout>"
    "<on_receipt><publish><publish_var>R</publish_var><all/></publish></on_receipt></message>"
    "</message_set>";

static kelp_dccl_loaded ld;
static kelp_dccl_mbedtls mb;
static kelp_dccl_alg_entry store[40];
static kelp_dccl_modem_entry modems[4];
static kelp_dccl_algs algs;
static kelp_dccl_builtin bi;
static int ready;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kelp_dccl_val vals[512];
    static kelp_dccl_pub pubs[64];
    kelp_dccl_codec cx;
    size_t i, np;
    unsigned id;
    kelp_dccl_header h;
    if (!ready) {
        kelp_dccl_algs_init(&algs, store, 40);
        kelp_dccl_builtin_init(&bi, modems, 4);
        if (kelp_dccl_algs_add_builtin(&algs, &bi)) abort();
        if (kelp_dccl_builtin_parse_modems(&bi, "1,a,b\n2,c,d\n", 12)) abort();
        kelp_dccl_builtin_set_origin(&bi, 42.35, -70.95);
        kelp_dccl_loaded_init(&ld);
        if (kelp_dccl_load_buffer(&ld, "fuzz.xml", XML, sizeof XML - 1, &algs, NULL)) abort();
        if (kelp_dccl_mbedtls_init(&mb, "fuzz")) abort();
        ready = 1;
    }
    (void)kelp_dccl_peek_id(data, size, &id);
    (void)kelp_dccl_head_read(data, size, 1.7e9, &h);
    for (i = 0; i < ld.set.n; i++) {
        const kelp_dccl_msgdef *d = ld.set.msgs[i];
        int pass;
        for (pass = 0; pass < 2; pass++) {
            kelp_dccl_codec_init(&cx, 3, pass ? &mb.ops : NULL, &algs);
            if (kelp_dccl_decode(&cx, d, data, size, 1.7e9, vals, 512) == 0)
                (void)kelp_dccl_publish_all(&cx, d, vals, 512, pubs, 64, &np);
        }
    }
    return 0;
}
