/* uFldMessageHandler's state machine (src/field/msghandler.c): ufield.md 6.6, 1.2 and the
 * MOOS-IvP 24.8 parameters (aux_info, msg_flag, bad_msg_flag, appcast_trunc_msg). */
#include <check.h>
#include "check_diag.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <kelp/field.h>

#define REC_MAX 64
/* both found, a first */
#define BEFORE(a, b) ck_assert((a) != NULL && (b) != NULL && (a) < (b))

typedef struct rec {
    int n;
    char var[REC_MAX][64];
    char val[REC_MAX][512];
    bool str[REC_MAX];
    double d[REC_MAX];
    char aux[REC_MAX][2 * KELP_MAX_NAME]; /* the MOOS source-aux the app would post it with */
} rec;

static kelp_field_umh h;

static void pub(void *ctx, const char *var, bool is_string, const char *sval, double dval)
{
    rec *r = ctx;
    if (r->n >= REC_MAX) return;
    snprintf(r->var[r->n], sizeof r->var[0], "%s", var);
    if (is_string) snprintf(r->val[r->n], sizeof r->val[0], "%s", sval);
    else snprintf(r->val[r->n], sizeof r->val[0], "%g", dval);
    r->str[r->n] = is_string;
    r->d[r->n] = dval;
    snprintf(r->aux[r->n], sizeof r->aux[0], "%s", h.posting ? h.aux : "");
    r->n++;
}

/* the last publication of var, or -1 */
static int find(const rec *r, const char *var)
{
    for (int i = r->n; i-- > 0;)
        if (!strcmp(r->var[i], var)) return i;
    return -1;
}

static rec r;
static kelp_field_sink sink = { &r, pub, NULL };

static void start(const char *me, bool strict)
{
    kelp_field_umh_cfg c;
    kelp_field_umh_cfg_default(&c, me);
    c.strict = strict;
    kelp_field_umh_init(&h, &c);
    memset(&r, 0, sizeof r);
}

/* bravo, with one parameter of its block */
static void start_with(const char *key, const char *val)
{
    kelp_field_umh_cfg c;
    kelp_diag why = { 0 };
    kelp_field_umh_cfg_default(&c, "bravo");
    ck_assert_int_eq(kelp_field_umh_config(&c, key, val, &why), 1);
    kelp_field_umh_init(&h, &c);
    memset(&r, 0, sizeof r);
}

static int mail(const char *msg, double now)
{
    return kelp_field_umh_mail(&h, "NODE_MESSAGE", true, msg, now, &sink);
}

/* mail msg, which must be taken; what was posted to var (a double as %g) */
static const char *posted(const char *msg, const char *var)
{
    ck_assert_int_eq(mail(msg, 1), 1);
    int i = find(&r, var);
    ck_assert_int_ge(i, 0);
    return r.val[i];
}

/* 6.6.1: a double posted as a double, aux source alpha */
START_TEST(umh_double_posted)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=SPEED,double_val=2.5", 10), 1);
    int i = find(&r, "SPEED");
    ck_assert_int_ge(i, 0);
    ck_assert(!r.str[i]);
    ck_assert_double_eq(r.d[i], 2.5);
    ck_assert_str_eq(h.aux, "alpha");
    ck_assert_uint_eq(h.valid, 1);
    ck_assert_uint_eq(h.invalid + h.rejected, 0);
}
END_TEST

/* 6.6.2: src_var accepted, string_val posted as a string; the seed's "dest_node;bravo" typo */
START_TEST(umh_string_src_var)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node;bravo,src_var=SPEED,string_val=fast", 1), 1);
    int i = find(&r, "SPEED");
    ck_assert_int_ge(i, 0);
    ck_assert(r.str[i]);
    ck_assert_str_eq(r.val[i], "fast");
    /* var_name wins over src_var; dest_name stands for dest_node */
    ck_assert_int_eq(mail("src_node=alpha,src_var=A,dest_name=bravo,var_name=B,string_val=x", 2), 1);
    ck_assert_int_ge(find(&r, "B"), 0);
    ck_assert_int_lt(find(&r, "A"), 0);
}
END_TEST

/* a quoted string_val carries commas; the quotes are removed */
START_TEST(umh_quoted_string)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=abe,dest_node=bravo,var_name=SAY,string_val=\"hold,station\",string_val_quoted=true", 1), 1);
    ck_assert_str_eq(r.val[find(&r, "SAY")], "hold,station");
    ck_assert_int_eq(mail("src_node=abe,dest_node=bravo,var_name=POLY,string_val=\"pts={1,2:3,4}\"", 2), 1);
    ck_assert_str_eq(r.val[find(&r, "POLY")], "pts={1,2:3,4}");
}
END_TEST

/* 6.6.3: group-addressed, posted unless strict */
START_TEST(umh_group_strict)
{
    const char *m = "src_node=alpha,dest_group=redteam,src_var=SPEED,double_val=2.2";
    start("bravo", false);
    ck_assert_int_eq(mail(m, 1), 1);
    ck_assert_int_ge(find(&r, "SPEED"), 0);
    start("bravo", true);
    ck_assert_int_eq(mail(m, 1), KELP_ERR_ARG);
    ck_assert_int_lt(find(&r, "SPEED"), 0);
    ck_assert_uint_eq(h.rejected, 1);
    ck_assert_uint_eq(h.valid, 1); /* 24.8: well formed, then rejected: counted in both */
    ck_assert_str_eq(h.last_rejected.why[0], "group address (strict addressing)");
}
END_TEST

/* 6.6.4: another vehicle's message is rejected, nothing posted */
START_TEST(umh_other_dest_rejected)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=charlie,var_name=SPEED,double_val=1", 1), KELP_ERR_ARG);
    ck_assert_int_lt(find(&r, "SPEED"), 0);
    ck_assert_uint_eq(h.rejected, 1);
    ck_assert_str_eq(h.last_rejected.why[0], "dest_node is not this node");
}
END_TEST

