/* Film accumulation, output format choice and checks, EXR values, PNG tone mapping. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "colour.h"
#include "film.h"
#include "image_io.h"
#include "output.h"
#include "render_stats.h"
#include "testutil.h"
#include "tonemap.h"

static char dir[256];

static const char *in_dir(const char *name)
{
    static char buf[512];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

/* IEC 61966-2-1 encoding written out here, independent of colour.c. */
static int srgb8(double lin)
{
    lin = lin < 0 ? 0 : lin > 1 ? 1 : lin;
    double v = lin <= 0.0031308 ? 12.92 * lin : 1.055 * pow(lin, 1 / 2.4) - 0.055;
    return (int)lround(255 * v);
}

/* Passes hold per-pixel sums; the image is the total over the total sample count. */
static void film_passes(void)
{
    enum { W = 3, H = 2, N = W * H };
    const int spp[3] = {1, 2, 4};
    spm_film f;
    spm_error err;
    CHECK(spm_film_init(&f, 0, 5, &err) != 0, "zero width accepted");
    CHECK(spm_film_init(&f, 1 << 16, 1 << 16, &err) != 0, "2^32 pixels accepted");
    CHECK(spm_film_init(&f, W, H, &err) == 0, "%s", err.msg);
    float img[N * 3];
    spm_film_resolve(&f, img);
    CHECK(img[0] == 0 && img[N * 3 - 1] == 0, "film without passes is not black");
    /* Pass k's samples all have value (k+1)*(i+1) (negative for channel Z), so its sum is that times spp. */
    for (int k = 0; k < 3; k++) {
        float pass[N * 3];
        for (int i = 0; i < N; i++)
            for (int c = 0; c < 3; c++)
                pass[3 * i + c] = (float)((k + 1) * (i + 1) * spp[k]) * (c == 2 ? -1.0f : 1.0f + c);
        spm_film_add_pass(&f, pass, spp[k]);
    }
    CHECK(f.samples == 7, "samples %lld", f.samples);
    spm_film_resolve(&f, img);
    for (int i = 0; i < N; i++) {
        /* sum over passes of (k+1)(i+1) spp_k = (1*1 + 2*2 + 3*4)(i+1) = 17(i+1) */
        double mean = 17.0 * (i + 1) / 7.0;
        CHECK_NEAR(img[3 * i], mean, 1e-6 * mean, "X = sum / samples");  /* float rounding */
        CHECK_NEAR(img[3 * i + 1], 2 * mean, 2e-6 * mean, "Y");
        CHECK_NEAR(img[3 * i + 2], -mean, 1e-6 * mean, "Z (negative kept)");
    }
    /* A NaN pixel in a pass is counted and left out; the others go on. */
    float pass[N * 3];
    for (int i = 0; i < N * 3; i++)
        pass[i] = 7.0f;
    pass[4] = NAN;
    spm_film_add_pass(&f, pass, 1);
    CHECK(f.nonfinite == 1, "nonfinite %lld", f.nonfinite);
    spm_film_resolve(&f, img);
    CHECK(isfinite(img[4]), "NaN reached the image");
    CHECK_NEAR(img[0], (17.0 + 7.0) / 8.0, 1e-6 * 3, "pixel 0 after the fourth pass");
    spm_film_free(&f);
}

static void output_check(void)
{
    spm_error err = {{0}};
    CHECK(spm_output_check(in_dir("a.exr"), &err) == 0, "%s", err.msg);
    CHECK(spm_output_check(in_dir("a.PNG"), &err) == 0, "upper-case extension: %s", err.msg);
    CHECK(spm_output_check(in_dir("a.tif"), &err) == 0, "%s", err.msg);
    CHECK(spm_output_check(in_dir("a.gif"), &err) != 0, "unsupported extension accepted");
    CHECK(strstr(err.msg, "a.gif"), "message names the file: %s", err.msg);
    CHECK(spm_output_check(in_dir("noext"), &err) != 0, "no extension accepted");
    CHECK(spm_output_check(in_dir("missing/a.exr"), &err) != 0, "missing directory accepted");
    CHECK(strstr(err.msg, "does not exist"), "message: %s", err.msg);
    mkdir(in_dir("sub.png"), 0755);
    CHECK(spm_output_check(in_dir("sub.png"), &err) != 0, "a directory accepted as output");
    CHECK(spm_output_check("relative.exr", &err) == 0, "current directory: %s", err.msg);
}

