/* Delta E heat map: the map, a colour bar, tick marks and digit labels. */
#include "heatmap.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "image_io.h"

/* Colour stops (Delta E, sRGB): dark for "invisible", blue/cyan below the usual
 * noticeability threshold of about 2, green..yellow for visible, red for large. */
static const struct {
    double de;
    double rgb[3];
} stops[] = {
    {0.0, {0.02, 0.02, 0.12}}, {1.0, {0.10, 0.25, 0.85}}, {2.0, {0.05, 0.75, 0.85}},
    {3.0, {0.20, 0.80, 0.20}}, {5.0, {1.00, 0.90, 0.10}}, {10.0, {0.90, 0.10, 0.10}},
};
#define NSTOPS ((int)(sizeof stops / sizeof stops[0]))

/* Layout in pixels. */
#define GAP 6          /* map to bar */
#define BAR_W 10
#define TICK_W 3
#define LABEL_GAP 2
#define LABEL_W 7      /* "10": two 3-pixel digits and a space */
#define RIGHT_PAD 3
#define MIN_H 128      /* room for 11 ticks and their labels */
#define BAR_MARGIN 5   /* above and below the bar: half a label */

/* Digits 0-9, 5 rows of 3 bits, most significant bit leftmost. */
static const unsigned char font3x5[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
};

void spm_heatmap_colour(double de, unsigned char rgb[3])
{
    if (!(de > 0))
        de = 0;
    int k = 1;
    while (k < NSTOPS - 1 && de > stops[k].de)
        k++;
    double t = (de - stops[k - 1].de) / (stops[k].de - stops[k - 1].de);
    t = t > 1 ? 1 : t;
    for (int c = 0; c < 3; c++)
        rgb[c] = (unsigned char)lround(255.0 * (stops[k - 1].rgb[c] + t * (stops[k].rgb[c] - stops[k - 1].rgb[c])));
}

void spm_heatmap_size(int width, int height, int *canvas_w, int *canvas_h)
{
    *canvas_w = width + GAP + BAR_W + TICK_W + LABEL_GAP + LABEL_W + RIGHT_PAD;
    *canvas_h = height > MIN_H ? height : MIN_H;
}

typedef struct {
    unsigned char *px;
    int w, h;
} canvas;

static void put(canvas *cv, int x, int y, const unsigned char rgb[3])
{
    if (x >= 0 && y >= 0 && x < cv->w && y < cv->h)
        memcpy(cv->px + 3 * ((size_t)y * cv->w + x), rgb, 3);
}

static void draw_digit(canvas *cv, int x, int y, int d, const unsigned char rgb[3])
{
    for (int r = 0; r < 5; r++)
        for (int c = 0; c < 3; c++)
            if (font3x5[d][r] & (4 >> c))
                put(cv, x + c, y + r, rgb);
}

int spm_heatmap_write(const char *path, int width, int height, const double *de, spm_error *err)
{
    canvas cv;
    spm_heatmap_size(width, height, &cv.w, &cv.h);
    cv.px = spm_xmalloc((size_t)cv.w * cv.h * 3);
    memset(cv.px, 40, (size_t)cv.w * cv.h * 3);  /* dark grey background */
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            unsigned char rgb[3];
            spm_heatmap_colour(de[(size_t)y * width + x], rgb);
            put(&cv, x, y, rgb);
        }
    /* Bar: value SPM_HEATMAP_MAX at row top, 0 at row bottom. */
    int top = BAR_MARGIN, bottom = cv.h - 1 - BAR_MARGIN, x0 = width + GAP;
    for (int y = top; y <= bottom; y++) {
        unsigned char rgb[3];
        spm_heatmap_colour(SPM_HEATMAP_MAX * (bottom - y) / (bottom - top), rgb);
        for (int x = 0; x < BAR_W; x++)
            put(&cv, x0 + x, y, rgb);
    }
    static const unsigned char ink[3] = {230, 230, 230};
    for (int v = 0; v <= (int)SPM_HEATMAP_MAX; v++) {
        int y = bottom - (int)lround((double)v / SPM_HEATMAP_MAX * (bottom - top));
        for (int x = 0; x < TICK_W; x++)
            put(&cv, x0 + BAR_W + x, y, ink);
        if (v % 2)
            continue;
        int lx = x0 + BAR_W + TICK_W + LABEL_GAP;
        if (v >= 10) {
            draw_digit(&cv, lx, y - 2, v / 10, ink);
            lx += 4;
        }
        draw_digit(&cv, lx, y - 2, v % 10, ink);
    }
    int rc = spm_image_write(path, cv.w, cv.h, cv.px, SPM_PIXEL_UINT8, err);
    free(cv.px);
    return rc;
}
