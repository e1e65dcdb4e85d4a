/* Image comparison: identical images, known Lab differences through the whole
 * image path, the common white, the box blur's border rule, bad input. */
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "compare.h"
#include "heatmap.h"
#include "image_io.h"
#include "testutil.h"

static spm_image make(int w, int h)
{
    spm_image img = {w, h, calloc((size_t)w * h * 3, sizeof(float)), 0};
    return img;
}

/* XYZ -> linear RGB by the exact inverse of spm_linear_srgb_to_xyz, which compare
 * uses for reading (colour.h's two IEC matrices are each rounded to 4 decimals and
 * so are inverse only to about 1e-4). */
static void xyz_to_rgb_exact(const double xyz[3], double rgb[3])
{
    double m[3][3], col[3];
    for (int j = 0; j < 3; j++) {
        double e[3] = {j == 0, j == 1, j == 2};
        spm_linear_srgb_to_xyz(e, col);
        for (int i = 0; i < 3; i++)
            m[i][j] = col[i];
    }
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; i++) {  /* Cramer's rule */
        double t[3][3];
        memcpy(t, m, sizeof t);
        for (int k = 0; k < 3; k++)
            t[k][i] = xyz[k];
        rgb[i] = (t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) -
                  t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
                  t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0])) / det;
    }
}

/* Pixel i of img gets the colour lab under white (D65 chromaticity, Y = yn). */
static void set_lab(spm_image *img, int i, const double lab[3], double yn)
{
    double white[3], xyz[3], rgb[3];
    spm_white_d65(white);
    for (int c = 0; c < 3; c++)
        white[c] *= yn;
    spm_lab_to_xyz(lab, white, xyz);
    xyz_to_rgb_exact(xyz, rgb);
    for (int c = 0; c < 3; c++)
        img->rgb[3 * i + c] = (float)rgb[c];
}

static void identical(void)
{
    spm_image a = make(7, 5), b = make(7, 5);
    for (int i = 0; i < 7 * 5 * 3; i++)
        a.rgb[i] = b.rgb[i] = (float)((i * 7919) % 101) / 50.0f;
    spm_compare_opts o = {5, 0};
    spm_compare_result r;
    spm_error err = {{0}};
    CHECK(spm_compare_images(&a, &b, &o, &r, &err) == 0, "%s", err.msg);
    CHECK(r.de00.max == 0 && r.deab.max == 0 && r.de00.mean == 0, "identical images differ: %g",
          r.de00.max);
    CHECK(r.de00.buckets[0] == 35 && r.deab.buckets[0] == 35, "bucket <1 holds %lld", r.de00.buckets[0]);
    spm_compare_result_free(&r);
    free(a.rgb);
    free(b.rgb);
}

/* A lightness shift: Delta E*ab = |dL| exactly, and CIEDE2000 = |dL| / S_L with
 * S_L = 1 + 0.015 (L-50)^2 / sqrt(20 + (L-50)^2) at the mean L (Sharma et al. 2005
 * eq. 12; no chroma or hue terms as a*, b* are equal). Tolerance: float32 pixels
 * carry a relative 6e-8, moving L* by < 1e-5; 1e-4 is generous yet tight enough to
 * catch a wrong white or a missing S_L. */
static void lightness_shift(void)
{
    const double la[3] = {60, 20, -10}, lb[3] = {62.5, 20, -10}; /* 2.5: away from bucket edges */
    spm_image a = make(4, 4), b = make(4, 4);
    for (int i = 0; i < 16; i++) {
        set_lab(&a, i, la, 1.0);
        set_lab(&b, i, lb, 1.0);
    }
    spm_compare_opts o = {5, 1.0};
    spm_compare_result r;
    spm_error err = {{0}};
    CHECK(spm_compare_images(&a, &b, &o, &r, &err) == 0, "%s", err.msg);
    double lbar = 61.25, d = (lbar - 50) * (lbar - 50);
    double sl = 1 + 0.015 * d / sqrt(20 + d);
    CHECK_NEAR(r.deab.mean, 2.5, 1e-4, "dE*ab of a 2.5-unit lightness shift");
    CHECK_NEAR(r.deab.max, 2.5, 1e-4, "dE*ab max");
    CHECK_NEAR(r.de00.mean, 2.5 / sl, 1e-4, "dE00 of a 2.5-unit lightness shift");
    CHECK_NEAR(r.de00.p99, 2.5 / sl, 1e-4, "dE00 p99");
    CHECK(r.de00.buckets[2] == 16 && r.deab.buckets[2] == 16, "buckets: dE00 %.3f and dEab in [2,3)",
          r.de00.mean);
    spm_compare_result_free(&r);
    free(a.rgb);
    free(b.rgb);
}

