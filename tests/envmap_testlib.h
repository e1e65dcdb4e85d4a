/* Environment maps the tests make themselves (no binary files in the
 * repository): a Radiance HDR (RGBE, uncompressed scanlines) written from a
 * function of the texel, and the maps the tests share. */
#ifndef SPM_ENVMAP_TESTLIB_H
#define SPM_ENVMAP_TESTLIB_H
#include <math.h>
#include <stdio.h>
#include "geometry.h"
#include "scene.h"

typedef void (*envmap_texel_fn)(int i, int j, int w, int h, float rgb[3]);

/* one RGBE texel: the shared exponent of the largest component */
static inline void envmap_rgbe(const float c[3], unsigned char out[4])
{
    float m = fmaxf(c[0], fmaxf(c[1], c[2]));
    if (!(m > 1e-32f)) {
        out[0] = out[1] = out[2] = out[3] = 0;
        return;
    }
    int e;
    frexpf(m, &e);
    float f = ldexpf(1.0f, -e) * 256.0f;
    for (int k = 0; k < 3; k++)
        out[k] = (unsigned char)(c[k] * f);
    out[3] = (unsigned char)(e + 128);
}

/* RGBE stores 8 bits of mantissa: the value a texel is read back as */
static inline void envmap_quantise(float c[3])
{
    unsigned char b[4];
    envmap_rgbe(c, b);
    for (int k = 0; k < 3; k++)
        c[k] = b[3] ? ldexpf((float)b[k], (int)b[3] - 136) : 0.0f;
}

static inline int envmap_write_hdr(const char *path, int w, int h, envmap_texel_fn fn)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return 1;
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", h, w);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            float c[3];
            unsigned char b[4];
            fn(i, j, w, h, c);
            envmap_rgbe(c, b);
            fwrite(b, 1, 4, f);
        }
    return fclose(f) != 0;
}

/* a constant white map (linear sRGB 1 1 1) */
static inline void envmap_white(int i, int j, int w, int h, float rgb[3])
{
    (void)i, (void)j, (void)w, (void)h;
    rgb[0] = rgb[1] = rgb[2] = 1.0f;
}

/* a blue sky (redder toward u = 1) over a brown ground, a small bright sun (a 2 x 2 texel patch
 * at u 0.3, v 0.25 of a 64 x 32 map, 500 times the sky) and a black band
 * (v in [0.55, 0.65]) */
static inline void envmap_sun(int i, int j, int w, int h, float rgb[3])
{
    float u = (i + 0.5f) / w, v = (j + 0.5f) / h;
    if (fabsf(u - 0.3f) < 1.0f / w && fabsf(v - 0.25f) < 1.0f / h) {
        rgb[0] = 600.0f, rgb[1] = 540.0f, rgb[2] = 450.0f;
    } else if (v >= 0.55f && v < 0.65f) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
    } else if (v < 0.5f) {
        rgb[0] = 0.3f + 0.4f * v + 0.3f * u, rgb[1] = 0.45f + 0.3f * v, rgb[2] = 0.9f - 0.2f * v;
    } else {
        rgb[0] = 0.35f, rgb[1] = 0.25f, rgb[2] = 0.15f;
    }
}
/* a sky graded along u and v and a soft sun (a Gaussian 10 degrees wide at
 * u 0.3, v 0.3, 30 times the sky): every strategy reaches it with little noise */
static inline void envmap_soft_sun(int i, int j, int w, int h, float rgb[3])
{
    float u = (i + 0.5f) / w, v = (j + 0.5f) / h;
    float th = (float)M_PI * v, ph = 2.0f * (float)M_PI * u;
    float st = (float)(M_PI * 0.3), sp = 2.0f * (float)M_PI * 0.3f;
    float c = sinf(th) * sinf(ph) * sinf(st) * sinf(sp) + cosf(th) * cosf(st) +
              sinf(th) * cosf(ph) * sinf(st) * cosf(sp);
    float a = acosf(fmaxf(-1.0f, fminf(1.0f, c))) / (10.0f * (float)M_PI / 180.0f);
    float sun = 30.0f * expf(-a * a);
    rgb[0] = 0.3f + 0.3f * v + 0.2f * u + sun;
    rgb[1] = 0.4f + 0.2f * v + 0.85f * sun;
    rgb[2] = 0.8f - 0.4f * v + 0.6f * sun;
}
/* the soft sun's sky with every other column black: the bilinear lookup
 * reaches into each black column from both sides (a quarter of the map's
 * light), where a distribution of the texels' own luminance never draws */
static inline void envmap_striped(int i, int j, int w, int h, float rgb[3])
{
    envmap_soft_sun(i, j, w, h, rgb);
    if (i % 2 == 0)
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
}
/* A scene of one small far triangle (a scene needs one) under the background
 * statement `background` (a map or a sky), written to FILE, loaded into *s and
 * its geometry built into *g: 0 on success (then the caller frees both). */
static inline int envmap_test_scene(const char *file, const char *background, spm_scene *s,
                                    spm_geometry *g)
{
    FILE *f = fopen(file, "w");
    if (!f)
        return 1;
    fprintf(f, "image 8 8\ncamera position 0 0 0 direction 0 0 1 fov 40\n"
               "spectrum grey equal\nmaterial m reflect grey 0.5\n"
               "tri m 100 -100 100  101 -100 100  100 -100 101\n%s\n", background);
    fclose(f);
    spm_error err;
    if (spm_scene_load(file, s, &err)) {
        printf("load: %s\n", err.msg);
        return 1;
    }
    if (spm_geometry_build(s, g, &err)) {
        printf("geometry: %s\n", err.msg);
        spm_scene_free(s);
        return 1;
    }
    return 0;
}

#endif