/* 6.6.5: dest_node=all (any case) posted unless strict */
START_TEST(umh_all)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=henry,dest_node=all,var_name=FOOBAR,string_val=74", 1), 1);
    ck_assert_int_eq(mail("src_node=henry,dest_node=ALL,var_name=FOOBAR,string_val=75", 1), 1);
    ck_assert_str_eq(r.val[find(&r, "FOOBAR")], "75");
    start("bravo", true);
    ck_assert_int_eq(mail("src_node=henry,dest_node=all,var_name=FOOBAR,string_val=74", 1), KELP_ERR_ARG);
    ck_assert_uint_eq(h.rejected, 1);
    /* strict still takes its own name */
    ck_assert_int_eq(mail("src_node=henry,dest_node=bravo,var_name=FOOBAR,string_val=74", 1), 1);
}
END_TEST

/* MOOS-IvP 24.8 (MessageHandler::handleMailNodeMessage): dest_node must equal this
 * community as written -- another case is another name, and a colon list is no name (the
 * recorded run: dest_node=Bravo and dest_node=bravo:charlie are rejected) */
START_TEST(umh_colon_list)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=alpha:bravo,var_name=X,double_val=3", 1), KELP_ERR_ARG);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=Bravo,var_name=X,double_val=3", 1), KELP_ERR_ARG);
    ck_assert_int_lt(find(&r, "X"), 0);
    ck_assert_uint_eq(h.rejected, 2);
    ck_assert_uint_eq(h.valid, 2);
}
END_TEST

/* 24.8: an empty string_val is no string (the variable is posted as the double 0); a
 * double_val is read as atof reads it (abc: 0, 2.5x: 2.5); a message with neither value is
 * well formed (posts 0) */
START_TEST(umh_values_as_248)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=E,string_val=", 1), 1);
    int i = find(&r, "E");
    ck_assert(i >= 0 && !r.str[i]);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=D,double_val=abc", 1), 1);
    ck_assert(!r.str[find(&r, "D")]);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=P,double_val=2.5x", 1), 1);
    ck_assert(!r.str[find(&r, "P")]);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=N", 1), 1);
    ck_assert(!r.str[find(&r, "N")]);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=S,string_val=,double_val=4", 1), 1);
    ck_assert_uint_eq(h.valid, 5);
    ck_assert_uint_eq(h.invalid, 0);
}
END_TEST

/* 6.6.7 and 1.2: invalid messages counted with a reason, nothing posted */
static const struct {
    const char *msg, *why;
} invalid[] = {
    { "src_node=alpha,dest_node=bravo,string_val=x", "no var_name" },
    { "dest_node=bravo,var_name=X,string_val=x", "no src_node" },
    { "src_node=alpha,var_name=X,string_val=x", "no dest_node or dest_group" },
    { "src_node=alpha,dest_node=bravo,var_name=X,string_val=x,double_val=2", "both string_val and double_val" },
    { "src_node=alpha,dest_node=bravo,var_name=MY VAR,double_val=1", "var_name is not a variable name" },
    { "src_node=alpha,dest_node=bravo,var_name=NODE_MESSAGE,string_val=a", "var_name NODE_MESSAGE would loop" },
    { "", "no src_node" },
};

START_TEST(umh_invalid)
{
    start("bravo", false);
    ck_assert_int_eq(mail(invalid[_i].msg, 1), KELP_ERR_PARSE);
    ck_assert_uint_eq(h.invalid, 1);
    ck_assert_uint_eq(h.valid + h.rejected, 0);
#ifndef KELP_NO_ERRMSG
    ck_assert_str_eq(h.last_invalid.why[0], invalid[_i].why); /* the diag's text */
#else
    ck_assert_str_eq(h.last_invalid.why[0], kelp_err_str(KELP_ERR_PARSE));
#endif
    ck_assert_str_eq(h.last_invalid.msg[0], invalid[_i].msg);
    ck_assert_int_lt(find(&r, "X"), 0);
    ck_assert_int_eq(r.n, 0);
}
END_TEST

/* a number on NODE_MESSAGE, and other variables */
START_TEST(umh_not_a_string)
{
    start("bravo", false);
    ck_assert_int_eq(kelp_field_umh_mail(&h, "NODE_MESSAGE", false, NULL, 1, &sink), KELP_ERR_PARSE);
    ck_assert_uint_eq(h.invalid, 1);
    ck_assert_int_eq(kelp_field_umh_mail(&h, "NODE_MESSAGE_LOCAL", true, "src_node=a", 1, &sink), 0);
    ck_assert_uint_eq(h.total, 1);
}
END_TEST

/* 6.6.8 and the per-source table: totals per source, last variable and value */
START_TEST(umh_per_source_and_report)
{
    start("james", false);
    /* in time order (a time before the newest seen is a clock step back: docs/ARCHITECTURE.md) */
    for (int i = 0; i < 4; i++) ck_assert_int_eq(mail("src_node=ike,dest_node=all,var_name=FOOBAR,double_val=20.25", 90), 1);
    for (int i = 0; i < 19; i++) {
        if (i < 5) ck_assert_int_eq(mail("src_node=henry,dest_node=all,var_name=FOOBAR,string_val=44", 100 + i), 1);
        ck_assert_int_eq(mail("src_node=gilda,dest_node=all,var_name=FOOBAR,string_val=35", 100 + i), 1);
    }
    ck_assert_uint_eq(h.valid, 28);
    ck_assert_uint_eq(h.nsrc, 3);
    char buf[4096];
    size_t n = kelp_field_umh_report(&h, 120.5, buf, sizeof buf);
    ck_assert_uint_eq(n, strlen(buf));
    /* MOOS-IvP 24.8's report, line for line as the recorded APPCAST shows it */
    ck_assert_ptr_eq(strstr(buf, "Overall Totals Summary\n======================================\n"), buf);
    ck_assert_ptr_nonnull(strstr(buf, "\n   Total Received Valid: 28\n"));
    ck_assert_ptr_nonnull(strstr(buf, "\n                Invalid: 0\n"));
    ck_assert_ptr_nonnull(strstr(buf, "\n    Time since last Msg: 2.5\n"));
    ck_assert_ptr_nonnull(strstr(buf, "\nSource  Total  Elapsed  Variable  Value\n------  -----  -------  --------  -----\n"));
    ck_assert_ptr_nonnull(strstr(buf, "\ngilda   19     2.5      FOOBAR    35\n"));
    ck_assert_ptr_nonnull(strstr(buf, "\nhenry   5      16.5     FOOBAR    44\n"));
    ck_assert_ptr_nonnull(strstr(buf, "\nike     4      30.5     FOOBAR    20.25\n\nLast Few Messages: (oldest to newest) \n"));
    /* sources in name order */
    BEFORE(strstr(buf, "\ngilda"), strstr(buf, "\nhenry"));
    BEFORE(strstr(buf, "\nhenry"), strstr(buf, "\nike"));
    ck_assert_ptr_nonnull(strstr(buf, "Invalid Mgs: \n  NONE  \nRejected Mgs: \n  NONE  \n"));
    ck_assert_uint_eq(h.reports, 1);
    (void)kelp_field_umh_report(&h, 121, buf, sizeof buf);
    ck_assert_uint_eq(h.reports, 2);
}
END_TEST

