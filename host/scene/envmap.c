/* Environment maps (envmap.h): the statement, the palette of lifted
 * spectra, the sampling distribution. */
#include "envmap.h"
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "colour.h"
#include "rgb2spec_table.h"
#include "spm_shared.h"
#include "texture.h"

void spm_envmap_free(spm_scene_envmap *e)
{
    if (!e)
        return;
    free(e->rgb);
    free(e->colour);
    free(e->node);
    free(e->frac);
    free(e->node_colour);
    free(e->node_y);
    free(e->lum);
    free(e->sky);
    free(e);
}

void spm_envmap_from_pixels(spm_scene *s, int w, int h, const float *rgb, double scale,
                            double rotate, const char *where)
{
    spm_scene_envmap *e = spm_xcalloc(1, sizeof *e);
    e->w = w;
    e->h = h;
    e->rgb = spm_xmalloc((size_t)w * h * 3 * sizeof *e->rgb);
    memcpy(e->rgb, rgb, (size_t)w * h * 3 * sizeof *e->rgb);
    e->scale = scale;
    e->rotate = rotate;
    e->first = -1;
    snprintf(e->where, sizeof e->where, "%s", where);
    spm_envmap_free(s->env);
    s->env = e;
}

int spm_envmap_load(spm_scene *s, const spm_file *f, double scale, double rotate,
                    const char *where, spm_error *err)
{
    struct stat st;
    if (stat(f->path, &st) != 0 || !S_ISREG(st.st_mode)) {
        spm_errorf(err, "%s: environment map '%s' not found (or not a regular file)", where,
                   f->shown);
        return 1;
    }
    float *rgb;
    int w, h;
    char why[256];
    if (spm_texture_read_file(f, &rgb, &w, &h, why, sizeof why)) {
        spm_errorf(err, "%s: environment map '%s' cannot be read: %s", where, f->shown, why);
        return 1;
    }
    size_t neg = 0;
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        if (rgb[i] < 0.0f) { /* outside sRGB's gamut: no light is negative */
            rgb[i] = 0.0f;
            neg++;
        }
    if (neg)
        spm_warnf("%s: environment map '%s': %zu negative components (colours outside linear "
                  "sRGB) taken as 0", where, f->shown, neg);
    spm_envmap_from_pixels(s, w, h, rgb, scale, rotate, where);
    free(rgb);
    return 0;
}

/* map FILE [scale S] [rotate DEG], each option once */
int spm_envmap_statement(spm_scene *s, spm_lexer *lx, const char *dir, spm_error *err)
{
    char where[600], name[1024];
    spm_lex_where(lx, where, sizeof where);
    if (spm_lex_next(lx, err) ||
        spm_lex_path(lx, "an environment map's file name", name, sizeof name, err))
        return 1;
    double scale = 1.0, rotate = 0.0;
    int have_scale = 0, have_rotate = 0;
    while (lx->type != SPM_TOK_NEWLINE && lx->type != SPM_TOK_EOF) {
        if (!have_scale && spm_lex_is(lx, "scale")) {
            have_scale = 1;
            if (spm_lex_next(lx, err) ||
                spm_lex_number(lx, "a scale (0 or more)", 0.0, 1e30, &scale, err))
                return 1;
        } else if (!have_rotate && spm_lex_is(lx, "rotate")) {
            have_rotate = 1;
            if (spm_lex_next(lx, err) ||
                spm_lex_number(lx, "an angle in degrees", -1e6, 1e6, &rotate, err))
                return 1;
        } else {
            return spm_lex_expected(lx, err, "'scale' or 'rotate' (each once) or the end of the line");
        }
    }
    spm_file f;
    return spm_path_check(dir, name, where, &f, err) ||
           spm_envmap_load(s, &f, scale, rotate, where, err) ||
           spm_lex_end_of_statement(lx, err);
}

/* A shape's place on the node grid: the face l of its largest component,
 * the next two components (in the order l+1, l+2) times q, x = a + fa and
 * y = b + fb with the cell (a, b) < q; returns its base node (l, a, b), f
 * its fractions in 16-bit fixed point; -1 for black. */
