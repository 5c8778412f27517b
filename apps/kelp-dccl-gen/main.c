/* kelp-dccl-gen: DCCL message XML -> C const tables for firmware. */
#include "../../src/dccl/edge/programs.h"

int main(int argc, char **argv)
{
    return kelp_dccl_gen_main(argc, argv);
}