/* 6.6.9: the last five of seven, oldest first; appcast_trunc_msg cuts listed messages */
START_TEST(umh_last_five)
{
    start("bravo", false);
    char m[128];
    for (int i = 1; i <= 7; i++) {
        snprintf(m, sizeof m, "src_node=alpha,dest_node=bravo,var_name=N,double_val=%d", i);
        ck_assert_int_eq(mail(m, i), 1);
    }
    ck_assert_int_eq(mail("src_node=alpha,dest_node=zed,var_name=N,double_val=1", 8), KELP_ERR_ARG);
    char buf[4096];
    (void)kelp_field_umh_report(&h, 8, buf, sizeof buf);
    const char *v = strstr(buf, "Valid Mgs: \n");
    ck_assert_ptr_nonnull(v);
    /* 24.8 lists a rejected (well formed) message among the valid ones too: 4..7 and zed */
    ck_assert_ptr_null(strstr(v, "double_val=3\n"));
    const char *p4 = strstr(v, "double_val=4\n"), *p7 = strstr(v, "double_val=7\n");
    ck_assert_ptr_nonnull(p4);
    ck_assert_ptr_nonnull(p7);
    BEFORE(p4, p7);
    ck_assert_ptr_nonnull(strstr(buf, "Rejected Mgs: \n  src_node=alpha,dest_node=zed,var_name=N,double_val=1\n"));
    /* truncation at 20 characters with "..." */
    h.cfg.trunc = 20;
    (void)kelp_field_umh_report(&h, 8, buf, sizeof buf);
    ck_assert_ptr_nonnull(strstr(buf, "Valid Mgs: \n  src_node=alpha,dest_...\n"));
    /* not verbose: the totals only */
    h.cfg.verbose = false;
    (void)kelp_field_umh_report(&h, 8, buf, sizeof buf);
    ck_assert_ptr_nonnull(strstr(buf, "Total Received Valid: 8")); /* 24.8: every message received */
    ck_assert_ptr_null(strstr(buf, "Valid Mgs: "));
}
END_TEST

/* a report into a small buffer is cut and still a string */
START_TEST(umh_report_small_buffer)
{
    start("bravo", false);
    char buf[40];
    size_t n = kelp_field_umh_report(&h, 1, buf, sizeof buf);
    ck_assert_uint_eq(n, strlen(buf));
    ck_assert_uint_lt(n, sizeof buf);
    ck_assert_ptr_nonnull(strstr(buf, "Overall Totals"));
}
END_TEST

/* UMH_SUMMARY_MSGS: first iteration, then after changes, at most once a second; "a summary of
 * total messages, valid messages and rejected messages" (seed 6.1.2), written as MOOS-IvP
 * 24.8 writes it (MessageHandler.cpp postMsgSummary: total=..,valid=..,rejected=..) */
START_TEST(umh_summary)
{
    start("bravo", false);
    ck_assert_int_eq(kelp_field_umh_iterate(&h, 10, &sink), 1);
    ck_assert_str_eq(r.val[find(&r, "UMH_SUMMARY_MSGS")], "total=0,valid=0,rejected=0");
    ck_assert_int_eq(kelp_field_umh_iterate(&h, 12, &sink), 0); /* nothing new */
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=X,double_val=1", 12), 1);
    ck_assert_int_eq(mail("src_node=a,dest_node=c,var_name=X,double_val=1", 12), KELP_ERR_ARG);
    ck_assert_int_eq(mail("src_node=a", 12), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_umh_iterate(&h, 12.2, &sink), 1);
    /* 24.8: valid counts the rejected message too (it was well formed) */
    ck_assert_str_eq(r.val[find(&r, "UMH_SUMMARY_MSGS")], "total=3,valid=2,rejected=1");
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=X,double_val=1", 12.25), 1);
    /* every iteration with mail posts, however close (24.8: m_newmail) */
    ck_assert_int_eq(kelp_field_umh_iterate(&h, 12.25, &sink), 1);
    ck_assert_str_eq(r.val[find(&r, "UMH_SUMMARY_MSGS")], "total=4,valid=3,rejected=1");
    /* and iterations 101, 201, ... without mail */
    int posted = 0;
    for (int i = 4; i <= 201; i++) posted += kelp_field_umh_iterate(&h, 13 + i * 0.25, &sink);
    ck_assert_int_eq(posted, 2);
}
END_TEST

