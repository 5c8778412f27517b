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
    kelp_plot_opts o = { 800, 600, "test", NULL, true };
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

Suite *kelp_plot_suite(void)
{
    Suite *s = suite_create("plot");
    TCase *tc = tcase_create("edge");
    tcase_add_test(tc, plot_scene_and_svg);
    suite_add_tcase(s, tc);
    return s;
}
