/* kelp plot (src/plot/edge): a scene from bus writes, and its rendering. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <kelp/edge/plot.h>

static void add_str(kelp_plot_scene *s, const char *name, const char *val, double t)
{
    kelp_var v;
    memset(&v, 0, sizeof v);
    snprintf(v.name, sizeof v.name, "%s", name);
    snprintf(v.community, sizeof v.community, "shore");
    v.kind = KELP_VAR_STRING;
    v.slen = strlen(val);
    memcpy(v.sval, val, v.slen + 1);
    v.time = t;
    kelp_plot_scene_add_var(s, &v);
}

START_TEST(plot_scene_and_svg)
{
    kelp_plot_scene s;
    kelp_plot_scene_init(&s);
    for (int i = 0; i <= 10; i++) {
        char rep[200];
        snprintf(rep, sizeof rep, "NAME=alder,TYPE=UUV,TIME=%d,X=%d,Y=0,SPD=1,HDG=90,DEPTH=0", 100 + i, 10 * i);
        add_str(&s, "NODE_REPORT", rep, 100 + i);
    }
    add_str(&s, "NODE_REPORT", "NAME=broken,X=", 105);
    add_str(&s, "VIEW_POINT", "x=50,y=20,label=buoy", 101);
    kelp_plot_scene_finish(&s);
    kelp_plot_track *t = kelp_plot_scene_track(&s, "ALDER");
    ck_assert_ptr_nonnull(t);
    ck_assert_uint_eq(t->n, 11);
    ck_assert(fabs(t->dist - 100) < 1e-6);
    ck_assert_uint_eq(s.bad_reports, 1);
    ck_assert_uint_eq(s.nviews, 1);
    char path[] = "/tmp/kelp-plot-test-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    char svg[64];
    snprintf(svg, sizeof svg, "%s.svg", path);
    kelp_plot_opts o = { 800, 600, "test", NULL, true, true };
    ck_assert_int_eq(kelp_plot_render(&s, &o, svg), 0);
    FILE *f = fopen(svg, "r");
    ck_assert_ptr_nonnull(f);
    static char buf[1 << 20];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    ck_assert_ptr_nonnull(strstr(buf, "<svg"));
    ck_assert_ptr_nonnull(strstr(buf, "width=\"800"));
    remove(svg);
    remove(path);
    kelp_plot_scene_free(&s);
    kelp_plot_release();
    double rgb[3];
    ck_assert_int_eq(kelp_plot_color("dark_green", rgb), 0);
    ck_assert(rgb[1] > rgb[0] && rgb[1] > rgb[2]);
    ck_assert_int_eq(kelp_plot_color("invisible", rgb), 1);
    ck_assert_int_lt(kelp_plot_color("not_a_colour", rgb), 0);
}
END_TEST

/* closest approach between fixes: A (10t, 0) with fixes at t=0 and 10 only, B (50, 10t-45)
 * with fixes at 0, 3, 7, 10: least at t = 4.75, 2.5 * sqrt(2) m apart */
START_TEST(plot_closest_between_fixes)
{
    kelp_plot_scene s;
    kelp_plot_scene_init(&s);
    char rep[200];
    for (int t = 0; t <= 10; t += 10) {
        snprintf(rep, sizeof rep, "NAME=a,TYPE=UUV,TIME=%d,X=%d,Y=0,SPD=10,HDG=90", t, 10 * t);
        add_str(&s, "NODE_REPORT", rep, t);
    }
    const int tb[] = {0, 3, 7, 10};
    for (int k = 0; k < 4; k++) {
        snprintf(rep, sizeof rep, "NAME=b,TYPE=UUV,TIME=%d,X=50,Y=%d,SPD=10,HDG=0", tb[k], 10 * tb[k] - 45);
        add_str(&s, "NODE_REPORT", rep, tb[k]);
    }
    /* c is seen only after a and b are done: no overlap */
    add_str(&s, "NODE_REPORT", "NAME=c,TYPE=UUV,TIME=20,X=0,Y=0", 20);
    add_str(&s, "NODE_REPORT", "NAME=c,TYPE=UUV,TIME=21,X=1,Y=0", 21);
    kelp_plot_scene_finish(&s);
    kelp_plot_cpa c;
    ck_assert_int_eq(kelp_plot_closest(kelp_plot_scene_track(&s, "a"), kelp_plot_scene_track(&s, "b"), &c), 0);
    ck_assert(fabs(c.d - 2.5 * sqrt(2.0)) < 1e-9);
    ck_assert(fabs(c.t - 4.75) < 1e-9);
    ck_assert(fabs(c.ax - 47.5) < 1e-9 && fabs(c.ay) < 1e-9);
    ck_assert(fabs(c.bx - 50) < 1e-9 && fabs(c.by - 2.5) < 1e-9);
    ck_assert_int_eq(kelp_plot_closest(kelp_plot_scene_track(&s, "a"), kelp_plot_scene_track(&s, "c"), &c), -1);
    char *out = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&out, &len);
    kelp_plot_print_closest(&s, f);
    fclose(f);
    ck_assert_ptr_nonnull(strstr(out, "closest a b 3.54 m at 4.8 s (47.5,0.0) (50.0,2.5)"));
    ck_assert_ptr_null(strstr(out, "closest a c"));
    free(out);
    kelp_plot_scene_free(&s);
}
END_TEST

Suite *kelp_plot_suite(void)
{
    Suite *s = suite_create("plot");
    TCase *tc = tcase_create("edge");
    tcase_add_test(tc, plot_scene_and_svg);
    tcase_add_test(tc, plot_closest_between_fixes);
    suite_add_tcase(s, tc);
    return s;
}