/* 24.8's parameters: names, values and reasons */
START_TEST(umh_config)
{
    kelp_field_umh_cfg c;
    kelp_diag why = { 0 };
    kelp_field_umh_cfg_default(&c, "bravo");
    ck_assert(c.verbose && !c.strict && !c.aux_app);
    ck_assert_uint_eq(c.trunc, 75);
    ck_assert_int_eq(kelp_field_umh_config(&c, "strict_addressing", "TRUE", &why), 1);
    ck_assert(c.strict);
    ck_assert_int_eq(kelp_field_umh_config(&c, "VERBOSE", "false", &why), 1);
    ck_assert(!c.verbose);
    ck_assert_int_eq(kelp_field_umh_config(&c, "aux_info", "node+app", &why), 1);
    ck_assert(c.aux_app);
    ck_assert_int_eq(kelp_field_umh_config(&c, "aux_info", "app", &why), KELP_ERR_PARSE);
    ck_diag_msg(&why, "expected node or node+app");
    ck_assert_int_eq(kelp_field_umh_config(&c, "appcast_trunc_msg", "40", &why), 1);
    ck_assert_uint_eq(c.trunc, 40);
    ck_assert_int_eq(kelp_field_umh_config(&c, "appcast_trunc_msg", "-1", &why), 1); /* 24.8: below 0 is 0 */
    ck_assert_uint_eq(c.trunc, 0);
    ck_assert_int_eq(kelp_field_umh_config(&c, "strict_addressing", "maybe", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "RETURN=true", &why), 1);
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "GOT = 3", &why), 1);
    ck_assert_int_eq(kelp_field_umh_config(&c, "bad_msg_flag", "TOTAL_BAD=$[BAD_CTR]", &why), 1);
    ck_assert_uint_eq(c.nmsg_flag, 2);
    ck_assert(c.msg_flag[0].is_string);
    ck_assert_str_eq(c.msg_flag[0].sval, "true");
    ck_assert(!c.msg_flag[1].is_string);
    ck_assert_str_eq(c.msg_flag[1].var, "GOT");
    ck_assert_double_eq(c.msg_flag[1].dval, 3);
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "novalue", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "A B=1", &why), KELP_ERR_PARSE);
    ck_assert_int_eq(kelp_field_umh_config(&c, "app_logging", "true", &why), 0);
    for (int i = 0; i < 6; i++) ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "X=1", &why), 1);
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "X=1", &why), KELP_ERR_NOSPACE);
}
END_TEST

/* msg_flag after each posted message, bad_msg_flag after each rejected one, with
 * $[CTR], $[GOOD_CTR] and $[BAD_CTR] expanded */
START_TEST(umh_flags)
{
    kelp_field_umh_cfg c;
    kelp_diag why = { 0 };
    kelp_field_umh_cfg_default(&c, "bravo");
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "GOT=n$[GOOD_CTR]_of_$[CTR]", &why), 1);
    ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", "RETURN=\"2\"", &why), 1);
    ck_assert_int_eq(kelp_field_umh_config(&c, "bad_msg_flag", "TOTAL_BAD=$[BAD_CTR]", &why), 1);
    ck_assert_int_eq(kelp_field_umh_config(&c, "bad_msg_flag", "BAD_NUM=7", &why), 1);
    kelp_field_umh_init(&h, &c);
    memset(&r, 0, sizeof r);
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=X,double_val=1", 1), 1);
    ck_assert_str_eq(r.val[find(&r, "GOT")], "n1_of_1");
    ck_assert(r.str[find(&r, "RETURN")]);
    ck_assert_str_eq(r.val[find(&r, "RETURN")], "2");
    ck_assert_int_lt(find(&r, "TOTAL_BAD"), 0);
    ck_assert_int_eq(mail("src_node=a,dest_node=zulu,var_name=X,double_val=1", 2), KELP_ERR_ARG);
    ck_assert_int_eq(mail("garbage", 3), KELP_ERR_PARSE);
    ck_assert_str_eq(r.val[find(&r, "TOTAL_BAD")], "1");
    ck_assert(!r.str[find(&r, "BAD_NUM")]);
    ck_assert_double_eq(r.d[find(&r, "BAD_NUM")], 7);
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=X,double_val=1", 4), 1);
    ck_assert_str_eq(r.val[find(&r, "GOT")], "n3_of_4"); /* 24.8: GOOD_CTR counts the rejected one too */
    /* order: the variable first, then its flags */
    ck_assert_int_lt(find(&r, "X"), find(&r, "GOT"));
}
END_TEST

/* MOOS-IvP 24.8 (MessageHandler.cpp handleMailNodeMessage, postFlags): the BAD_MSG_FLAGs
 * follow a message rejected for its address only (an invalid one posts no flag), and
 * $[BAD_CTR] counts the rejected messages */
START_TEST(umh_bad_flags_on_rejected_only)
{
    start_with("bad_msg_flag", "TOTAL_BAD=$[BAD_CTR]");
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,double_val=1", 1), KELP_ERR_PARSE);
    ck_assert_int_lt(find(&r, "TOTAL_BAD"), 0);
    ck_assert_int_eq(mail("src_node=a,dest_node=zulu,var_name=X,double_val=1", 2), KELP_ERR_ARG);
    ck_assert_str_eq(r.val[find(&r, "TOTAL_BAD")], "1");
    ck_assert_int_eq(mail("garbage", 3), KELP_ERR_PARSE);
    ck_assert_int_eq(mail("src_node=a,dest_node=yankee,var_name=X,double_val=1", 4), KELP_ERR_ARG);
    ck_assert_str_eq(r.val[find(&r, "TOTAL_BAD")], "2");
    int n = 0;
    for (int i = 0; i < r.n; i++) n += !strcmp(r.var[i], "TOTAL_BAD");
    ck_assert_int_eq(n, 2);
}
END_TEST

/* aux_info = node+app: the aux source names the sending app too */
START_TEST(umh_aux_node_app)
{
    kelp_field_umh_cfg c;
    kelp_field_umh_cfg_default(&c, "bravo");
    c.aux_app = true;
    kelp_field_umh_init(&h, &c);
    memset(&r, 0, sizeof r);
    ck_assert_int_eq(mail("src_node=alpha,src_app=pHelmIvP,dest_node=bravo,var_name=X,double_val=1", 1), 1);
    ck_assert_str_eq(h.aux, "alpha+pHelmIvP");
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=X,double_val=1", 1), 1);
    ck_assert_str_eq(h.aux, "alpha");
}
END_TEST

