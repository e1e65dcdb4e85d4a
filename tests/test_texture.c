/* Image textures (texture.h) against values computed by hand: wrap modes,
 * texel and bilinear lookups, the pyramid's levels (power-of-two and odd
 * sizes), the level of detail of a footprint and the trilinear blend, a
 * procedural checkerboard, images read from files and from memory
 * (8-bit PNG sRGB-decoded, float EXR as it is), and glTF's texture
 * transform: its matrix, a one-byte map read through it, its footprint. */
#include "colour.h"
#include "geometry.h"
#include "image_io.h"
#include "paths.h"
#include "texture.h"
#include "testutil.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void wraps(void)
{
    static const struct { int i, n; spm_wrap m; int want; } c[] = {
        {-1, 4, SPM_WRAP_REPEAT, 3}, {5, 4, SPM_WRAP_REPEAT, 1}, {-8, 4, SPM_WRAP_REPEAT, 0},
        {-3, 4, SPM_WRAP_CLAMP, 0},  {7, 4, SPM_WRAP_CLAMP, 3},  {2, 4, SPM_WRAP_CLAMP, 2},
        {-1, 4, SPM_WRAP_MIRROR, 0}, {4, 4, SPM_WRAP_MIRROR, 3}, {5, 4, SPM_WRAP_MIRROR, 2},
        {8, 4, SPM_WRAP_MIRROR, 0},  {-5, 4, SPM_WRAP_MIRROR, 3}, {-9, 4, SPM_WRAP_MIRROR, 0},
        {0, 1, SPM_WRAP_MIRROR, 0},  {-1, 1, SPM_WRAP_REPEAT, 0},
    };
    for (size_t k = 0; k < sizeof c / sizeof c[0]; k++)
        CHECK(spm_wrap_index(c[k].i, c[k].n, c[k].m) == c[k].want, "wrap %d of %d mode %d: %d",
              c[k].i, c[k].n, c[k].m, spm_wrap_index(c[k].i, c[k].n, c[k].m));
}

/* A grey image from values, one float per texel. */
static void grey(int w, int h, const float *v, spm_wrap wu, spm_wrap wv, spm_texture *t)
{
    float *px = malloc(sizeof(float) * 3 * w * h);
    for (int i = 0; i < w * h; i++)
        px[3 * i] = px[3 * i + 1] = px[3 * i + 2] = v[i];
    spm_texture_from_pixels(w, h, px, wu, wv, t);
    free(px);
}

static float bil(const spm_texture *t, int level, double u, double v)
{
    float o[3];
    spm_texture_bilinear(t, level, u, v, o);
    return o[0];
}

/* 2 x 2: rows top to bottom 1 2 / 3 4 */
static void bilinear(void)
{
    const float v[4] = {1, 2, 3, 4};
    spm_texture t;
    grey(2, 2, v, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT, &t);
    CHECK_NEAR(bil(&t, 0, 0.25, 0.75), 1, 1e-6, "top-left texel centre");
    CHECK_NEAR(bil(&t, 0, 0.75, 0.25), 4, 1e-6, "bottom-right texel centre");
    CHECK_NEAR(bil(&t, 0, 0.5, 0.5), 2.5, 1e-6, "the centre: mean of four");
    CHECK_NEAR(bil(&t, 0, 0.375, 0.75), 1.25, 1e-6, "a quarter of the way to texel 2");
    CHECK_NEAR(bil(&t, 0, 0.0, 0.75), 1.5, 1e-6, "left edge, repeat: half texel 2");
    CHECK_NEAR(bil(&t, 0, 1.25, -0.25), 1, 1e-6, "repeat: u + 1, v - 1");
    CHECK_NEAR(bil(&t, 0, 1e12 + 0.25, 0.75), 1, 1e-3, "a far coordinate repeats");
    spm_texture_free(&t);
    grey(2, 2, v, SPM_WRAP_CLAMP, SPM_WRAP_CLAMP, &t);
    CHECK_NEAR(bil(&t, 0, 0.0, 0.75), 1, 1e-6, "left edge, clamp: texel 1");
    CHECK_NEAR(bil(&t, 0, -3.0, -3.0), 3, 1e-6, "clamp far below-left: bottom-left texel");
    spm_texture_free(&t);
    grey(2, 2, v, SPM_WRAP_MIRROR, SPM_WRAP_MIRROR, &t);
    CHECK_NEAR(bil(&t, 0, 1.25, 0.75), 2, 1e-6, "mirror: u 1.25 is u 0.75");
    CHECK_NEAR(bil(&t, 0, -0.25, 0.75), 1, 1e-6, "mirror: u -0.25 is u 0.25");
    CHECK_NEAR(bil(&t, 0, 0.0, 0.75), 1, 1e-6, "mirror at the edge: texel 1 twice");
    spm_texture_free(&t);
}

