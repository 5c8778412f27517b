/* kelp-plot: colour names as MOOS tools write them (X11/CSS names, any case, with or without
 * '_' between words), plus hex forms. */
#include <ctype.h>
#include <string.h>
#include <kelp/edge/plot.h>
#include <kelp/util.h>

static const struct {
    const char *name;
    unsigned rgb;
} colors[] = {
    {"white", 0xffffff},        {"black", 0x000000},          {"red", 0xff0000},          {"green", 0x00ff00},
    {"blue", 0x0000ff},         {"yellow", 0xffff00},         {"orange", 0xffa500},       {"purple", 0x800080},
    {"pink", 0xffc0cb},         {"gray", 0x808080},           {"grey", 0x808080},         {"cyan", 0x00ffff},
    {"magenta", 0xff00ff},      {"brown", 0xa52a2a},          {"gold", 0xffd700},         {"lime", 0x00ff00},
    {"navy", 0x000080},         {"olive", 0x808000},          {"teal", 0x008080},         {"silver", 0xc0c0c0},
    {"maroon", 0x800000},       {"coral", 0xff7f50},          {"salmon", 0xfa8072},       {"tan", 0xd2b48c},
    {"khaki", 0xf0e68c},        {"violet", 0xee82ee},         {"turquoise", 0x40e0d0},    {"dodgerblue", 0x1e90ff},
    {"darkgreen", 0x006400},    {"lightgreen", 0x90ee90},     {"darkred", 0x8b0000},      {"hotpink", 0xff69b4},
    {"lightblue", 0xadd8e6},    {"darkblue", 0x00008b},       {"skyblue", 0x87ceeb},      {"steelblue", 0x4682b4},
    {"darkorange", 0xff8c00},   {"orangered", 0xff4500},      {"firebrick", 0xb22222},    {"crimson", 0xdc143c},
    {"indigo", 0x4b0082},       {"lightgray", 0xd3d3d3},      {"lightgrey", 0xd3d3d3},    {"darkgray", 0xa9a9a9},
    {"darkgrey", 0xa9a9a9},     {"slategray", 0x708090},      {"seagreen", 0x2e8b57},     {"forestgreen", 0x228b22},
    {"limegreen", 0x32cd32},    {"yellowgreen", 0x9acd32},    {"chartreuse", 0x7fff00},   {"aqua", 0x00ffff},
    {"aquamarine", 0x7fffd4},   {"royalblue", 0x4169e1},      {"midnightblue", 0x191970}, {"cornflowerblue", 0x6495ed},
    {"plum", 0xdda0dd},         {"orchid", 0xda70d6},         {"beige", 0xf5f5dc},        {"ivory", 0xfffff0},
    {"chocolate", 0xd2691e},    {"sienna", 0xa0522d},         {"peru", 0xcd853f},         {"goldenrod", 0xdaa520},
    {"darkgoldenrod", 0xb8860b}, {"lightyellow", 0xffffe0},   {"darkcyan", 0x008b8b},     {"darkmagenta", 0x8b008b},
    {"darkviolet", 0x9400d3},   {"deeppink", 0xff1493},       {"deepskyblue", 0x00bfff},  {"lightcoral", 0xf08080},
    {"mediumblue", 0x0000cd},   {"springgreen", 0x00ff7f},    {"lawngreen", 0x7cfc00},    {"tomato", 0xff6347},
    {"wheat", 0xf5deb3},        {"lavender", 0xe6e6fa},       {"mintcream", 0xf5fffa},    {"bisque", 0xffe4c4},
};

int kelp_plot_color(const char *name, double rgb[3])
{
    char n[64] = "";
    size_t k = 0;
    for (const char *p = name; *p && k + 1 < sizeof n; p++)
        if (*p != '_' && *p != ' ' && *p != '-') n[k++] = (char)tolower((unsigned char)*p);
    n[k] = 0;
    if (!strcmp(n, "invisible") || !strcmp(n, "off") || !strcmp(n, "none") || !strcmp(n, "empty")) return 1;
    const char *h = NULL;
    if (n[0] == '#') h = n + 1;
    else if (!strncmp(n, "hex:", 4)) h = n + 4;
    if (h) {
        /* "ff8800" or MOOS's "hex:ff,88,00" (commas already kept) */
        char d[7] = "";
        size_t m = 0;
        for (const char *p = h; *p && m < 7; p++)
            if (*p != ',') d[m++] = *p;
        if (m != 6) return -1;
        unsigned v = 0;
        for (int i = 0; i < 6; i++) {
            int x = kelp_util_hex_digit(d[i]);
            if (x < 0) return -1;
            v = v * 16 + (unsigned)x;
        }
        rgb[0] = ((v >> 16) & 0xff) / 255.0;
        rgb[1] = ((v >> 8) & 0xff) / 255.0;
        rgb[2] = (v & 0xff) / 255.0;
        return 0;
    }
    for (size_t i = 0; i < sizeof colors / sizeof colors[0]; i++)
        if (strcmp(n, colors[i].name) == 0) {
            rgb[0] = ((colors[i].rgb >> 16) & 0xff) / 255.0;
            rgb[1] = ((colors[i].rgb >> 8) & 0xff) / 255.0;
            rgb[2] = (colors[i].rgb & 0xff) / 255.0;
            return 0;
        }
    return -1;
}
