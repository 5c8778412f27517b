/* kelp-dccl: encode, decode, publish and inspect Goby 1.1 DCCL messages. */
#include "../../src/dccl/edge/programs.h"

int main(int argc, char **argv)
{
    return kelp_dccl_cli_main(argc, argv);
}
