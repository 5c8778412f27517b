/* A user program of the installed library, compiled as C11 and as C++17 (the same source):
 * two bus clients on one LCM community, one publishes HELLO, the other receives it; and a
 * call into the core (an IvP domain). Exit 0 when the message arrived. */
#include <stdio.h>
#include <string.h>
#include <kelp/bus.h>
#include <kelp/ivp.h>
#include <kelp/lcmbus.h>

#ifdef __cplusplus
#define LANG_NAME "C++"
#else
#define LANG_NAME "C"
#endif

static int got;

static void on_var(const kelp_var *v, void *user)
{
    (void)user;
    if (strcmp(v->name, "HELLO") == 0 && v->kind == KELP_VAR_STRING && strcmp(v->sval, "world") == 0) got = 1;
}

int main(int argc, char **argv)
{
    const char *url = argc > 1 ? argv[1] : "udpm://239.255.76.67:7791?ttl=0";
    kelp_ivp_domain dom;
    kelp_diag e;
    memset(&e, 0, sizeof e);
    if (kelp_ivp_domain_parse(&dom, "course:0:359:360", &e) != 0 || dom.dim != 1) {
        fprintf(stderr, "core call failed\n");
        return 1;
    }
    kelp_diag err;
    kelp_diag_clear(&err);
    kelp_lcmbus *rx = kelp_lcmbus_open(url, "rx", "link", on_var, NULL, &err);
    kelp_lcmbus *tx = kelp_lcmbus_open(url, "tx", "link", NULL, NULL, &err);
    if (!rx || !tx) {
        fprintf(stderr, "open: %s\n", kelp_diag_text(&err));
        return 1;
    }
    if (kelp_bus_register(kelp_lcmbus_bus(rx), "HELLO", 0, 0) < 0) return 1;
    for (int i = 0; i < 50 && !got; i++) {
        if (kelp_bus_notify_string(kelp_lcmbus_bus(tx), "HELLO", "world", 0) < 0) return 1;
        KELP_IGNORE(kelp_lcmbus_handle(tx, 0, 0));
        KELP_IGNORE(kelp_lcmbus_handle(rx, 100, 0));
    }
    kelp_lcmbus_close(tx);
    kelp_lcmbus_close(rx);
    printf("%s: %s\n", LANG_NAME, got ? "received HELLO=world" : "nothing received");
    return got ? 0 : 1;
}