/* the parser on its own: fields, the colon list, ack and color */
START_TEST(nodemsg_parse_fields)
{
    const char *s = " SRC_NODE = abe , dest_group=blue,var_name=SAY,string_val=\"hold,station\",color=green,ack=true,ack_id=42";
    kelp_node_message m;
    kelp_diag why = { 0 };
    ck_assert_int_eq(kelp_field_nodemsg_parse(s, strlen(s), &m, &why), 0);
    ck_assert_int_eq((int)m.src_node.n, 3);
    ck_assert(!strncmp(m.src_node.p, "abe", 3));
    ck_assert(!strncmp(m.dest_group.p, "blue", m.dest_group.n));
    ck_assert(!strncmp(m.string_val.p, "hold,station", m.string_val.n));
    ck_assert_int_eq((int)m.string_val.n, 12);
    ck_assert(!strncmp(m.color.p, "green", m.color.n));
    ck_assert(!strncmp(m.ack_id.p, "42", m.ack_id.n));
    ck_assert(m.ack && m.has_string && !m.has_double);
    s = "src_node=a,dest_node=bravo:Charlie:gilda,var_name=V,double_val=-1.5e2";
    ck_assert_int_eq(kelp_field_nodemsg_parse(s, strlen(s), &m, &why), 0);
    ck_assert_double_eq(m.double_val, -150);
    ck_assert(kelp_field_nodemsg_to(&m, "charlie"));
    ck_assert(kelp_field_nodemsg_to(&m, "gilda"));
    ck_assert(!kelp_field_nodemsg_to(&m, "gild"));
    /* a length shorter than the string: only that part is read */
    ck_assert_int_eq(kelp_field_nodemsg_parse(s, 25, &m, &why), KELP_ERR_PARSE);
    ck_diag_msg(&why, "no var_name");
}
END_TEST

/* more sources than the table holds: the least recent one is replaced */
START_TEST(umh_many_sources)
{
    start("bravo", false);
    char m[128];
    for (int i = 0; i < KELP_UMH_MAX_SOURCES + 3; i++) {
        snprintf(m, sizeof m, "src_node=n%02d,dest_node=bravo,var_name=X,double_val=%d", i, i);
        ck_assert_int_eq(mail(m, i), 1);
    }
    ck_assert_uint_eq(h.nsrc, KELP_UMH_MAX_SOURCES);
    ck_assert_uint_eq(h.valid, KELP_UMH_MAX_SOURCES + 3);
    bool have_first = false, have_last = false;
    for (unsigned i = 0; i < h.nsrc; i++) {
        have_first = have_first || !strcmp(h.src[i].name, "n00");
        have_last = have_last || !strcmp(h.src[i].name, "n34");
    }
    ck_assert(!have_first && have_last);
}
END_TEST

/* msghandler_b1_default: each NODE_MESSAGE the DB delivered (the double one it dropped is not
 * here) at the MOOS time 24.8 handled it (its UMH_SUMMARY_MSGS row), scenario time */
static const struct {
    double t;
    const char *msg;
} b1_in[] = {
    { 1.0456, "src_node=alpha,dest_node=bravo,var_name=FOO,string_val=hello" },
    { 2.0478, "src_node=alpha,dest_node=bravo,var_name=SPEED,double_val=2.5" },
    { 3.0483, "src_node=charlie,dest_node=all,var_name=BAR,string_val=to_all" },
    { 4.0509, "src_node=charlie,dest_node=ALL,var_name=BAR2,double_val=-7" },
    { 5.0525, "src_node=delta,dest_group=red,var_name=GRP,string_val=group_msg" },
    { 6.0550, "src_node=alpha,dest_node=charlie,var_name=NOT_MINE,string_val=x" },
    { 7.0565, "src_node=alpha,dest_node=bravo,string_val=novar" },
    { 8.0594, "dest_node=bravo,var_name=NOSRC,string_val=x" },
    { 9.0606, "src_node=alpha,var_name=NODEST,string_val=x" },
    { 10.0631, "src_node=alpha,dest_node=bravo,var_name=BOTH,string_val=s,double_val=3" },
    { 11.0660, "src_node=alpha,dest_node=bravo,var_name=QUOTED,string_val=\"a,b=c\"" },
    { 12.0685, "src_node=alpha,dest_node=bravo,var_name=QUOTED2,string_val=\"keep\",string_val_quoted=true" },
    { 13.0727, "src_node=alpha,src_app=pHelmIvP,dest_node=bravo,var_name=WITHAPP,string_val=app" },
    { 14.0751, "src_node=alpha,dest_node=bravo,var_name=NUMSTR,string_val=42" },
    { 15.0768, "src_node=alpha,dest_node=bravo,var_name=DBLBAD,double_val=abc" },
    { 16.0790, "this is not a node message" },
    { 18.0836, "src_node=alpha,dest_node=Bravo,var_name=CASE,string_val=case" },
    { 19.0844, "SRC_NODE=alpha,DEST_NODE=bravo,VAR_NAME=UPPERKEYS,STRING_VAL=up" },
    { 20.0864, "src_node=alpha,dest_node=bravo,var_name=EMPTYSTR,string_val=" },
    { 21.0879, "src_node=alpha,dest_node=bravo:charlie,var_name=LIST,string_val=l" },
    { 22.0912, "src_node=alpha , dest_node = bravo , var_name = SPACES , string_val = sp" },
    { 22.0912, "src_node=echo,dest_node=bravo,var_name=BURST1,double_val=1" },
    { 22.0912, "src_node=echo,dest_node=bravo,var_name=BURST2,double_val=2" },
};
/* every posting of uFldMessageHandler in the recording but its status and APPCAST: variable,
 * type, value, MOOS source-aux, time */
