/* Tests of the kelp_diag error path: the code always, the message only when compiled in. */
#ifndef KELP_CHECK_DIAG_H
#define KELP_CHECK_DIAG_H
#include <check.h>
#include <kelp/err.h>

#include <string.h>

#ifdef KELP_NO_ERRMSG
#define ck_diag_msg(d, s) ((void)(d), (void)(s))
#define ck_diag_has(d, s) ((void)(d), (void)(s))
#else
/** The diag's message is s. */
#define ck_diag_msg(d, s) ck_assert_str_eq(kelp_diag_text(d), (s))
/** The diag's message contains s. */
#define ck_diag_has(d, s) ck_assert_ptr_nonnull(strstr(kelp_diag_text(d), (s)))
#endif
/** The diag records a failure with code c and message s. */
#define ck_diag(d, c, s)                                                                                                \
    do {                                                                                                                \
        ck_assert_int_eq((d)->code, (c));                                                                               \
        ck_diag_msg(d, s);                                                                                              \
    } while (0)

#endif
