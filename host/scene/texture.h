/* Image textures on the host: linear RGB texels, a mip pyramid per image,
 * wrap modes and filtered lookups (texel, bilinear, trilinear by a footprint).
 *
 * Conventions. Rows are stored top to bottom. A texture coordinate (u, v) has
 * v = 0 at the image's bottom row and 1 at its top (OpenGL's and Assimp's,
 * which turns glTF's top-left origin into it), so texel space is
 *   x = u w,  y = (1 - v) h,
 * and texel (i, j) covers [i, i+1] x [j, j+1]: its centre is at (i + 1/2, j + 1/2).
 *
 * The pyramid: level 0 the image; level n+1 is (max(1, floor(w/2)), max(1,
 * floor(h/2))) and each of its texels the area mean of the level-n texels it
 * covers (the texel is s = w_n / w_{n+1} texels wide: 2 for an even width, a
 * little over 2 for an odd one, whose texels are counted by the fraction
 * covered), so every level has the image's mean and the last, 1 x 1, is it. */
#ifndef SPM_TEXTURE_H
#define SPM_TEXTURE_H
#include <stddef.h>
#include "paths.h"
#include "rgb2spec_table.h"
#include "spm_shared.h"
#ifdef __cplusplus
extern "C" {
#endif

#define SPM_TEXTURE_MAX_LEVELS 32

typedef enum { SPM_WRAP_REPEAT = 0, SPM_WRAP_CLAMP = 1, SPM_WRAP_MIRROR = 2 } spm_wrap;

typedef struct {
    int w, h;
    float *rgb; /* 3 floats a texel, rows top to bottom */
} spm_texmap;

/* A map's texture coordinate transform (glTF KHR_texture_transform), in
 * the convention above (v up):
 *   u' = m0 u + m1 v + m2,  v' = m3 u + m4 v + m5;
 * on = 0: the identity (a map without one is looked up as before). Each
 * binding of an image carries its own (spm_shared.h SPM_TEX_UVX). */
typedef struct {
    float m[6];
    int on;
} spm_uvx;

/* glTF's transform uv' = T(offset) R(rotation) S(scale) uv, written in
 * glTF's convention (v down: v_gltf = 1 - v), in ours:
 *   u' = c sx u - s sy v + (s sy + ox),
 *   v' = s sx u + c sy v + (1 - c sy - oy),  c = cos r, s = sin r;
 * on unless it is the identity. */
void spm_uvx_gltf(const double offset[2], double rotation, const double scale[2], spm_uvx *out);

typedef struct spm_texture_s {
    int nlevels;
    spm_texmap lv[SPM_TEXTURE_MAX_LEVELS];
    spm_wrap wrap[2]; /* along u, along v */
    spm_uvx uvx;      /* its texture coordinates' transform */
} spm_texture;

/* A texture of w x h linear RGB texels (copied) and its pyramid. */
void spm_texture_from_pixels(int w, int h, const float *rgb, spm_wrap wrap_u, spm_wrap wrap_v,
                             spm_texture *t);
/* A checkerboard of checks x checks squares, colour a at the top-left, b
 * beside it, each square res texels wide. */
void spm_texture_checker(int checks, int res, const float a[3], const float b[3], spm_wrap wrap,
                         spm_texture *t);
void spm_texture_free(spm_texture *t);

/* Index i on an axis of n texels under a wrap mode: repeat i mod n; clamp to
 * [0, n-1]; mirror with period 2n (n..2n-1 run back n-1..0). */
int spm_wrap_index(int i, int n, spm_wrap mode);

/* Texel (i, j) of `level`, wrapped. */
void spm_texture_texel(const spm_texture *t, int level, int i, int j, float out[3]);
/* Bilinear at (u, v) on `level`: the four texel centres around
 * (x - 1/2, y - 1/2) weighted by the fractions. */
void spm_texture_bilinear(const spm_texture *t, int level, double u, double v, float out[3]);
/* The level of detail for a footprint `width` in texture coordinates (a ray
 * cone's width at the hit over |cos| times sqrt(uv area / world area) of the
 * triangle; Akenine-Moller et al. 2021): lod = log2(width sqrt(w h)), clamped
 * to [0, nlevels - 1]. */
double spm_texture_lod(const spm_texture *t, double width);
/* A ray cone's footprint in texture coordinates at a hit on a triangle:
 * width = cone_width / |cos| * sqrt(uv area / world area), the triangle's
 * areas from its texture coordinates uv (u0 v0 u1 v1 u2 v2) and vertices p
 * (Akenine-Moller et al. 2021, eq. for the base level Delta). 0 for a
 * triangle without area or a ray along it (level 0 then). */
double spm_texture_cone_footprint(double cone_width, double cos_theta, const float uv[6],
                                  const float p[9]);
/* Trilinear: bilinear on the two levels around the footprint's lod, blended. */
void spm_texture_trilinear(const spm_texture *t, double u, double v, double width, float out[3]);
/* The image's mean (its 1 x 1 level). */
void spm_texture_mean(const spm_texture *t, float out[3]);

/* A level's texels lifted to the model: 4 floats a texel (c0, c1, c2, scale;
 * spm_rgb2spec_texel), into out (w h 4 floats). Each distinct RGB value is
 * lifted once (a texture's colours repeat: an 8-bit image has few distinct
 * values per channel triple); the result is the same as lifting each texel.
 * Returns the number of distinct values lifted. */
long spm_texture_lift(const spm_rgb2spec_table *t, spm_texel_kind kind, const spm_texmap *m,
                      float *out);

/* The colour grid's nodes (spm_shared.h SPM_TEX_GRID) and the cell of x in
 * [0, 1]: the largest k <= SPM_TEX_GRID - 2 with nodes[k] <= x
 * (texture_palette.c; the kernels' texture.clh has its own). */
void spm_tex_grid_nodes(float nodes[SPM_TEX_GRID]);
int spm_tex_grid_cell(const float nodes[SPM_TEX_GRID], float x);

/* Where an image is: a file checked by the path rule, or (file NULL) size
 * bytes at data, an image embedded in a model whose format `hint` names by
 * its extension ("png", "jpg"). Both are read alike. */
typedef struct {
    const spm_file *file;
    const void *data;
    size_t size;
    const char *hint;
} spm_image_src;
/* What spm_texture_read gives: linear colour (integer codes sRGB-decoded
 * unless the file says linear) or data (integer codes over their maximum:
 * a normal map). */
enum { SPM_IMAGE_COLOUR = 0, SPM_IMAGE_DATA = 1 };
/* Reading images through OpenImageIO (texture_io.cpp): the first three
 * channels (one or two: grey) as linear RGB, rows top to bottom; integer
 * codes (8- and 16-bit PNG, JPEG) decoded as `as` says, float and half (EXR,
 * HDR) as they are. 0 with *rgb (malloc'd), *w, *h; 1 with why filled. The
 * _file and _data forms are the same for a file and for bytes. */
int spm_texture_read(const spm_image_src *src, int as, float **rgb, int *w, int *h, char *why,
                     size_t whylen);
int spm_texture_read_file(const spm_file *file, float **rgb, int *w, int *h, char *why,
                          size_t whylen);
int spm_texture_read_data(const char *hint, const void *data, size_t size, float **rgb, int *w,
                          int *h, char *why, size_t whylen);
/* SPM_IMAGE_DATA from a file: an image of data, not colour (a normal map). */
int spm_texture_read_data_file(const spm_file *file, float **rgb, int *w, int *h, char *why,
                               size_t whylen);
/* One channel as stored (integer codes over their maximum, no sRGB
 * decoding: opacity, metallic and roughness are data), one float a pixel,
 * rows top to bottom. which >= 0: an opacity image's alpha channel, or its
 * first channel when it has none (which 1, alpha only: *a NULL then);
 * which = -1 - c: channel c, the first when the image has fewer. */
int spm_texture_read_one(const spm_image_src *src, int which, float **a, int *w, int *h,
                         char *why, size_t whylen);
int spm_texture_read_alpha_file(const spm_file *file, int alpha_only, float **a, int *w, int *h,
                                char *why, size_t whylen);
int spm_texture_read_channel_file(const spm_file *file, int channel, float **a, int *w, int *h,
                                  char *why, size_t whylen);
#ifdef __cplusplus
}
#endif
#endif
