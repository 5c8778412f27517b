/* pAcommsHandler: the Goby 1.1 acoustic communications handler over kelp.
 *
 * The logic is the core state machine kelp_acomms_handler (include/kelp/acomms.h, 4b; DCCL
 * encode on trigger/time, decode and publish on receipt, priority queues, TDMA MAC, WHOI
 * Micro-Modem driver).  This app reads the ProcessConfig block, loads the DCCL message files,
 * and wires the handler to the bus, the modem link (handler.c) and the status report (report.c).
 * DRIVER_NONE runs an ideal in-process channel (see kelp_acomms_node_cfg.loopback_channel). */
#include "handler.h"

static const kelp_app_def pacomms_def = {
    .name = "pAcommsHandler",
    .purpose = "Goby 1.1 acoustic communications: DCCL codec, priority queues, TDMA MAC, WHOI Micro-Modem driver.",
    .textformat = true,
    .params = (const kelp_app_param_info[]){
        { "modem_id", "1", "required: this modem, 1..31 (0 is broadcast)", NULL },
        { "common", "{ log: true log_path: \"./\" verbosity: VERBOSITY_VERBOSE }", "optional: Goby's common block", NULL },
        { "driver_type", "DRIVER_NONE", "or DRIVER_WHOI_MICROMODEM", NULL },
        { "driver_cfg", "{ connection_type: CONNECTION_SERIAL serial_port: \"/dev/ttyS0\" serial_baud: 19200 }",
          "the modem link", NULL },
        { "mac_cfg", "{ type: MAC_NONE }", "or MAC_FIXED_DECENTRALIZED, MAC_AUTO_DECENTRALIZED, MAC_POLLED", NULL },
        { "queue_cfg", "{ message_file { path: \"simple_status.xml\" manipulator: NO_MANIP } }", "DCCL and CCL queues", NULL },
        { "dccl_cfg", "{ message_file { path: \"example1.xml\" manipulator: LOOPBACK } }", "DCCL messages", NULL },
        { "modem_id_lookup_path", "\"modemidlookup.txt\"", "optional: \"id,name,type\" lines", NULL },
        { "tcp_share_enable", "false", "experimental in Goby: not implemented", NULL },
        { "tcp_share_port", "11000", "experimental in Goby: not implemented", NULL },
        { "tcp_share_to_ip", "\"192.168.1.20\"", "repeatable (up to 4); experimental in Goby: not implemented", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<src_var>", "23.5", "every DCCL <src_var>/<moos_var> and <trigger_var> of the message files" },
        { "OUT_<NAME>_HEX_<size>B", "src: 1 dest: 2 data: \"...\"", "ModemDataTransmission to encode and queue"
          " (or <outgoing_hex_moos_var>)" },
        { "<queue.out_pubsub_var>", "data: \"\\002\\002\\003\\004\"", "CCL: ModemDataTransmission to queue" },
        { "ACOMMS_RANGE_COMMAND", "src: 1 dest: 2 type: MODEM_TWO_WAY_PING", "ModemRangingRequest" },
        { "ACOMMS_MAC_CYCLE_UPDATE", "dest: 1 update_type: REPLACE slot { src: 2 dest: 1 }", "MACUpdate" },
        { "ACOMMS_POLLER_UPDATE", "(as ACOMMS_MAC_CYCLE_UPDATE)", NULL },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<publish_var>", "23.5", "DCCL publishes on receipt" },
        { "ACOMMS_INCOMING_DATA", "src: 2 dest: 1 data: \"...\"", "ModemDataTransmission (TextFormat)" },
        { "ACOMMS_OUTGOING_DATA", "src: 1 dest: 2 data: \"...\"", "ModemDataTransmission" },
        { "OUT_<NAME>_HEX_<size>B", "src: 1 dest: 2 data: \"...\"", "on encode" },
        { "IN_<NAME>_HEX_<size>B", "src: 2 dest: 1 data: \"...\"", "on receipt" },
        { "<queue.in_pubsub_var>", "data: \"\\002\\002\\003\\004\"", "CCL, on receipt" },
        { "ACOMMS_ACK", "src: 2 dest: 1 frame: 0", "ModemDataAck" },
        { "ACOMMS_EXPIRE", "src: 1 dest: 2", "ModemDataExpire" },
        { "ACOMMS_QSIZE", "key { type: QUEUE_DCCL id: 14 } size: 3", "QueueSize" },
        { "ACOMMS_RANGE_RESPONSE", "src: 1 dest: 2 one_way_travel_time: 0.35", "ModemRangingReply" },
        { "ACOMMS_NMEA_IN", "$CARXD,2,1,0,1,0102*2C", "every sentence from the modem" },
        { "ACOMMS_NMEA_OUT", "$CCCYC,0,1,2,0,0,1*5B", "every sentence to the modem" },
        { "MODEM_ID", "1", "at start-up; also the common.initializer variables" },
        { "VEHICLE_ID", "1", "at start-up" },
        { "ACOMMS_STATUS_LCM", "(kelp.acomms_status_t)", "LCM structures on their own channels, once a second;"
          " also ACOMMS_{INCOMING,OUTGOING}_DATA_LCM, ACOMMS_{ACK,EXPIRE,QSIZE,RANGE_RESPONSE}_LCM" },
        { NULL, NULL, NULL } },
    .notes = PACOMMS_EXAMPLE,
    .startup = handler_startup,
    .on_mail = handler_mail,
    .iterate = handler_iterate,
    .report = handler_report,
    .shutdown = handler_shutdown,
};

int main(int argc, char **argv)
{
    handler *h = handler_new();
    if (!h) return 1;
    int rc = kelp_app_run(argc, argv, &pacomms_def, h);
    handler_free(h);
    return rc;
}