static void pyramid(void)
{
    float v[16];
    for (int i = 0; i < 16; i++)
        v[i] = (float)i; /* texel (x, y) = x + 4 y */
    spm_texture t;
    grey(4, 4, v, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT, &t);
    CHECK(t.nlevels == 3 && t.lv[1].w == 2 && t.lv[2].w == 1, "4x4: three levels (%d)",
          t.nlevels);
    const float l1[4] = {2.5f, 4.5f, 10.5f, 12.5f};
    for (int i = 0; i < 4; i++)
        CHECK_NEAR(t.lv[1].rgb[3 * i], l1[i], 1e-6, "4x4 level 1: 2x2 box");
    CHECK_NEAR(t.lv[2].rgb[0], 7.5, 1e-6, "4x4 level 2: the mean");
    spm_texture_free(&t);

    /* 5 x 1: level 1 is 2 x 1, each texel 2.5 wide: (a + b + c/2) / 2.5, (c/2 + d + e) / 2.5 */
    const float r[5] = {1, 2, 4, 8, 16};
    grey(5, 1, r, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT, &t);
    CHECK(t.nlevels == 3 && t.lv[1].w == 2 && t.lv[1].h == 1, "5x1: levels 5, 2, 1");
    CHECK_NEAR(t.lv[1].rgb[0], (1 + 2 + 2) / 2.5, 1e-6, "5x1 level 1, texel 0");
    CHECK_NEAR(t.lv[1].rgb[3], (2 + 8 + 16) / 2.5, 1e-6, "5x1 level 1, texel 1");
    CHECK_NEAR(t.lv[2].rgb[0], 31 / 5.0, 1e-5, "5x1 level 2: the mean");
    spm_texture_free(&t);

    /* 3 x 3: level 1 is 1 x 1, the mean */
    const float q[9] = {1, 2, 3, 4, 5, 6, 7, 8, 90};
    grey(3, 3, q, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT, &t);
    CHECK(t.nlevels == 2, "3x3: two levels");
    CHECK_NEAR(t.lv[1].rgb[0], 126 / 9.0, 1e-5, "3x3 level 1: the mean");
    spm_texture_free(&t);
}

/* 8 x 8 checks of 8 texels, white at the top left: levels 0..3 keep the
 * checks, level 4 (4 x 4) and above are grey 0.5. */
