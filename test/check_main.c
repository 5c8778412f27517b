/* kelp: Check runner. The suite list is generated from the test sources
 * (see the Makefile), so each test file only defines Suite *kelp_<x>_suite(void). */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define X(fn) Suite *fn(void);
#include KELP_SUITES
#undef X

/* check_<runner>            every suite, in one run
 * check_<runner> --count    how many suites there are
 * check_<runner> --suite N  only the N-th suite (0-based; scripts/run-tests.sh runs them side by
 *                           side: one process per suite keeps each fork small, which under ASan
 *                           is most of the time a single run of every suite takes) */
int main(int argc, char **argv)
{
    SRunner *sr = NULL;
    int nsuites = 0, only = -1;
    if (argc == 2 && !strcmp(argv[1], "--count")) {
#define X(fn) nsuites++;
#include KELP_SUITES
#undef X
        printf("%d\n", nsuites);
        return 0;
    }
    if (argc == 3 && !strcmp(argv[1], "--suite")) {
        char *end;
        long v = strtol(argv[2], &end, 10);
        if (*end || v < 0 || v > 100000) {
            fprintf(stderr, "%s: --suite takes a suite number\n", KELP_RUNNER_NAME);
            return 2;
        }
        only = (int)v;
    } else if (argc != 1) {
        fprintf(stderr, "usage: %s [--count | --suite N]\n", KELP_RUNNER_NAME);
        return 2;
    }
#define X(fn) do { if (only < 0 || nsuites == only) { if (!sr) sr = srunner_create(fn()); else srunner_add_suite(sr, fn()); } nsuites++; } while (0);
#include KELP_SUITES
#undef X
    if (!sr) {
        printf("%s: no suites\n", KELP_RUNNER_NAME);
        return only < 0 ? 0 : 2;
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
    printf("%s: %d suites, %d checks, %d failed\n", KELP_RUNNER_NAME, only < 0 ? nsuites : 1, ntests, failed);
    return failed ? 1 : 0;
}
