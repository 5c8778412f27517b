/* kelp-acomms-replay (private). */
#ifndef KELP_ACOMMS_REPLAY_H
#define KELP_ACOMMS_REPLAY_H
int replay_main(int argc, char **argv);
#endif
