/* kelp DCCL: private declarations shared by the files of src/dccl (never installed). */
#ifndef KELP_DCCL_INT_H
#define KELP_DCCL_INT_H

#include <stdlib.h>
#include <kelp/dccl.h>

/* Hosted builds use the C library's strtod/snprintf, which give the exact
 * conversions libstdc++ (and therefore Goby) gives. newlib's versions allocate
 * (_Balloc), so firmware builds use the approximate conversions in value.c. */
#ifndef KELP_DCCL_LIBC_NUM
#if defined(_NEWLIB_VERSION)
#define KELP_DCCL_LIBC_NUM 0
#else
#define KELP_DCCL_LIBC_NUM 1
#endif
#endif

/** Buffer that holds any double's string form. */
#define DCCL_NUMBUF 400

/** 10^p as pow(10.0, p) gives it (exact table for |p| <= 22). */
double dccl_pow10(int p);
/** "%.*f" and "%.*g" (prec < 0 means %g with 6). Return length (cut to cap-1). */
size_t dccl_fmt_fixed(double d, int prec, char *out, size_t cap);
size_t dccl_fmt_g(double d, int prec, char *out, size_t cap);
size_t dccl_fmt_long(int64_t l, char *out, size_t cap);
/** v becomes the string form of the double d shown with precision p (as kelp_dccl_val_to_str
 *  of that double, then kelp_dccl_val_set_strn), formatted in place in v->s. */
void dccl_val_set_double_str(kelp_dccl_val *v, double d, int p);
/** The string form of v (kelp_dccl_val_to_str, cut to KELP_DCCL_MAX_STRLEN) in v->s itself,
 *  *n its length: for an algorithm that replaces v with a string made from it (v is not a
 *  valid value of its kind until it is replaced). */
char *dccl_val_str_inplace(kelp_dccl_val *v, size_t *n);
/** Case-insensitive equality of (a, an) and NUL-terminated b. */
bool dccl_ieq(const char *a, size_t an, const char *b);
/** Apply a list of algorithm calls to v. `vals` gives the referenced values (a
 *  resolver is used by the encoder, which sees earlier fields pre-rounded). */
typedef const kelp_dccl_val *(*dccl_ref_fn)(void *ctx, unsigned field, unsigned element);
void dccl_apply_algs(const kelp_dccl_algs *algs, const kelp_dccl_algcall *calls, unsigned n_calls, kelp_dccl_val *v,
                     unsigned element, dccl_ref_fn ref, void *ref_ctx);

#endif