static const struct {
    const char *var;
    bool str;
    const char *val, *aux;
    double t;
} b1_out[] = {
    { "FOO", true, "hello", "alpha", 1.0455 },
    { "UMH_SUMMARY_MSGS", true, "total=1,valid=1,rejected=0", "", 1.0456 },
    { "SPEED", false, "2.5", "alpha", 2.0476 },
    { "UMH_SUMMARY_MSGS", true, "total=2,valid=2,rejected=0", "", 2.0478 },
    { "BAR", true, "to_all", "charlie", 3.0482 },
    { "UMH_SUMMARY_MSGS", true, "total=3,valid=3,rejected=0", "", 3.0483 },
    { "BAR2", false, "-7", "charlie", 4.0507 },
    { "UMH_SUMMARY_MSGS", true, "total=4,valid=4,rejected=0", "", 4.0509 },
    { "GRP", true, "group_msg", "delta", 5.0525 },
    { "UMH_SUMMARY_MSGS", true, "total=5,valid=5,rejected=0", "", 5.0525 },
    { "UMH_SUMMARY_MSGS", true, "total=6,valid=6,rejected=1", "", 6.0550 },
    { "UMH_SUMMARY_MSGS", true, "total=7,valid=6,rejected=1", "", 7.0565 },
    { "UMH_SUMMARY_MSGS", true, "total=8,valid=6,rejected=1", "", 8.0594 },
    { "UMH_SUMMARY_MSGS", true, "total=9,valid=6,rejected=1", "", 9.0606 },
    { "UMH_SUMMARY_MSGS", true, "total=10,valid=6,rejected=1", "", 10.0631 },
    { "QUOTED", true, "a,b=c", "alpha", 11.0660 },
    { "UMH_SUMMARY_MSGS", true, "total=11,valid=7,rejected=1", "", 11.0660 },
    { "QUOTED2", true, "keep", "alpha", 12.0685 },
    { "UMH_SUMMARY_MSGS", true, "total=12,valid=8,rejected=1", "", 12.0685 },
    { "WITHAPP", true, "app", "alpha", 13.0725 },
    { "UMH_SUMMARY_MSGS", true, "total=13,valid=9,rejected=1", "", 13.0727 },
    { "NUMSTR", true, "42", "alpha", 14.0750 },
    { "UMH_SUMMARY_MSGS", true, "total=14,valid=10,rejected=1", "", 14.0751 },
    { "DBLBAD", false, "0", "alpha", 15.0767 },
    { "UMH_SUMMARY_MSGS", true, "total=15,valid=11,rejected=1", "", 15.0768 },
    { "UMH_SUMMARY_MSGS", true, "total=16,valid=11,rejected=1", "", 16.0790 },
    { "UMH_SUMMARY_MSGS", true, "total=17,valid=12,rejected=2", "", 18.0836 },
    { "UPPERKEYS", true, "up", "alpha", 19.0844 },
    { "UMH_SUMMARY_MSGS", true, "total=18,valid=13,rejected=2", "", 19.0844 },
    { "EMPTYSTR", false, "0", "alpha", 20.0863 },
    { "UMH_SUMMARY_MSGS", true, "total=19,valid=14,rejected=2", "", 20.0864 },
    { "UMH_SUMMARY_MSGS", true, "total=20,valid=15,rejected=3", "", 21.0879 },
    { "SPACES", true, "sp", "alpha", 22.0911 },
    { "BURST1", false, "1", "echo", 22.0912 },
    { "BURST2", false, "2", "echo", 22.0912 },
    { "UMH_SUMMARY_MSGS", true, "total=23,valid=18,rejected=3", "", 22.0912 },
    { "UMH_SUMMARY_MSGS", true, "total=23,valid=18,rejected=3", "", 22.5924 },
};
/* the messages= field of its APPCAST at t=24.0970 (iter=107), one report line per line */
static const char b1_report[] =
    "Overall Totals Summary\n"
    "======================================\n"
    "   Total Received Valid: 23\n"
    "                Invalid: 5\n"
    "               Rejected: 3\n"
    "    Time since last Msg: 2.0\n"
    "\n"
    "Per Source Node Summary\n"
    "======================================\n"
    "Source   Total  Elapsed  Variable  Value\n"
    "-------  -----  -------  --------  ---------\n"
    "alpha    13     2.0      SPACES    sp\n"
    "charlie  2      20.0     BAR2      -7\n"
    "delta    1      19.0     GRP       group_msg\n"
    "echo     2      2.0      BURST2    2\n"
    "\n"
    "Last Few Messages: (oldest to newest) \n"
    "======================================\n"
    "Valid Mgs: \n"
    "  src_node=alpha,dest_node=bravo,var_name=EMPTYSTR,string_val=\n"
    "  src_node=alpha,dest_node=bravo:charlie,var_name=LIST,string_val=l\n"
    "  src_node=alpha , dest_node = bravo , var_name = SPACES , string_val = sp\n"
    "  src_node=echo,dest_node=bravo,var_name=BURST1,double_val=1\n"
    "  src_node=echo,dest_node=bravo,var_name=BURST2,double_val=2\n"
    "Invalid Mgs: \n"
    "  src_node=alpha,dest_node=bravo,string_val=novar\n"
    "  dest_node=bravo,var_name=NOSRC,string_val=x\n"
    "  src_node=alpha,var_name=NODEST,string_val=x\n"
    "  src_node=alpha,dest_node=bravo,var_name=BOTH,string_val=s,double_val=3\n"
    "  this is not a node message\n"
    "Rejected Mgs: \n"
    "  src_node=alpha,dest_node=charlie,var_name=NOT_MINE,string_val=x\n"
    "  src_node=alpha,dest_node=Bravo,var_name=CASE,string_val=case\n"
    "  src_node=alpha,dest_node=bravo:charlie,var_name=LIST,string_val=l\n"
    ;

/* The recorded run of MOOS-IvP 24.8 (conformance scenario msghandler_b1_default), replayed on the
 * state machine at 4 Hz: every posting in order with its type, value and source-aux, the
 * summary after each iteration with mail and on iteration 101 (t=22.59, no mail), and the
 * APPCAST report text at t=24.097 exactly. */
START_TEST(umh_golden_b1_default)
{
    start("bravo", false);
    const double t1 = 22.5924 - 100 * 0.25; /* iteration 1 (the recording's 101st posted at 22.5924) */
    size_t next = 0;
    double now = 0;
    for (int k = 1; k <= 107; k++) {
        now = t1 + 0.25 * (k - 1);
        while (next < sizeof b1_in / sizeof b1_in[0] && b1_in[next].t < now + 0.125) {
            now = b1_in[next].t;
            KELP_IGNORE(mail(b1_in[next].msg, now));
            next++;
        }
        KELP_IGNORE(kelp_field_umh_iterate(&h, now, &sink));
    }
    ck_assert_uint_eq(next, sizeof b1_in / sizeof b1_in[0]);
    /* the start-up summary of iteration 1 is not in the recording (posted before t0) */
    ck_assert_str_eq(r.var[0], "UMH_SUMMARY_MSGS");
    ck_assert_str_eq(r.val[0], "total=0,valid=0,rejected=0");
    ck_assert_int_eq(r.n - 1, (int)(sizeof b1_out / sizeof b1_out[0]));
    for (int i = 1; i < r.n; i++) {
        ck_assert_str_eq(r.var[i], b1_out[i - 1].var);
        ck_assert_int_eq(r.str[i], b1_out[i - 1].str);
        ck_assert_str_eq(r.val[i], b1_out[i - 1].val);
        ck_assert_str_eq(r.aux[i], b1_out[i - 1].aux);
    }
    static char buf[4096];
    (void)kelp_field_umh_report(&h, 24.0970, buf, sizeof buf);
    ck_assert_str_eq(buf, b1_report);
}
END_TEST

