/* kelp-acomms-replay: see replay.c and --help. */
#include "replay.h"

int main(int argc, char **argv)
{
    return replay_main(argc, argv);
}