static int place_of(const float rgb[3], int q, unsigned f[2])
{
    float m = fmaxf(rgb[0], fmaxf(rgb[1], rgb[2]));
    if (!(m > 0.0f))
        return -1;
    int l = rgb[0] >= rgb[1] && rgb[0] >= rgb[2] ? 0 : rgb[1] >= rgb[2] ? 1 : 2, c[2];
    for (int k = 0; k < 2; k++) {
        double x = (double)rgb[(l + 1 + k) % 3] / m * q;
        c[k] = (int)x < q ? (int)x : q - 1;
        f[k] = (unsigned)lround((x - c[k]) * 65535.0);
    }
    return (l * (q + 1) + c[0]) * (q + 1) + c[1];
}

/* node n's RGB shape on a grid of q steps: 1 at its face, a / q, b / q */
static void node_shape(int n, int q, double rgb[3])
{
    int s = q + 1, l = n / (s * s), a = n / s % s, b = n % s;
    rgb[l] = 1.0;
    rgb[(l + 1) % 3] = (double)a / q;
    rgb[(l + 2) % 3] = (double)b / q;
}

/* the four corners of base node n (stride s along a) and their weights,
 * bilinear in the fractions f (16-bit) times each node's luminance y:
 * w_k = w_bilinear,k Y_k (kernels/light_envmap.clh env_node) */
static void corners(int n, int s, const unsigned f[2], const float *y, int k[4], double w[4])
{
    double fa = f[0] / 65535.0, fb = f[1] / 65535.0;
    k[0] = n, k[1] = n + 1, k[2] = n + s, k[3] = n + s + 1;
    w[0] = (1.0 - fa) * (1.0 - fb), w[1] = (1.0 - fa) * fb, w[2] = fa * (1.0 - fb), w[3] = fa * fb;
    for (int i = 0; i < 4; i++)
        w[i] *= y ? y[k[i]] : 1.0;
}

static double luminance(const float rgb[3])
{
    double c[3] = {rgb[0], rgb[1], rgb[2]}, xyz[3];
    spm_linear_srgb_to_xyz(c, xyz);
    return xyz[1];
}

/* CIE 1976 u', v' of an XYZ */
static void uv_prime(const double xyz[3], double uv[2])
{
    double den = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
    uv[0] = den > 0.0 ? 4.0 * xyz[0] / den : 0.0;
    uv[1] = den > 0.0 ? 9.0 * xyz[1] / den : 0.0;
}

/* Node n's colour: its shape lifted, normalised to Y = 1, appended to the
 * scene's colours; xyz its XYZ (Y = 1). */
static int add_colour(spm_scene *s, const spm_rgb2spec_table *tab, int n, int q, double xyz[3],
                      spm_error *err)
{
    double shape[3], coef[3], scale;
    node_shape(n, q, shape);
    spm_rgb2spec_texel(tab, SPM_TEXEL_EMISSION, shape, coef, &scale);
    spm_colour col;
    memset(&col, 0, sizeof col);
    snprintf(col.name, sizeof col.name, "map %d", n);
    if (spm_rgb2spec_texel_spectrum(SPM_TEXEL_EMISSION, coef, scale, &col.s, err))
        return 1;
    spm_xyz_emission(&col.s, xyz);
    if (!(xyz[1] > 0.0)) {
        spm_errorf(err, "%s: environment map colour %g %g %g has no luminance", s->env->where,
                   shape[0], shape[1], shape[2]);
        return 1;
    }
    spm_spectrum_scale(&col.s, 1.0 / xyz[1]);
    double y = xyz[1];
    for (int k = 0; k < 3; k++)
        xyz[k] /= y;
    s->colours = spm_xrealloc(s->colours, ((size_t)s->ncolours + 1) * sizeof *s->colours);
    s->colours[s->ncolours++] = col;
    return 0;
}

/* The palette's chromaticity error: the distance in u'v' of each texel's own
 * colour (its linear sRGB) from the expectation of its drawn nodes' lifted
 * spectra (their XYZ of Y = 1 mixed by the pick's weights), the largest and
 * the luminance-weighted mean: the lift's error alone. */
