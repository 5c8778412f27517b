/* pXRelay: the MOOS example app. One post of OUTGOING_VAR (a counter) for each mail
 * received on INCOMING_VAR, made in Iterate; also <OUTGOING_VAR>_ITER_HZ and _POST_HZ. */
#include <stdio.h>
#include <string.h>
#include <kelp/edge/app.h>

typedef struct xrelay {
    char in[KELP_MAX_NAME], out[KELP_MAX_NAME];
    char iter_hz[KELP_MAX_NAME + 8], post_hz[KELP_MAX_NAME + 8];
    unsigned long recd, sent, unanswered, iterations, posting_passes;
    double first_iter, first_post;
} xrelay;

static int startup(kelp_app *app, void *st)
{
    xrelay *x = st;
    if (kelp_app_param_str(app, "INCOMING_VAR", x->in, sizeof x->in) <= 0)
        return kelp_app_config_error(app, NULL, "ProcessConfig = %s needs INCOMING_VAR", kelp_app_name(app));
    if (kelp_app_param_str(app, "OUTGOING_VAR", x->out, sizeof x->out) <= 0)
        return kelp_app_config_error(app, NULL, "ProcessConfig = %s needs OUTGOING_VAR", kelp_app_name(app));
    snprintf(x->iter_hz, sizeof x->iter_hz, "%s_ITER_HZ", x->out);
    snprintf(x->post_hz, sizeof x->post_hz, "%s_POST_HZ", x->out);
    return kelp_app_register(app, x->in, 0);
}

static void on_mail(kelp_app *app, void *st, const kelp_var *v)
{
    xrelay *x = st;
    (void)app;
    if (strcmp(v->name, x->in) == 0) {
        x->recd++;
        x->unanswered++;
    }
}

static int iterate(kelp_app *app, void *st, double now)
{
    xrelay *x = st;
    x->iterations++;
    if (x->iterations == 1) x->first_iter = now;
    else if (now > x->first_iter) KELP_IGNORE(kelp_app_notify_double(app, x->iter_hz, (x->iterations - 1) / (now - x->first_iter)));
    if (x->unanswered) {
        x->posting_passes++;
        if (x->posting_passes == 1) x->first_post = now;
        for (; x->unanswered; x->unanswered--) {
            x->sent++;
            if (kelp_app_notify_double(app, x->out, (double)x->sent) < 0) kelp_app_run_warning(app, "publish failed");
        }
        if (x->posting_passes > 1 && now > x->first_post)
            KELP_IGNORE(kelp_app_notify_double(app, x->post_hz, (x->sent - 1) / (now - x->first_post)));
    }
    return 0;
}

static void report(kelp_app *app, void *st, FILE *out)
{
    xrelay *x = st;
    (void)app;
    fprintf(out, "%s -> %s   received %lu   posted %lu\n", x->in, x->out, x->recd, x->sent);
}

static const kelp_app_def def = {
    .name = "pXRelay",
    .purpose = "Relay: one post of OUTGOING_VAR (a counter) per mail on INCOMING_VAR (the MOOS example app).",
    .params = (const kelp_app_param_info[]){
        { "INCOMING_VAR", "PEARS", "required: the variable whose mail is counted", NULL },
        { "OUTGOING_VAR", "APPLES", "required: the variable posted (a counter) once per mail", NULL },
        { NULL, NULL, NULL, NULL } },
    .subscribes = (const kelp_app_var_info[]){
        { "<INCOMING_VAR>", "any value", "each mail asks for one post of OUTGOING_VAR" },
        { NULL, NULL, NULL } },
    .publishes = (const kelp_app_var_info[]){
        { "<OUTGOING_VAR>", "17", "the number of posts so far" },
        { "<OUTGOING_VAR>_ITER_HZ", "24.98", "Iterate frequency" },
        { "<OUTGOING_VAR>_POST_HZ", "4.01", "posting frequency" },
        { NULL, NULL, NULL } },
    .startup = startup,
    .on_mail = on_mail,
    .iterate = iterate,
    .report = report,
};

int main(int argc, char **argv)
{
    static xrelay x;
    return kelp_app_run(argc, argv, &def, &x);
}
