/* gen_hazards: a random hazard field for uFldHazardSensor (uField seed section 9.2.2): objects
 * of the given types placed uniformly at random in a convex polygon, one line each,
 * "x=20.1,y=13.8,type=hazard", grouped in the order of the --objects options. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <kelp/edge/cli.h>
#include <kelp/hazardsensor.h>
#include <kelp/nodereport.h>
#include <kelp/util.h>

#define GEN_MAX_SETS 32
#define GEN_MAX_OBJECTS 100000

typedef struct objset {
    long count;
    char type[16];
} objset;

static int parse_set(const char *s, objset *o)
{
    const char *comma = strchr(s, ',');
    if (!comma || kelp_util_parse_long(s, (size_t)(comma - s), &o->count) < 0 || o->count < 0 || o->count > GEN_MAX_OBJECTS)
        return -1;
    const char *t = comma + 1;
    while (*t == ' ') t++;
    if (!kelp_util_strieq(t, "hazard") && !kelp_util_strieq(t, "benign")) return -1;
    kelp_util_snprintf(o->type, sizeof o->type, "%s", kelp_util_strieq(t, "hazard") ? "hazard" : "benign");
    return 0;
}

/* 1 decimal, trailing zeros dropped (the seed's "x=32.6,y=38") */
static void fmt1(char *b, size_t cap, double v)
{
    if (kelp_util_fmt_fixed(b, cap, v, 1, true) < 0) kelp_util_snprintf(b, cap, "0");
}

int main(int argc, char **argv)
{
    const kelp_cli cli = {
        .name = "gen_hazards",
        .purpose = "Print a random hazard field (hazard and benign objects in a convex polygon) for\n"
                   "uFldHazardSensor's hazard_file.",
        .synopsis = "--polygon=X,Y:X,Y:... --objects=N,hazard|benign [--objects=...] [--seed=N] [--labels]",
        .opts = (const kelp_cli_opt[]){
            { "objects", required_argument, 'o', "N,TYPE", "N objects of TYPE (hazard or benign); repeat" },
            { "polygon", required_argument, 'p', "PTS", "the convex region, \"0,0:50,0:50,50:0,50\"" },
            { "seed", required_argument, 's', "N", "seed of the generator (default: from the clock); same seed, same field" },
            { "labels", no_argument, 'l', NULL, "add label=<index> to each line" },
            { NULL, 0, 0, NULL, NULL } },
        .more = "Example: gen_hazards --objects=5,hazard --objects=6,benign --polygon=\"0,0:50,0:50,50:0,50\"\n",
    };
    objset set[GEN_MAX_SETS];
    int nset = 0, opt, status;
    bool labels = false, have_seed = false;
    unsigned long long seed = 0;
    kelp_view poly;
    bool have_poly = false;
    while ((opt = kelp_cli_next(&cli, argc, argv, &status)) != -1) {
        if (opt == KELP_CLI_EXIT) return status;
        if (opt == 'o') {
            if (nset >= GEN_MAX_SETS || parse_set(optarg, &set[nset]) < 0)
                return kelp_cli_error(&cli, "bad --objects '%s' (N,hazard or N,benign; at most %d)", optarg, GEN_MAX_SETS);
            nset++;
        } else if (opt == 'p') {
            char spec[4096];
            kelp_diag dg = { 0 };
            int n = kelp_util_snprintf(spec, sizeof spec, "pts={%s}", optarg);
            if (n < 0 || (size_t)n >= sizeof spec || kelp_nodereport_view_parse(KELP_VIEW_POLYGON, spec, strlen(spec), &poly, &dg) < 0 ||
                poly.npts < 3)
                return kelp_cli_error(&cli, "bad --polygon '%s': %s", optarg, dg.code ? kelp_diag_text(&dg) : "three vertices or more");
            have_poly = true;
        } else if (opt == 's') {
            long long v;
            if (kelp_util_parse_llong(optarg, strlen(optarg), &v) < 0) return kelp_cli_error(&cli, "bad --seed '%s'", optarg);
            seed = (unsigned long long)v;
            have_seed = true;
        } else if (opt == 'l') {
            labels = true;
        }
    }
    if (optind != argc) return kelp_cli_error(&cli, "unexpected argument '%s'", argv[optind]);
    if (!have_poly) return kelp_cli_error(&cli, "no --polygon");
    if (nset == 0) return kelp_cli_error(&cli, "no --objects");
    if (!have_seed) seed = (unsigned long long)time(NULL) ^ ((unsigned long long)clock() << 32);
    kelp_rng rng;
    kelp_rng_seed(&rng, seed);
    const double(*pts)[2] = (const double(*)[2])poly.pts;
    long index = 0;
    for (int s = 0; s < nset; s++) {
        for (long i = 0; i < set[s].count; i++) {
            char xs[64], ys[64];
            double x, y, rx, ry;
            int tries = 0;
            do { /* the printed (rounded) point must lie in the polygon too */
                if (kelp_hazardsensor_random_point(pts, poly.npts, &rng, &x, &y) < 0) {
                    fprintf(stderr, "gen_hazards: the polygon has no area (is it convex?)\n");
                    return 1;
                }
                fmt1(xs, sizeof xs, x);
                fmt1(ys, sizeof ys, y);
                if (kelp_util_parse_double(xs, strlen(xs), &rx) < 0 || kelp_util_parse_double(ys, strlen(ys), &ry) < 0) rx = ry = 0;
            } while (!kelp_hazardsensor_in_convex(pts, poly.npts, rx, ry) && ++tries < 1000);
            if (labels) printf("x=%s,y=%s,type=%s,label=%ld\n", xs, ys, set[s].type, index);
            else printf("x=%s,y=%s,type=%s\n", xs, ys, set[s].type);
            index++;
        }
    }
    return 0;
}
