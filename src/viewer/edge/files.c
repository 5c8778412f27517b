/* kelp-viewer's files (see include/kelp/edge/viewer.h): where the page's files are, the
 * background image pMarineViewer's tiff_file names, and its .info georeference. No
 * microhttpd here, so the edge unit tests link this alone. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <kelp/edge/viewer.h>
#include <kelp/util.h>

static bool is_file(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0 && S_ISREG(st.st_mode);
}

int kelp_viewer_docroot(char *buf, size_t cap)
{
    const char *env = getenv("KELP_VIEWER_DOCROOT");
    char probe[PATH_MAX + 64];
    if (env && env[0]) {
        snprintf(probe, sizeof probe, "%s/index.html", env);
        if (!is_file(probe)) return KELP_ERR_NOTFOUND;
        snprintf(buf, cap, "%s", env);
        return 0;
    }
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) return KELP_ERR_NOTFOUND;
    exe[n] = '\0';
    char *slash = strrchr(exe, '/');
    if (!slash) return KELP_ERR_NOTFOUND;
    *slash = '\0';
    static const char *const rel[] = {"/../../share/viewer", "/../share/kelp/viewer"};
    for (size_t i = 0; i < sizeof rel / sizeof rel[0]; i++) {
        snprintf(probe, sizeof probe, "%s%s/index.html", exe, rel[i]);
        if (!is_file(probe)) continue;
        char *real = realpath(probe, NULL);
        if (!real) continue;
        *strrchr(real, '/') = '\0';
        snprintf(buf, cap, "%s", real);
        free(real);
        return 0;
    }
    return KELP_ERR_NOTFOUND;
}

int kelp_viewer_image_files(const char *tiff, const char *mission_path, char *image, size_t icap, char *info,
                            size_t infocap)
{
    char base[PATH_MAX];
    if (tiff[0] != '/' && mission_path && strchr(mission_path, '/')) {
        const char *s = strrchr(mission_path, '/');
        snprintf(base, sizeof base, "%.*s/%s", (int)(s - mission_path), mission_path, tiff);
    } else {
        snprintf(base, sizeof base, "%s", tiff);
    }
    char stem[PATH_MAX];
    snprintf(stem, sizeof stem, "%s", base);
    char *dot = strrchr(stem, '.');
    if (dot && !strchr(dot, '/')) *dot = '\0';
    snprintf(info, infocap, "%s.info", stem);
    static const char *const ext[] = {".png", ".jpg", ".jpeg"};
    for (size_t i = 0; i < sizeof ext / sizeof ext[0]; i++) {
        snprintf(image, icap, "%s%s", stem, ext[i]);
        if (is_file(image)) return 0;
    }
    snprintf(image, icap, "%s", base);
    return is_file(image) ? 0 : KELP_ERR_NOTFOUND;
}

int kelp_viewer_read_info(const char *path, double *lat_n, double *lat_s, double *lon_e, double *lon_w, kelp_diag *d)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        (void)kelp_failf(d, KELP_ERR_IO, "%s: %s", path, strerror(errno));
        return KELP_ERR_IO;
    }
    char line[256];
    unsigned have = 0, lineno = 0;
    double *dst[4] = {lat_n, lat_s, lon_e, lon_w};
    static const char *const keys[4] = {"lat_north", "lat_south", "lon_east", "lon_west"};
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *c = strstr(line, "//");
        if (c) *c = '\0';
        char *eq = strchr(line, '=');
        if (!eq) continue;
        *eq = '\0';
        char *k = line, *v = eq + 1;
        while (*k == ' ' || *k == '\t') k++;
        size_t kl = strlen(k);
        while (kl && (k[kl - 1] == ' ' || k[kl - 1] == '\t')) k[--kl] = '\0';
        for (unsigned i = 0; i < 4; i++) {
            if (!kelp_util_strieq(k, keys[i])) continue;
            if (kelp_util_parse_finite(v, strlen(v), dst[i]) < 0) {
                (void)kelp_failf(d, KELP_ERR_IO, "%s:%u: %s: not a number", path, lineno, keys[i]);
                fclose(f);
                return KELP_ERR_PARSE;
            }
            have |= 1u << i;
        }
    }
    fclose(f);
    if (have != 15u) {
        (void)kelp_failf(d, KELP_ERR_IO, "%s: needs lat_north, lat_south, lon_east and lon_west", path);
        return KELP_ERR_PARSE;
    }
    return 0;
}