/* NodeMessageUtils.cpp string2NodeMessage: every set... call overwrites, so of a repeated key
 * the last one counts (kelp took the first) */
START_TEST(umh_repeated_key_last_wins)
{
    start("bravo", false);
    ck_assert_str_eq(posted("src_node=alpha,dest_node=charlie,var_name=X,dest_node=bravo,string_val=a,string_val=b", "X"), "b");
    ck_assert_str_eq(posted("src_node=alpha,dest_node=bravo,var_name=Y,double_val=1,double_val=2", "Y"), "2");
}
END_TEST

/* NodeMessage::setStringVal and MessageHandler.cpp: quotes come off (isQuoted/stripQuotes), and
 * a string left empty posts the double instead (is_string = var_sval != ""): string_val=""
 * posts 0 as a double, as the recording's EMPTYSTR does; string_val_quoted=true strips once
 * more before NodeMessage::valid() looks */
static const struct {
    const char *msg;
    int rc;
    bool str; /* posted as a string (val) or a double (d) */
    const char *val;
    double d;
} quoted[] = {
    { "src_node=alpha,dest_node=bravo,var_name=Q,string_val=\"\"", 1, false, NULL, 0 },
    { "src_node=alpha,dest_node=bravo,var_name=Q,string_val=\"\",string_val_quoted=true,double_val=4", 1, false, NULL, 4 },
    { "src_node=alpha,dest_node=bravo,var_name=Q,string_val=\"\",double_val=4", KELP_ERR_PARSE, false, NULL, 0 },
    { "src_node=alpha,dest_node=bravo,var_name=Q,string_val_quoted=true,string_val=\"\"x\"\"", 1, true, "x", 0 },
};

START_TEST(umh_quoted_empty_posts_double)
{
    start("bravo", false);
    ck_assert_int_eq(mail(quoted[_i].msg, 1), quoted[_i].rc);
    int i = find(&r, "Q");
    if (quoted[_i].rc != 1) {
        ck_assert_int_lt(i, 0);
        return;
    }
    ck_assert_int_ge(i, 0);
    ck_assert_int_eq(r.str[i], quoted[_i].str);
    if (quoted[_i].str) ck_assert_str_eq(r.val[i], quoted[_i].val);
    else ck_assert_double_eq(r.d[i], quoted[_i].d);
}
END_TEST

/* MBUtils.cpp parseStringQ: an unclosed quote or brace runs to the end of the message (no
 * error), and a brace counts inside quotes too */
START_TEST(umh_unclosed_quote_runs_to_end)
{
    start("bravo", false);
    ck_assert_str_eq(posted("src_node=alpha,dest_node=bravo,var_name=X,string_val=\"open", "X"), "\"open");
    ck_assert_str_eq(posted("src_node=alpha,dest_node=bravo,var_name=B,string_val={a,b", "B"), "{a,b");
    /* the '{' inside the quotes opens a brace: var_name=X is part of string_val's text */
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,string_val=\"{\",var_name=Z", 3), KELP_ERR_PARSE);
    ck_assert_int_lt(find(&r, "Z"), 0);
    ck_assert_uint_eq(h.valid, 2);
}
END_TEST

/* MessageHandler.h: the per-source table is a std::map keyed by src_node as written, so alpha
 * and Alpha are two rows (kelp merged them) */
START_TEST(umh_sources_by_exact_name)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=X,double_val=1", 1), 1);
    ck_assert_int_eq(mail("src_node=Alpha,dest_node=bravo,var_name=Y,double_val=2", 1), 1);
    ck_assert_uint_eq(h.nsrc, 2);
    static char buf[4096];
    (void)kelp_field_umh_report(&h, 2, buf, sizeof buf);
    /* std::string order: upper case first */
    ck_assert_ptr_nonnull(strstr(buf, "\nAlpha   1      1.0      Y         2\nalpha   1      1.0      X         1\n"));
}
END_TEST

/* MacroUtils.cpp macroExpand: $(CTR) as well as $[CTR] */
START_TEST(umh_flag_round_macros)
{
    start_with("msg_flag", "GOT=$(CTR)/$(GOOD_CTR)/$(BAD_CTR)");
    ck_assert_int_eq(mail("src_node=a,dest_node=zulu,var_name=X,double_val=1", 1), KELP_ERR_ARG);
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=X,double_val=1", 2), 1);
    ck_assert_str_eq(r.val[find(&r, "GOT")], "2/2/1");
}
END_TEST

/* VarDataPairUtils.cpp setVarDataPairOnString and VarDataPair(var, val, "auto"): the value is
 * a double only when MBUtils' isNumber says so (1e3 is a string); "clearall" empties the list;
 * post and destination tags and an [if] condition are read past; VAR= with no value refused */
START_TEST(umh_flag_values_as_248)
{
    static const struct {
        const char *line;
        int rc;
        unsigned n; /* flags after it */
    } lines[] = { { "OLD=1", 1, 1 },       { "clearall", 1, 0 },
                  { "E=1e3", 1, 1 },       { "@cpa T=+2.5", 1, 2 },
                  { "#red G=go [if] MODE=survey", 1, 3 }, { "EMPTY=", KELP_ERR_PARSE, 3 } };
    kelp_field_umh_cfg c;
    kelp_diag why = { 0 };
    kelp_field_umh_cfg_default(&c, "bravo");
    for (size_t k = 0; k < sizeof lines / sizeof lines[0]; k++) {
        ck_assert_int_eq(kelp_field_umh_config(&c, "msg_flag", lines[k].line, &why), lines[k].rc);
        ck_assert_uint_eq(c.nmsg_flag, lines[k].n);
    }
    ck_assert(c.msg_flag[0].is_string);
    ck_assert_str_eq(c.msg_flag[0].sval, "1e3");
    ck_assert(!c.msg_flag[1].is_string);
    ck_assert_str_eq(c.msg_flag[1].var, "T");
    ck_assert_double_eq(c.msg_flag[1].dval, 2.5);
    ck_assert_str_eq(c.msg_flag[2].var, "G");
    ck_assert_str_eq(c.msg_flag[2].sval, "go");
}
END_TEST

