/* Minimal Cortex-M4 image used only to measure the linked size of libkelp_core
 * (make firmware). The whole archive is linked with --whole-archive. */
#include <kelp/err.h>

int main(void);

int main(void)
{
    volatile int rc = 0;
    return kelp_err_str(rc)[0] == 'o' ? 0 : 1;
}