/* The 34 pairs of Sharma, Wu & Dalal (2005) as a 34x1 image pair: each pixel's
 * CIEDE2000 must be the published one. Tolerance: the table has 4 decimals
 * (+-5e-5) and float32 pixels move each Lab value by < 1e-5 (the published pairs'
 * sensitivity is at most a few units per unit): 2e-4. Pairs 10 and 14 sit exactly
 * at |h1' - h2'| = 180 degrees, where CIEDE2000 jumps (Sharma et al. discuss it);
 * float32 pixels may land them on either side, so they are left out. */
static void sharma_pairs(void)
{
    const char *path = SPM_SOURCE_DIR "/tests/data/ciede2000_sharma2005.csv";
    FILE *f = fopen(path, "r");
    CHECK(f != NULL, "cannot open %s", path);
    if (!f)
        return;
    double row[40][7];
    int n = 0;
    char line[256];
    while (fgets(line, sizeof line, f) && n < 40)
        if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &row[n][0], &row[n][1], &row[n][2], &row[n][3],
                   &row[n][4], &row[n][5], &row[n][6]) == 7)
            n++;
    fclose(f);
    CHECK(n == 34, "read %d pairs", n);
    spm_image a = make(n, 1), b = make(n, 1);
    for (int i = 0; i < n; i++) {
        set_lab(&a, i, row[i], 1.0);
        set_lab(&b, i, row[i] + 3, 1.0);
    }
    spm_compare_opts o = {0, 1.0};
    spm_compare_result r;
    spm_error err = {{0}};
    CHECK(spm_compare_images(&a, &b, &o, &r, &err) == 0, "%s", err.msg);
    for (int i = 0; r.de00_map && i < n; i++)
        if (i + 1 != 10 && i + 1 != 14)
            CHECK(fabs(r.de00_map[i] - row[i][6]) <= 2e-4, "Sharma pair %d: %.5f vs %.4f", i + 1,
                  r.de00_map[i], row[i][6]);
    spm_compare_result_free(&r);
    free(a.rgb);
    free(b.rgb);
}

/* The white comes from the FIRST image: a uniform grey reference is L* = 100, and a
 * grey of L* = 90 beside it differs by Delta E*ab = 10 (greys: a* = b* = 0). */
static void white_from_reference(void)
{
    const double l100[3] = {100, 0, 0}, l90[3] = {90, 0, 0};
    spm_image a = make(3, 3), b = make(3, 3);
    for (int i = 0; i < 9; i++) {
        set_lab(&a, i, l100, 2.0);
        set_lab(&b, i, l90, 2.0);
    }
    spm_compare_opts o = {3, 0};
    spm_compare_result r;
    spm_error err = {{0}};
    CHECK(spm_compare_images(&a, &b, &o, &r, &err) == 0, "%s", err.msg);
    CHECK_NEAR(r.white_y, 2.0, 1e-5, "Yn from the reference (float pixels)");
    CHECK_NEAR(r.deab.mean, 10.0, 1e-4, "dE*ab of L* 100 vs 90");
    spm_compare_result_free(&r);
    /* Swapping the images changes the white to the darker one's Y. */
    spm_image a2 = make(3, 3), b2 = make(3, 3);
    memcpy(a2.rgb, b.rgb, 27 * sizeof(float));
    memcpy(b2.rgb, a.rgb, 27 * sizeof(float));
    CHECK(spm_compare_images(&a2, &b2, &o, &r, &err) == 0, "%s", err.msg);
    double y90 = pow((90 + 16) / 116.0, 3) * 2.0;
    CHECK_NEAR(r.white_y, y90, 1e-5, "Yn from the swapped reference");
    spm_compare_result_free(&r);
    free(a.rgb);
    free(b.rgb);
    free(a2.rgb);
    free(b2.rgb);
}

/* Border rule: each output is the mean over the window's part inside the image,
 * computed here by brute force. */