static void chroma_error(spm_scene_envmap *e, const double (*xyz)[3])
{
    size_t n = (size_t)e->w * e->h;
    double wsum = 0.0, dsum = 0.0;
    e->duv_max = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (e->node[i] < 0)
            continue;
        const float *rgb = &e->rgb[3 * i];
        unsigned f[2] = {e->frac[i] & 0xFFFFu, e->frac[i] >> 16};
        int k[4];
        double w[4], m[3] = {0.0, 0.0, 0.0}, in[3] = {rgb[0], rgb[1], rgb[2]}, t[3], a[2], b[2];
        corners(e->node[i], e->stride, f, e->node_y, k, w);
        for (int c = 0; c < 4; c++)
            for (int x = 0; x < 3 && w[c] > 0.0; x++)
                m[x] += w[c] * xyz[k[c]][x];
        spm_linear_srgb_to_xyz(in, t);
        uv_prime(t, a);
        uv_prime(m, b);
        double d = hypot(a[0] - b[0], a[1] - b[1]);
        e->duv_max = d > e->duv_max ? d : e->duv_max;
        dsum += d * t[1];
        wsum += t[1];
    }
    e->duv_mean = wsum > 0.0 ? dsum / wsum : 0.0;
}

int spm_envmap_palette(spm_scene *s, spm_error *err)
{
    return spm_envmap_palette_grid(s, SPM_ENVMAP_GRID, err);
}

/* each texel's base node, fractions and luminance; marks the nodes a texel
 * may draw (a weight above 0) in used */
static void place_texels(spm_scene_envmap *e, int q, char *used)
{
    size_t n = (size_t)e->w * e->h;
    for (size_t i = 0; i < n; i++) {
        const float *rgb = &e->rgb[3 * i];
        unsigned f[2] = {0, 0};
        int b = place_of(rgb, q, f), k[4];
        double y = b >= 0 ? luminance(rgb) : 0.0, w[4];
        e->node[i] = y > 0.0 ? b : -1;
        e->frac[i] = f[0] | f[1] << 16;
        e->lum[i] = e->node[i] >= 0 ? (float)(y * e->scale) : 0.0f;
        if (e->node[i] < 0)
            continue;
        corners(b, q + 1, f, NULL, k, w);
        for (int c = 0; c < 4; c++)
            used[k[c]] |= w[c] > 0.0;
    }
}

int spm_envmap_palette_grid(spm_scene *s, int q, spm_error *err)
{
    spm_scene_envmap *e = s->env;
    if (!e || !e->rgb)
        return 0;
    const spm_rgb2spec_table *tab = spm_rgb2spec_srgb(err);
    if (!tab)
        return 1;
    size_t n = (size_t)e->w * e->h;
    int rc = 0;
    e->stride = q + 1;
    e->nnodes = 3 * e->stride * e->stride;
    e->node = spm_xmalloc(n * sizeof *e->node);
    e->frac = spm_xmalloc(n * sizeof *e->frac);
    e->lum = spm_xmalloc(n * sizeof *e->lum);
    e->node_colour = spm_xmalloc((size_t)e->nnodes * sizeof *e->node_colour);
    e->node_y = spm_xcalloc((size_t)e->nnodes, sizeof *e->node_y);
    char *used = spm_xcalloc((size_t)e->nnodes, 1);
    double (*xyz)[3] = spm_xcalloc((size_t)e->nnodes, sizeof *xyz);
    place_texels(e, q, used);
    e->first = s->ncolours;
    for (int k = 0; k < e->nnodes && !rc; k++) {
        double shape[3];
        float f[3];
        node_shape(k, q, shape);
        for (int c = 0; c < 3; c++)
            f[c] = (float)shape[c];
        e->node_y[k] = (float)luminance(f);
        e->node_colour[k] = used[k] ? s->ncolours : -1;
        if (used[k])
            rc = add_colour(s, tab, k, q, xyz[k], err);
    }
    e->ncolours = s->ncolours - e->first;
    if (!rc) {
        chroma_error(e, (const double (*)[3])xyz);
        free(e->rgb);
        e->rgb = NULL;
    }
    free(used);
    free(xyz);
    return rc;
}

/* The mean over texel (i, j) of the luminance the lookup interpolates
 * bilinearly between texel centres (columns wrapping, rows clamped, as
 * kernels/light_envmap.clh env_tap): along each axis the mean of the two
 * half-texels' ramps, (Y[k-1] + 6 Y[k] + Y[k+1]) / 8; so it is positive
 * wherever the interpolation is, and the distribution misses none of it. */
