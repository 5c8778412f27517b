/* kelp-viewer's files (src/viewer/edge/files.c): pMarineViewer's .info georeference, the image
 * served for a tiff_file (a .png/.jpg of the same name first, relative to the mission), the
 * page's document root. */
#include <check.h>
#include "check_diag.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <kelp/edge/viewer.h>

static char dir[64];

static void put(const char *name, const char *text)
{
    char p[256];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    ck_assert_ptr_nonnull(f);
    fputs(text, f);
    fclose(f);
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/kelp-vfiles-XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(dir));
}

static void teardown(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    ck_assert_int_eq(system(cmd), 0);
}

START_TEST(info_file)
{
    put("a.info", "// MIT sailing pavilion\n  lat_north = 42.360264 \nlat_south=42.35415\nlon_east = -71.080058 // e\n"
                  "LON_WEST = -71.094214\ndatum_lat = 42.358456\n");
    char p[256];
    kelp_diag err = {0};
    double n = 0, s = 0, e = 0, w = 0;
    snprintf(p, sizeof p, "%s/a.info", dir);
    ck_assert_int_eq(kelp_viewer_read_info(p, &n, &s, &e, &w, &err), 0);
    ck_assert(n == 42.360264 && s == 42.35415 && e == -71.080058 && w == -71.094214);
    put("b.info", "lat_north = 42.36\nlat_south = 42.35\nlon_east = -71.08\n");
    snprintf(p, sizeof p, "%s/b.info", dir);
    ck_assert_int_lt(kelp_viewer_read_info(p, &n, &s, &e, &w, &err), 0);
    ck_assert_int_ne(err.code, KELP_OK);
    ck_diag_has(&err, "lon_west");
    kelp_diag_clear(&err);
    put("c.info", "lat_north = 42.36x\nlat_south = 42.35\nlon_east = -71.08\nlon_west = -71.09\n");
    snprintf(p, sizeof p, "%s/c.info", dir);
    ck_assert_int_lt(kelp_viewer_read_info(p, &n, &s, &e, &w, &err), 0);
    ck_assert_int_ne(err.code, KELP_OK);
    ck_diag_has(&err, ":1: lat_north");
    kelp_diag_clear(&err);
    snprintf(p, sizeof p, "%s/none.info", dir);
    ck_assert_int_lt(kelp_viewer_read_info(p, &n, &s, &e, &w, &err), 0);
}
END_TEST

START_TEST(image_files)
{
    char mission[256], img[512], info[512];
    snprintf(mission, sizeof mission, "%s/shoreside.moos", dir);
    put("map.tif", "II*");
    /* the .tif itself when nothing else is there, relative to the mission's directory */
    ck_assert_int_eq(kelp_viewer_image_files("map.tif", mission, img, sizeof img, info, sizeof info), 0);
    ck_assert_ptr_nonnull(strstr(img, "/map.tif"));
    ck_assert_str_eq(info + strlen(dir), "/map.info");
    /* a .jpg, then a .png, of the same name are preferred */
    put("map.jpg", "jpg");
    ck_assert_int_eq(kelp_viewer_image_files("map.tif", mission, img, sizeof img, info, sizeof info), 0);
    ck_assert_str_eq(img + strlen(dir), "/map.jpg");
    put("map.png", "png");
    ck_assert_int_eq(kelp_viewer_image_files("map.tif", mission, img, sizeof img, info, sizeof info), 0);
    ck_assert_str_eq(img + strlen(dir), "/map.png");
    /* an absolute path is taken as it is; a missing image is NOTFOUND */
    char abs[256];
    snprintf(abs, sizeof abs, "%s/map.tif", dir);
    ck_assert_int_eq(kelp_viewer_image_files(abs, "elsewhere/m.moos", img, sizeof img, info, sizeof info), 0);
    ck_assert_str_eq(img + strlen(dir), "/map.png");
    ck_assert_int_eq(kelp_viewer_image_files("nothere.tif", mission, img, sizeof img, info, sizeof info), KELP_ERR_NOTFOUND);
}
END_TEST

START_TEST(docroot)
{
    char buf[512];
    setenv("KELP_VIEWER_DOCROOT", dir, 1);
    ck_assert_int_eq(kelp_viewer_docroot(buf, sizeof buf), KELP_ERR_NOTFOUND); /* no index.html there */
    put("index.html", "<html>");
    ck_assert_int_eq(kelp_viewer_docroot(buf, sizeof buf), 0);
    ck_assert_str_eq(buf, dir);
    unsetenv("KELP_VIEWER_DOCROOT");
}
END_TEST

Suite *kelp_viewer_files_suite(void);
Suite *kelp_viewer_files_suite(void)
{
    Suite *s = suite_create("viewer_files");
    TCase *tc = tcase_create("files");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, info_file);
    tcase_add_test(tc, image_files);
    tcase_add_test(tc, docroot);
    suite_add_tcase(s, tc);
    return s;
}
