/* The ht_* helm test harness (defined in check_helm.c: one helm, a post log of the last
 * iteration) and the helpers the behaviour suites share. */
#ifndef KELP_CHECK_HT_H
#define KELP_CHECK_HT_H

#include <check.h>
#include <stdbool.h>
#include <kelp/helm.h>

typedef struct ht_post {
    char var[KELP_MAX_NAME];
    bool is_str;
    char sval[KELP_HELM_MAX_SVAL];
    double dval;
    unsigned long iter;
} ht_post;

kelp_helm *ht_helm(void);
kelp_helm *ht_setup(const char *domain, const kelp_bhv_ops *const *types);
void ht_load(const char *bhv);
int ht_load_rc(const char *bhv);
void ht_iter(double now);
const ht_post *ht_last(const char *var);
unsigned ht_count(const char *var);
bool ht_has_str(const char *var, const char *val);
double ht_num(const char *var);
bool ht_has_sub(const char *var, const char *sub);

/* the behaviour of that name in the harness's helm (the test fails without it) */
static inline kelp_bhv *ht_find(const char *name)
{
    kelp_bhv *b = kelp_helm_find(ht_helm(), name);
    ck_assert_msg(b != NULL, "no behaviour %s", name);
    return b;
}

/* a two-variable function's value at the domain indices (a, b) */
static inline double ht_eval2(const kelp_ivp_func *f, uint32_t a, uint32_t b)
{
    uint32_t ix[2] = {a, b};
    double v = -1;
    ck_assert_int_eq(kelp_ivp_func_eval(f, ix, &v), 0);
    return v;
}

#endif