/* Film to EXR: linear sRGB float32 with negative and > 1 values as computed. */
static void film_to_exr(void)
{
    const double rgb[4][3] = {{1.5, 0.25, -0.125}, {-0.3, 2.0, 0.5}, {100.0, 50.0, 25.0}, {0, 0, 0}};
    spm_film f;
    spm_error err = {{0}};
    spm_film_init(&f, 2, 2, &err);
    float pass[12];
    for (int i = 0; i < 4; i++) {
        double xyz[3];
        spm_linear_srgb_to_xyz(rgb[i], xyz);
        for (int c = 0; c < 3; c++)
            pass[3 * i + c] = (float)xyz[c];
    }
    spm_film_add_pass(&f, pass, 1);
    CHECK(spm_output_write_film(in_dir("film.exr"), &f, NULL, &err) == 0, "%s", err.msg);
    spm_image img;
    CHECK(spm_image_read(in_dir("film.exr"), &img, &err) == 0, "%s", err.msg);
    for (int i = 0; img.rgb && i < 4; i++) {
        double xyz[3] = {pass[3 * i], pass[3 * i + 1], pass[3 * i + 2]}, out[3];
        spm_xyz_to_linear_srgb(xyz, out);
        for (int c = 0; c < 3; c++) {
            CHECK(img.rgb[3 * i + c] == (float)out[c], "EXR value %d.%d: %.9g vs %.9g", i, c,
                  img.rgb[3 * i + c], (float)out[c]);
            /* Back to the original only as far as the IEC matrices (both published to 4
             * decimals, so not exact inverses) allow: 1e-4 of the pixel's channel sum. */
            double mag = fabs(rgb[i][0]) + fabs(rgb[i][1]) + fabs(rgb[i][2]);
            CHECK_NEAR(img.rgb[3 * i + c], rgb[i][c], 1e-4 * mag, "original rgb");
        }
    }
    spm_image_free(&img);
    spm_film_free(&f);
}

static void grey(float *xyz, double y)
{
    double w[3];
    spm_white_d65(w);
    for (int c = 0; c < 3; c++)
        xyz[c] = (float)(w[c] * y);
}

/* Reads a PNG back as 8-bit codes (the reader decodes to linear; encode again). */
static void read_codes(const char *path, int n, int *codes)
{
    spm_image img;
    spm_error err = {{0}};
    CHECK(spm_image_read(path, &img, &err) == 0, "%s", err.msg);
    for (int i = 0; i < n * 3; i++)
        codes[i] = img.rgb && i < img.width * img.height * 3 ? srgb8(img.rgb[i]) : -1;
    spm_image_free(&img);
}

/* The D65 white of colour.h and the sRGB matrices' white differ in the 4th digit, so a
 * grey's expected code may be off by one at a rounding boundary: tolerance 1 code. */
