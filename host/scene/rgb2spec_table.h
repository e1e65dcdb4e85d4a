/* RGB to spectrum for many colours (texels): a table of the fitted model's
 * coefficients over the sRGB cube, looked up trilinearly, after Jakob and
 * Hanika (2019) and pbrt-v4's RGBToSpectrumTable.
 *
 * The cube is split by its largest component m = rgb[l] (l = 0, 1, 2): a
 * node (l, k, j, i) is the colour with rgb[l] = z_k, rgb[l+1] = z_k (i/(R-1))^2,
 * rgb[l+2] = z_k (j/(R-1))^2 (indices mod 3), where z_k = smoothstep(smoothstep(
 * k/(R-1))): nodes packed near black, near the top and near the cube's faces
 * (a component near 0), where the coefficients change fastest. Each node holds the coefficients the fitter of
 * rgb2spec.c finds for its colour (the same objective, CIELAB under D65 on the
 * 1 nm bins), each fit started from its neighbour's along z.
 *
 * The table is built on first use and cached (spm_rgb2spec_srgb). */
#ifndef SPM_RGB2SPEC_TABLE_H
#define SPM_RGB2SPEC_TABLE_H
#include "spectrum.h"
#include <stdint.h>
#include "util.h"

#define SPM_RGB2SPEC_RES 64

typedef struct {
    int res;
    float *z;    /* res values of the largest component at the nodes */
    float *coef; /* [3][res (z)][res (j)][res (i)][3] */
    double (*w)[SPM_TRUTH_BINS]; /* the fit's weights (rgb2spec.h), for texels' polish */
} spm_rgb2spec_table;

/* The sRGB table: loaded from the cache, else fitted (seconds to a minute on
 * every core) and written there. The cache is $SPECMIP_CACHE_DIR, else
 * $XDG_CACHE_HOME/specmip, else $HOME/.cache/specmip; a file is written to a
 * temporary name and renamed, and one that does not match this build's
 * fitter inputs (the resolution, the format and a hash of the D65 and CMF
 * weights) is fitted again. Without a writable cache the table is fitted and
 * kept in memory. NULL with err when the bundled data cannot be read. */
const spm_rgb2spec_table *spm_rgb2spec_srgb(spm_error *err);

/* Fits a table of res nodes per axis with `threads` threads (0: every core). */
int spm_rgb2spec_table_build(int res, int threads, spm_rgb2spec_table *t, spm_error *err);
void spm_rgb2spec_table_free(spm_rgb2spec_table *t);
/* The colour of node (l, k, j, i). */
void spm_rgb2spec_node_rgb(const spm_rgb2spec_table *t, int l, int k, int j, int i,
                           double rgb[3]);

/* The cache file: the hash of the fitter's inputs for a table of res nodes;
 * read (1 unless the file is whole and matches res and inputs); write (to a
 * temporary file beside path, flushed, then renamed: 1 on failure, nothing
 * left behind). */
uint64_t spm_rgb2spec_inputs_hash(int res);
int spm_rgb2spec_cache_read(const char *path, int res, uint64_t inputs, spm_rgb2spec_table *t);
int spm_rgb2spec_cache_write(const char *path, uint64_t inputs, const spm_rgb2spec_table *t);

/* Coefficients for linear sRGB rgb, clamped to [0, 1]: a grey g is exact
 * (0, 0, (g - 1/2) / sqrt(g (1 - g))), with g within [1e-6, 1 - 1e-6]; other
 * colours are the trilinear interpolation of the eight nodes around them. */
void spm_rgb2spec_lookup(const spm_rgb2spec_table *t, const double rgb[3], double coef[3]);

/* The same by Catmull-Rom interpolation over 4 x 4 x 4 nodes (in the node
 * index along each axis, the ends extrapolated linearly): more accurate where
 * the coefficients curve, eight times the reads. */
void spm_rgb2spec_lookup_cubic(const spm_rgb2spec_table *t, const double rgb[3],
                               double coef[3]);

/* A texel as the model: value(lambda) = scale * S(coef, lambda), times D65
 * normalised to Y = 1 for an emission. The coefficients are the cubic lookup,
 * polished by the fitter where its colour is more than SPM_TEXEL_MAX_DE00
 * from the target (2 % of the test colours; docs/METHODS.md).
 *   reflectance: rgb clamped to [0, 1], scale 1 (0 for black);
 *   unbounded (an index, an HDR value): scale = max component m, coef for
 *     rgb / m (a grey's spectrum is then exactly m);
 *   emission: as unbounded; the caller multiplies by D65 / Y(D65), so that a
 *     texel's luminance follows its rgb (not normalised per texel). */
#define SPM_TEXEL_MAX_DE00 0.01
typedef enum { SPM_TEXEL_REFLECTANCE, SPM_TEXEL_UNBOUNDED, SPM_TEXEL_EMISSION } spm_texel_kind;
void spm_rgb2spec_texel(const spm_rgb2spec_table *t, spm_texel_kind kind, const double rgb[3],
                        double coef[3], double *scale);

/* The texel's spectrum on the 1 nm bins (an emission: times D65 / Y(D65)).
 * Returns 0, or 1 with err when the bundled data cannot be read. */
int spm_rgb2spec_texel_spectrum(spm_texel_kind kind, const double coef[3], double scale,
                                spm_spectrum *out, spm_error *err);

/* The model's bin means at `level` (SPM_LEVEL_BINS(level) values): level 0 the
 * values at the 1 nm bin centres (as spm_rgb2spec_eval), a coarser bin the
 * mean of the 1 nm values it covers, summed (the reference). */
void spm_sigmoid_level_sum(const double coef[3], int level, double *out);
/* The same by `n`-point Gauss-Legendre quadrature per bin (n 1..8) of the
 * continuous model: what a shade stage can afford (rgb2spec_table.c says
 * how close it comes). */
void spm_sigmoid_level_gauss(const double coef[3], int level, int n, double *out);
#endif
