/* pAcommsHandler: see handler.c. */
#include "handler.h"

int main(int argc, char **argv)
{
    handler *h = handler_new();
    if (!h) return 1;
    int rc = kelp_app_run(argc, argv, &pacomms_def, h);
    handler_free(h);
    return rc;
}
