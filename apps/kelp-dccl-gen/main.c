/* kelp-dccl-gen: DCCL message XML -> C const tables for firmware. */
#include <kelp/dccl_edge.h>

int main(int argc, char **argv)
{
    return kelp_dccl_gen_main(argc, argv);
}