static double texel_mean(const spm_scene_envmap *e, int i, int j)
{
    static const double k[3] = {1.0 / 8.0, 6.0 / 8.0, 1.0 / 8.0};
    int w = e->w, h = e->h;
    double m = 0.0;
    for (int b = -1; b <= 1; b++) {
        int r = j + b < 0 ? 0 : j + b >= h ? h - 1 : j + b;
        for (int a = -1; a <= 1; a++)
            m += k[a + 1] * k[b + 1] * (double)e->lum[(size_t)r * w + (size_t)((i + a + w) % w)];
    }
    return m;
}

/* The node part of the buffer at t (spm_shared.h SPM_ENV_NODE ..): an
 * image's grid as made; a sky's palette (its own, of daylight spectra) as a
 * grid of stride 1 whose texels sit on their colour's node (fractions 0).
 * Past the last node, stride + 1 unused ones of luminance 0, so that a
 * corner's read stays in the buffer and is never drawn. */
static void node_tables(const spm_scene_envmap *e, float *t, size_t w, size_t h)
{
    size_t ntex = w * h;
    int sky = e->node == NULL, stride = sky ? 1 : e->stride;
    int nn = sky ? e->ncolours : e->nnodes;
    float *nd = t + SPM_ENV_NODES(w, h);
    spm_u32 us = (spm_u32)stride;
    memcpy(&nd[0], &us, sizeof us);
    for (int k = 0; k < nn + stride + 1; k++) {
        int c = k >= nn ? -1 : sky ? e->first + k : e->node_colour[k];
        spm_u32 id = c >= 0 ? (spm_u32)c : SPM_NONE;
        memcpy(&nd[1 + 2 * k], &id, sizeof id);
        nd[2 + 2 * k] = k >= nn ? 0.0f : sky ? 1.0f : e->node_y[k];
    }
    for (size_t i = 0; i < ntex; i++) {
        int b = sky ? (e->colour[i] >= 0 ? e->colour[i] - e->first : -1) : e->node[i];
        spm_u32 id = b >= 0 ? (spm_u32)b : SPM_NONE, f = sky ? 0u : e->frac[i];
        memcpy(&t[SPM_ENV_NODE(w, h) + i], &id, sizeof id);
        memcpy(&t[SPM_ENV_FRAC(w, h) + i], &f, sizeof f);
    }
}

float *spm_envmap_tables(const spm_scene_envmap *e, size_t *n, double *mean)
{
    spm_u32 w = (spm_u32)e->w, h = (spm_u32)e->h;
    size_t nn = (size_t)(e->node ? e->nnodes : e->ncolours) + (e->node ? e->stride : 1) + 1u;
    *n = SPM_ENV_FLOATS((size_t)w, (size_t)h, nn);
    float *t = spm_xcalloc(*n, sizeof *t);
    float *cond = t + SPM_ENV_COND((size_t)w, h), *pdf = t + SPM_ENV_PDF((size_t)w, h);
    double *f = spm_xmalloc((size_t)w * h * sizeof *f), *rowint = spm_xmalloc((size_t)h * sizeof *rowint);
    double total = 0.0;
    for (spm_u32 j = 0; j < h; j++) { /* f = the texel's mean Y x sin(theta) at the row's centre */
        double st = sin(M_PI * (j + 0.5) / h), acc = 0.0;
        float *c = cond + (size_t)j * (w + 1u);
        for (spm_u32 i = 0; i < w; i++) {
            f[(size_t)j * w + i] = texel_mean(e, (int)i, (int)j) * st;
            c[i] = (float)acc;
            acc += f[(size_t)j * w + i];
        }
        for (spm_u32 i = 0; i < w; i++) /* a black row: uniform (never chosen) */
            c[i] = acc > 0.0 ? (float)(c[i] / acc) : (float)((double)i / w);
        c[w] = 1.0f;
        rowint[j] = acc / w;
        total += rowint[j] / h;
    }
    double acc = 0.0;
    for (spm_u32 j = 0; j < h; j++) { /* the marginal over rows */
        t[j] = total > 0.0 ? (float)(acc / total) : (float)((double)j / h);
        acc += rowint[j] / h;
    }
    t[h] = 1.0f;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        pdf[i] = total > 0.0 ? (float)(f[i] / total) : 0.0f;
        t[SPM_ENV_LUM((size_t)w, h) + i] = e->lum[i];
    }
    node_tables(e, t, w, h);
    free(f);
    free(rowint);
    *mean = total;
    return t;
}