static void checker_and_lod(void)
{
    const float a[3] = {1, 1, 1}, b[3] = {0, 0, 0};
    spm_texture t;
    spm_texture_checker(8, 8, a, b, SPM_WRAP_REPEAT, &t);
    CHECK(t.nlevels == 7 && t.lv[0].w == 64, "64x64: seven levels (%d)", t.nlevels);
    float o[3];
    spm_texture_texel(&t, 0, 8, 0, o);
    CHECK(o[0] == 0, "the second check is black");
    spm_texture_texel(&t, 0, 9, 8, o);
    CHECK(o[0] == 1, "one check down it is white");
    for (int l = 0; l < 7; l++) {
        double u = 1.0 / 16, v = 1 - 1.0 / 16; /* the top-left check's centre */
        CHECK_NEAR(bil(&t, l, u, v), l <= 3 ? 1.0 : 0.5, 1e-6, "checker level at a check's centre");
    }
    CHECK_NEAR(spm_texture_lod(&t, 1.0 / 64), 0, 1e-12, "a footprint of one texel: lod 0");
    CHECK_NEAR(spm_texture_lod(&t, 4.0 / 64), 2, 1e-12, "four texels: lod 2");
    CHECK_NEAR(spm_texture_lod(&t, 3.0 / 64), 1.5849625007, 1e-9, "three texels: log2 3");
    CHECK_NEAR(spm_texture_lod(&t, 0.1 / 64), 0, 0, "under a texel: lod 0");
    CHECK_NEAR(spm_texture_lod(&t, 1e6), 6, 0, "beyond the image: the last level");
    /* lod 3.5 at a check's centre: half level 3 (1) and half level 4 (0.5) */
    spm_texture_trilinear(&t, 1.0 / 16, 1 - 1.0 / 16, sqrt(2.0) * 8 / 64, o);
    CHECK_NEAR(o[0], 0.75, 1e-5, "trilinear between levels 3 and 4");
    /* a ray cone's footprint: world triangle of area 2, uv area 1/2, cone
     * 0.1 wide at 60 degrees: 0.1 / 0.5 * sqrt(0.25) = 0.1 */
    const float uv[6] = {0, 0, 1, 0, 0, 1}, p[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
    CHECK_NEAR(spm_texture_cone_footprint(0.1, 0.5, uv, p), 0.1, 1e-12, "cone footprint");
    CHECK_NEAR(spm_texture_cone_footprint(0.1, -0.5, uv, p), 0.1, 1e-12, "cone from behind");
    const float flat[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    CHECK(spm_texture_cone_footprint(0.1, 0.5, uv, flat) == 0.0, "a triangle without area: 0");
    spm_texture_trilinear(&t, 0.3, 0.7, 2.0, o);
    CHECK_NEAR(o[0], 0.5, 1e-6, "a wide footprint: the mean");
    spm_texture_mean(&t, o);
    CHECK_NEAR(o[0], 0.5, 1e-6, "the checker's mean");
    spm_texture_free(&t);
}

/* An 8-bit PNG (code 128: sRGB-decoded) and a float EXR (2.5: as it is). */
static void files(void)
{
    spm_error err;
    unsigned char px[2 * 1 * 3] = {128, 128, 128, 255, 0, 51};
    float fx[2 * 1 * 3] = {2.5f, 0.25f, 0.0f, 1.0f, 2.0f, 3.0f};
    CHECK(spm_image_write("tex_test.png", 2, 1, px, SPM_PIXEL_UINT8, &err) == 0, "%s", err.msg);
    CHECK(spm_image_write("tex_test.exr", 2, 1, fx, SPM_PIXEL_FLOAT, &err) == 0, "%s", err.msg);
    spm_file top, f;
    CHECK(spm_paths_set_root("tex_test.png", &top, &err) == 0, "%s", err.msg);
    char why[256];
    float *rgb = NULL;
    int w, h;
    CHECK(spm_path_check(".", "tex_test.png", "test", &f, &err) == 0, "%s", err.msg);
    CHECK(spm_texture_read_file(&f, &rgb, &w, &h, why, sizeof why) == 0, "png: %s", why);
    if (rgb) {
        CHECK(w == 2 && h == 1, "png size %dx%d", w, h);
        CHECK_NEAR(rgb[0], spm_srgb_decode(128 / 255.0), 1e-6, "png code 128 decoded");
        CHECK_NEAR(rgb[5], spm_srgb_decode(51 / 255.0), 1e-6, "png code 51 decoded");
        free(rgb);
    }
    CHECK(spm_path_check(".", "tex_test.exr", "test", &f, &err) == 0, "%s", err.msg);
    CHECK(spm_texture_read_file(&f, &rgb, &w, &h, why, sizeof why) == 0, "exr: %s", why);
    if (rgb) {
        CHECK(rgb[0] == 2.5f && rgb[1] == 0.25f && rgb[5] == 3.0f, "exr as it is (%g %g %g)",
              rgb[0], rgb[1], rgb[5]);
        free(rgb);
    }
    /* the PNG's bytes from memory, as a model's embedded image */
    FILE *in = fopen("tex_test.png", "rb");
    static unsigned char bytes[4096];
    size_t n = in ? fread(bytes, 1, sizeof bytes, in) : 0;
    if (in)
        fclose(in);
    rgb = NULL;
    CHECK(spm_texture_read_data("embedded.png", bytes, n, &rgb, &w, &h, why, sizeof why) == 0,
          "embedded png: %s", why);
    if (rgb) {
        CHECK_NEAR(rgb[3], 1.0, 1e-6, "embedded png code 255");
        free(rgb);
    }
    /* bytes that are no image are refused (a PNG cut short is refused too,
     * but OpenImageIO 2.4's PNG reader leaks a string when libpng jumps out
     * of its read callback, which LeakSanitizer reports: not tested here) */
    static const char junk[] = "this is not an image, whatever its name says";
    CHECK(spm_texture_read_data("embedded.png", junk, sizeof junk, &rgb, &w, &h, why,
                                sizeof why),
          "bytes that are no image are refused");
    remove("tex_test.png");
    remove("tex_test.exr");
}

/* Lifting a level: each distinct value once, the same as each texel alone. */
static void lift(void)
{
    spm_error err;
    const spm_rgb2spec_table *t = spm_rgb2spec_srgb(&err);
    CHECK(t != NULL, "table: %s", err.msg);
    if (!t)
        return;
    enum { W = 16, H = 8 };
    static float px[W * H * 3], out[W * H * 4];
    const float pal[4][3] = {{0.8f, 0.1f, 0.1f}, {0.1f, 0.5f, 0.9f}, {2.0f, 1.0f, 0.5f},
                             {0.3f, 0.3f, 0.3f}};
    for (int i = 0; i < W * H; i++)
        memcpy(px + 3 * i, pal[i % 7 % 4], sizeof pal[0]);
    px[3 * 77] = 0.05f; /* one texel of its own */
    spm_texmap m = {W, H, px};
    for (int kind = SPM_TEXEL_REFLECTANCE; kind <= SPM_TEXEL_UNBOUNDED; kind++) {
        long d = spm_texture_lift(t, (spm_texel_kind)kind, &m, out);
        CHECK(d == 5, "five distinct values (%ld)", d);
        int same = 1;
        for (int i = 0; i < W * H; i++) {
            double rgb[3] = {px[3 * i], px[3 * i + 1], px[3 * i + 2]}, c[3], scale;
            spm_rgb2spec_texel(t, (spm_texel_kind)kind, rgb, c, &scale);
            for (int k = 0; k < 3; k++)
                same &= out[4 * i + k] == (float)c[k];
            same &= out[4 * i + 3] == (float)scale;
        }
        CHECK(same, "kind %d: the lifted level is each texel's lift", kind);
    }
}

/* KHR_texture_transform: offset (0.5, 0.25), a quarter turn, scale (2, 1).
 * glTF's uv' = T R S uv at glTF's (0.3, 0.4) (ours (0.3, 0.6)): u' = 0.4 +
 * 0.5 = 0.9, v' = -2 0.3 + 0.25 = -0.35, ours 1.35; the matrix by hand
 * (texture.h): c = 0, s = 1: (0, -1, 1.5; 2, 0, 0.75). */
static void transforms(void)
{
    double off[2] = {0.5, 0.25}, sc[2] = {2, 1}, one[2] = {1, 1}, zero[2] = {0, 0};
    spm_uvx x;
    spm_uvx_gltf(off, M_PI / 2, sc, &x);
    static const float want[6] = {0, -1, 1.5f, 2, 0, 0.75f};
    for (int i = 0; i < 6; i++)
        CHECK(fabsf(x.m[i] - want[i]) <= 1e-7f, "the quarter turn's matrix, entry %d: %g", i,
              x.m[i]);
    CHECK(x.on, "a transform is on");
    spm_uvx_gltf(zero, 0.0, one, &x);
    CHECK(!x.on, "the identity is off");
    /* a 2 x 2 one-byte map, rows top to bottom (0 255 / 51 102): at texel
     * (0, 0)'s centre (0.25, 0.75) through offset (0.5, 0), u' = 0.75: texel
     * (1, 0), 255; at (0.25, 0.375) through offset (0, 0.5) and scale (1, 2):
     * glTF's v = 0.625, v' = 1.75, ours -0.75, repeated 0.25: the bottom
     * row's centre, texel (0, 1), 51 */
    spm_u32 w[SPM_ALPHA_MAP_HEAD + 1 + 6] = {2, 2, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT};
    w[SPM_ALPHA_MAP_HEAD] = 0u | 255u << 8 | 51u << 16 | 102u << 24;
    double o1[2] = {0.5, 0}, o2[2] = {0, 0.5}, s2[2] = {1, 2};
    spm_uvx_gltf(o1, 0.0, one, &x);
    spm_geometry_uvx_put(&x, w, 0, SPM_ALPHA_UVX, SPM_ALPHA_MAP_HEAD + 1);
    CHECK(w[SPM_ALPHA_UVX] == SPM_ALPHA_MAP_HEAD + 1, "the transform's offset from the head");
    CHECK_NEAR(spm_byte_map_bilinear(w, 0.25f, 0.75f), 1.0, 1e-6, "offset: texel (1, 0)");
    CHECK_NEAR(spm_tex_uvx_scale(w, w[SPM_ALPHA_UVX]), 1.0, 1e-7, "an offset keeps the footprint");
    spm_uvx_gltf(o2, 0.0, s2, &x);
    spm_geometry_uvx_put(&x, w, 0, SPM_ALPHA_UVX, SPM_ALPHA_MAP_HEAD + 1);
    CHECK_NEAR(spm_byte_map_bilinear(w, 0.25f, 0.375f), 51.0 / 255, 1e-6, "scale: texel (0, 1)");
    CHECK_NEAR(spm_tex_uvx_scale(w, w[SPM_ALPHA_UVX]), sqrt(2.0), 1e-6,
               "scale (1, 2): the footprint sqrt 2 wider");
    w[SPM_ALPHA_UVX] = 0;
    CHECK_NEAR(spm_byte_map_bilinear(w, 0.25f, 0.75f), 0.0, 1e-6, "no transform: texel (0, 0)");
}

int main(void)
{
    transforms();
    lift();
    wraps();
    bilinear();
    pyramid();
    checker_and_lod();
    files();
    TEST_END();
}