static void png_tonemap(void)
{
    enum { N = 6 };
    const double ys[N] = {0.0, 0.2, 0.5, 1.0, 2.0, 4.0};
    float xyz[N * 3];
    for (int i = 0; i < N; i++)
        grey(xyz + 3 * i, ys[i]);
    spm_tonemap tm;
    spm_error err = {{0}};
    spm_tonemap_default(&tm);
    CHECK(spm_tonemap_set_exposure(&tm, "0.5", &err) == 0, "%s", err.msg);
    CHECK(spm_output_write_xyz(in_dir("grey.png"), N, 1, xyz, &tm, &err) == 0, "%s", err.msg);
    int codes[N * 3];
    read_codes(in_dir("grey.png"), N, codes);
    for (int i = 0; i < N; i++)
        for (int c = 0; c < 3; c++)
            CHECK(abs(codes[3 * i + c] - srgb8(0.5 * ys[i])) <= 1, "linear e=0.5, Y=%g: code %d, expected %d",
                  ys[i], codes[3 * i + c], srgb8(0.5 * ys[i]));

    /* Thesis operator, exposure 1: display Y = Y / (5 + Y). */
    CHECK(spm_tonemap_select(&tm, "thesis", &err) == 0, "%s", err.msg);
    spm_tonemap_set_exposure(&tm, "auto", &err);
    CHECK(spm_output_write_xyz(in_dir("thesis.png"), N, 1, xyz, &tm, &err) == 0, "%s", err.msg);
    read_codes(in_dir("thesis.png"), N, codes);
    for (int i = 0; i < N; i++)
        CHECK(abs(codes[3 * i + 1] - srgb8(ys[i] / (5 + ys[i]))) <= 1, "thesis Y=%g: code %d", ys[i],
              codes[3 * i + 1]);

    /* Out of range colour: hue kept by dividing by the largest channel; negatives to 0. */
    const double hot[3] = {2.0, 0.5, 0.25}, neg[3] = {0.5, -0.2, 0.1};
    double x1[3], x2[3];
    spm_linear_srgb_to_xyz(hot, x1);
    spm_linear_srgb_to_xyz(neg, x2);
    float px[6] = {(float)x1[0], (float)x1[1], (float)x1[2], (float)x2[0], (float)x2[1], (float)x2[2]};
    unsigned char out[6];
    spm_tonemap_default(&tm);
    spm_tonemap_set_exposure(&tm, "1", &err);
    spm_tonemap_apply(&tm, px, 2, out);
    const double want[6] = {1.0, 0.25, 0.125, 0.5, 0.0, 0.1};
    for (int i = 0; i < 6; i++)  /* float XYZ only: exact codes */
        CHECK(out[i] == srgb8(want[i]), "channel %d: %d vs %d", i, out[i], srgb8(want[i]));

    CHECK(spm_tonemap_select(&tm, "reinhard", &err) != 0, "unknown operator accepted");
    CHECK(spm_tonemap_set_exposure(&tm, "-1", &err) != 0, "negative exposure accepted");
    CHECK(spm_tonemap_set_exposure(&tm, "2x", &err) != 0, "'2x' accepted");
}

/* Automatic exposure: the 99th percentile of Y (type 7) maps to 1. */
static void auto_exposure(void)
{
    enum { N = 200 };
    float xyz[N * 3];
    for (int i = 0; i < N; i++)
        grey(xyz + 3 * ((i * 37) % N), (double)(i + 1));  /* Y = 1..200, shuffled */
    spm_tonemap tm;
    spm_tonemap_default(&tm);
    /* rank 0.99 * 199 = 197.01 between the sorted Y 198 and 199 */
    double p99 = 198.0 + 0.01 * 1.0;
    double w[3];
    spm_white_d65(w);  /* Y of the grey is w[1] * y (w[1] = 1 by the header) */
    CHECK_NEAR(spm_tonemap_exposure(&tm, xyz, N), 1.0 / (p99 * w[1]), 1e-6 / p99, "auto exposure");
    float black[6] = {0};
    CHECK(spm_tonemap_exposure(&tm, black, 2) == 1.0, "black image exposure is not 1");
}

/* The end-of-render warning about NaN/Inf left out: past 0.1% of the samples
 * or of the pixels' pass sums, not at it. */
static void dropped_warning(void)
{
    spm_film f;
    spm_error err;
    CHECK(spm_film_init(&f, 10, 10, &err) == 0, "%s", err.msg);
    spm_run_result r;
    memset(&r, 0, sizeof r);
    r.total.paths = 10000;
    r.passes_in_film = 10; /* 1000 pixel pass sums */
    spm_quiet_warnings = 1;
    CHECK(!spm_render_warn_dropped(&r, &f), "nothing dropped, no warning");
    r.total.nonfinite = 10;
    CHECK(!spm_render_warn_dropped(&r, &f), "0.1%% of the samples: no warning");
    r.total.nonfinite = 11;
    CHECK(spm_render_warn_dropped(&r, &f), "0.11%% of the samples: a warning");
    r.total.nonfinite = 0;
    /* pass sums the film left out, counted by the film itself */
    float pass[300];
    for (int i = 0; i < 300; i++)
        pass[i] = 1.0f;
    pass[4] = INFINITY;
    for (int p = 0; p < 10; p++)
        spm_film_add_pass(&f, pass, 1);
    CHECK(f.nonfinite == 10, "the film counts the dropped sums (%lld)", f.nonfinite);
    CHECK(spm_render_warn_dropped(&r, &f), "1%% of the pass sums: a warning");
    f.nonfinite = 1;
    CHECK(!spm_render_warn_dropped(&r, &f), "0.1%% of the pass sums: no warning");
    spm_quiet_warnings = 0;
    spm_film_free(&f);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/spm_test_film.XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    film_passes();
    output_check();
    film_to_exr();
    png_tonemap();
    auto_exposure();
    dropped_warning();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    TEST_END();
}
