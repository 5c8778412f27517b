/* kelp: Check runner. The suite list is generated from the test sources
 * (see the Makefile), so each test file only defines Suite *kelp_<x>_suite(void). */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>

#define X(fn) Suite *fn(void);
#include KELP_SUITES
#undef X

int main(void)
{
    SRunner *sr = NULL;
    int nsuites = 0;
#define X(fn) do { if (!sr) sr = srunner_create(fn()); else srunner_add_suite(sr, fn()); nsuites++; } while (0);
#include KELP_SUITES
#undef X
    if (!sr) {
        printf("%s: no suites\n", KELP_RUNNER_NAME);
        return 0;
    }
    srunner_run_all(sr, CK_ENV);
    int ntests = srunner_ntests_run(sr);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    if (ntests == 0) {
        /* Check prints "Checks: 0" and exits 0 when a filter selects nothing; that is not a pass. */
        fprintf(stderr, "%s: no test ran\n", KELP_RUNNER_NAME);
        return 2;
    }
    printf("%s: %d suites, %d checks, %d failed\n", KELP_RUNNER_NAME, nsuites, ntests, failed);
    return failed ? 1 : 0;
}