/* MessageHandler.cpp OnStartUp: strict_addressing through setBooleanOnString (on/off too);
 * aux_info exactly "node" or "node+app"; appcast_trunc_msg any isNumber, read as atoi */
START_TEST(umh_config_as_248)
{
    static const struct {
        const char *key, *val;
        int rc;
    } lines[] = { { "strict_addressing", "on", 1 },   { "aux_info", "NODE+APP", KELP_ERR_PARSE },
                  { "appcast_trunc_msg", "3.7", 1 },  { "appcast_trunc_msg", "1e2", KELP_ERR_PARSE },
                  { "strict_addressing", "toggle", 1 }, { "appcast_trunc_msg", "300", 1 } };
    kelp_field_umh_cfg c;
    kelp_diag why = { 0 };
    kelp_field_umh_cfg_default(&c, "bravo");
    for (size_t k = 0; k < sizeof lines / sizeof lines[0]; k++) {
        ck_assert_int_eq(kelp_field_umh_config(&c, lines[k].key, lines[k].val, &why), lines[k].rc);
        if (k == 2) ck_assert_uint_eq(c.trunc, 3);
    }
    ck_assert(!c.strict && !c.aux_app); /* on, then toggled off */
    ck_assert_uint_eq(c.trunc, 300);
}
END_TEST

/* MessageHandler.cpp OnNewMail: msg.GetString() of a double is "", listed as such */
START_TEST(umh_double_mail_listed_empty)
{
    start("bravo", false);
    ck_assert_int_eq(kelp_field_umh_mail(&h, "NODE_MESSAGE", false, NULL, 1, &sink), KELP_ERR_PARSE);
    static char buf[4096];
    (void)kelp_field_umh_report(&h, 2, buf, sizeof buf);
    ck_assert_ptr_nonnull(strstr(buf, "Invalid Mgs: \n  \nRejected Mgs: \n"));
}
END_TEST

/* ACTable.cpp operator<< and getFormattedString: a '|' in a value cuts it into two cells (the
 * row is then short and not drawn), and a cell loses its blanks */
START_TEST(umh_table_cells_as_actable)
{
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=V,string_val=p|q", 1), 1);
    static char buf[4096];
    (void)kelp_field_umh_report(&h, 1.5, buf, sizeof buf);
    ck_assert_ptr_nonnull(strstr(buf, "Source  Total  Elapsed  Variable  Value\n"
                                      "------  -----  -------  --------  -----\n"
                                      "alpha   1      0.5      V         p\n\nLast Few"));
    start("bravo", false);
    ck_assert_int_eq(mail("src_node=alpha,dest_node=bravo,var_name=V,string_val=\"  x  \"", 1), 1);
    ck_assert_str_eq(r.val[find(&r, "V")], "  x  ");
    (void)kelp_field_umh_report(&h, 1.5, buf, sizeof buf);
    ck_assert_ptr_nonnull(strstr(buf, "\nalpha   1      0.5      V         x\n\nLast Few"));
}
END_TEST

/* NodeMessageUtils.cpp: double_val through atof, whatever its length, overflow to inf */
START_TEST(umh_double_val_atof)
{
    start("bravo", false);
    char m[256];
    snprintf(m, sizeof m, "src_node=a,dest_node=bravo,var_name=L,double_val=1%070d", 0);
    ck_assert_int_eq(mail(m, 1), 1);
    ck_assert_double_eq_tol(r.d[find(&r, "L")], 1e70, 1e55);
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=H,double_val=1e400", 2), 1);
    ck_assert(isinf(r.d[find(&r, "H")]));
    ck_assert_int_eq(mail("src_node=a,dest_node=bravo,var_name=P,double_val=-2.5e1x", 3), 1);
    ck_assert_double_eq(r.d[find(&r, "P")], -25);
}
END_TEST

Suite *kelp_field_msghandler_suite(void);
Suite *kelp_field_msghandler_suite(void)
{
    Suite *s = suite_create("field_msghandler");
    TCase *tc = tcase_create("umh");
    tcase_add_test(tc, umh_double_posted);
    tcase_add_test(tc, umh_string_src_var);
    tcase_add_test(tc, umh_quoted_string);
    tcase_add_test(tc, umh_group_strict);
    tcase_add_test(tc, umh_other_dest_rejected);
    tcase_add_test(tc, umh_all);
    tcase_add_test(tc, umh_colon_list);
    tcase_add_loop_test(tc, umh_invalid, 0, (int)(sizeof invalid / sizeof invalid[0]));
    tcase_add_test(tc, umh_not_a_string);
    tcase_add_test(tc, umh_per_source_and_report);
    tcase_add_test(tc, umh_last_five);
    tcase_add_test(tc, umh_report_small_buffer);
    tcase_add_test(tc, umh_summary);
    tcase_add_test(tc, umh_values_as_248);
    tcase_add_test(tc, umh_config);
    tcase_add_test(tc, umh_flags);
    tcase_add_test(tc, umh_bad_flags_on_rejected_only);
    tcase_add_test(tc, umh_aux_node_app);
    tcase_add_test(tc, nodemsg_parse_fields);
    tcase_add_test(tc, umh_many_sources);
    tcase_add_test(tc, umh_golden_b1_default);
    tcase_add_test(tc, umh_repeated_key_last_wins);
    tcase_add_loop_test(tc, umh_quoted_empty_posts_double, 0, (int)(sizeof quoted / sizeof quoted[0]));
    tcase_add_test(tc, umh_unclosed_quote_runs_to_end);
    tcase_add_test(tc, umh_sources_by_exact_name);
    tcase_add_test(tc, umh_flag_round_macros);
    tcase_add_test(tc, umh_flag_values_as_248);
    tcase_add_test(tc, umh_config_as_248);
    tcase_add_test(tc, umh_double_mail_listed_empty);
    tcase_add_test(tc, umh_table_cells_as_actable);
    tcase_add_test(tc, umh_double_val_atof);
    suite_add_tcase(s, tc);
    return s;
}