static void blur_borders(void)
{
    enum { W = 6, H = 4 };
    const int sizes[] = {3, 5, 13};
    for (int s = 0; s < 3; s++) {
        int n = sizes[s], r = n / 2;
        spm_image img = make(W, H);
        float orig[W * H * 3];
        for (int i = 0; i < W * H * 3; i++)
            orig[i] = img.rgb[i] = (float)((i * 37) % 17) - 4.0f;
        spm_box_blur(&img, n);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                for (int c = 0; c < 3; c++) {
                    double sum = 0;
                    int cnt = 0;
                    for (int yy = y - r; yy <= y + r; yy++)
                        for (int xx = x - r; xx <= x + r; xx++)
                            if (xx >= 0 && yy >= 0 && xx < W && yy < H) {
                                sum += orig[3 * (yy * W + xx) + c];
                                cnt++;
                            }
                    /* values up to 12 through two float passes: 1e-5 */
                    CHECK_NEAR(img.rgb[3 * (y * W + x) + c], sum / cnt, 1e-5, "blurred pixel");
                }
        free(img.rgb);
    }
    /* A uniform image stays uniform up to the border (no zero padding). */
    spm_image u = make(5, 5);
    for (int i = 0; i < 75; i++)
        u.rgb[i] = 0.75f;
    spm_box_blur(&u, 5);
    CHECK(u.rgb[0] == 0.75f && u.rgb[74] == 0.75f, "uniform corner became %g", u.rgb[0]);
    free(u.rgb);
}

static void bad_input(void)
{
    spm_image a = make(4, 3), b = make(3, 4);
    spm_compare_opts o = {5, 0};
    spm_compare_result r;
    spm_error err = {{0}};
    CHECK(spm_compare_images(&a, &b, &o, &r, &err) != 0, "different sizes accepted");
    CHECK(strstr(err.msg, "4x3") && strstr(err.msg, "3x4"), "message gives both sizes: %s", err.msg);
    spm_image c = make(4, 3);
    CHECK(spm_compare_images(&a, &c, &o, &r, &err) != 0, "black reference accepted without --white-y");
    o.blur = 4;
    o.white_y = 1;
    CHECK(spm_compare_images(&a, &c, &o, &r, &err) != 0, "even blur accepted");
    free(a.rgb);
    free(b.rgb);
    free(c.rgb);
}

/* The heat map: size as laid out, map pixels in the scale's colours, bar ends. */
static void heatmap(void)
{
    char dir[] = "/tmp/spm_test_heatmap.XXXXXX", path[64];
    if (!mkdtemp(dir))
        return;
    snprintf(path, sizeof path, "%s/h.png", dir);
    const double de[4] = {0.0, 2.5, 5.0, 50.0};
    spm_error err = {{0}};
    CHECK(spm_heatmap_write(path, 2, 2, de, &err) == 0, "%s", err.msg);
    spm_image img;
    CHECK(spm_image_read(path, &img, &err) == 0, "%s", err.msg);
    int cw, ch;
    spm_heatmap_size(2, 2, &cw, &ch);
    CHECK(img.width == cw && img.height == ch, "heat map %dx%d, expected %dx%d", img.width, img.height, cw, ch);
    for (int i = 0; img.rgb && i < 4; i++) {
        unsigned char want[3];
        spm_heatmap_colour(de[i], want);
        const float *p = img.rgb + 3 * ((size_t)(i / 2) * img.width + i % 2);
        for (int c = 0; c < 3; c++) {
            double v = p[c] <= 0.0031308f ? 12.92 * p[c] : 1.055 * pow(p[c], 1 / 2.4) - 0.055;
            CHECK(lround(255 * v) == want[c], "map pixel %d channel %d", i, c);
        }
    }
    unsigned char lo[3], hi[3], over[3];
    spm_heatmap_colour(0, lo);
    spm_heatmap_colour(SPM_HEATMAP_MAX, hi);
    spm_heatmap_colour(1e9, over);
    CHECK(memcmp(lo, hi, 3) && !memcmp(hi, over, 3), "scale ends: distinct, saturating");
    spm_image_free(&img);
    remove(path);
    remove(dir);
}

int main(void)
{
    identical();
    lightness_shift();
    sharma_pairs();
    white_from_reference();
    blur_borders();
    bad_input();
    heatmap();
    TEST_END();
}
