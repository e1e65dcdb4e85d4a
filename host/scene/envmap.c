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

/* The palette cell of a shape: the face of its largest component l, the
 * next two components (in the order l+1, l+2) in q steps;
 * -1 for black. */
static int cell_of(const float rgb[3], int q)
{
    float m = fmaxf(rgb[0], fmaxf(rgb[1], rgb[2]));
    if (!(m > 0.0f))
        return -1;
    int l = rgb[0] >= rgb[1] && rgb[0] >= rgb[2] ? 0 : rgb[1] >= rgb[2] ? 1 : 2;
    int a = (int)(rgb[(l + 1) % 3] / m * (float)q), b = (int)(rgb[(l + 2) % 3] / m * (float)q);
    a = a < q ? a : q - 1;
    b = b < q ? b : q - 1;
    return (l * q + a) * q + b;
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

/* Cell c's colour: its texels' luminance-weighted mean shape sum[0..2] / sum[3],
 * lifted, normalised to Y = 1, appended to the scene's colours; uv its u'v'. */
static int add_colour(spm_scene *s, const spm_rgb2spec_table *tab, int c, const double sum[4],
                      double uv[2], spm_error *err)
{
    double shape[3] = {sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]}, coef[3], scale, xyz[3];
    spm_rgb2spec_texel(tab, SPM_TEXEL_EMISSION, shape, coef, &scale);
    spm_colour col;
    memset(&col, 0, sizeof col);
    snprintf(col.name, sizeof col.name, "map %d", c);
    if (spm_rgb2spec_texel_spectrum(SPM_TEXEL_EMISSION, coef, scale, &col.s, err))
        return 1;
    spm_xyz_emission(&col.s, xyz);
    if (!(xyz[1] > 0.0)) {
        spm_errorf(err, "%s: environment map colour %g %g %g has no luminance", s->env->where,
                   shape[0], shape[1], shape[2]);
        return 1;
    }
    spm_spectrum_scale(&col.s, 1.0 / xyz[1]);
    uv_prime(xyz, uv);
    s->colours = spm_xrealloc(s->colours, ((size_t)s->ncolours + 1) * sizeof *s->colours);
    s->colours[s->ncolours++] = col;
    return 0;
}

/* Each texel's colour and luminance; the palette's chromaticity error: the
 * distance in u'v' of each texel's own colour (its linear sRGB) from its
 * cell's lifted spectrum, the largest and the luminance-weighted mean. */
static void assign(spm_scene_envmap *e, int q, const int *cells, const double (*uv)[2])
{
    size_t n = (size_t)e->w * e->h;
    double wsum = 0.0, dsum = 0.0;
    e->duv_max = 0.0;
    for (size_t i = 0; i < n; i++) {
        const float *rgb = &e->rgb[3 * i];
        int c = cell_of(rgb, q);
        double y = c >= 0 ? luminance(rgb) : 0.0;
        e->colour[i] = c >= 0 && y > 0.0 ? cells[c] : -1;
        e->lum[i] = e->colour[i] >= 0 ? (float)(y * e->scale) : 0.0f;
        if (e->colour[i] < 0)
            continue;
        double in[3] = {rgb[0], rgb[1], rgb[2]}, xyz[3], t[2];
        spm_linear_srgb_to_xyz(in, xyz);
        uv_prime(xyz, t);
        const double *p = uv[e->colour[i] - e->first];
        double d = hypot(t[0] - p[0], t[1] - p[1]);
        e->duv_max = d > e->duv_max ? d : e->duv_max;
        dsum += d * y;
        wsum += y;
    }
    e->duv_mean = wsum > 0.0 ? dsum / wsum : 0.0;
}

int spm_envmap_palette(spm_scene *s, spm_error *err)
{
    return spm_envmap_palette_grid(s, SPM_ENVMAP_GRID, err);
}

int spm_envmap_palette_grid(spm_scene *s, int q, spm_error *err)
{
    spm_scene_envmap *e = s->env;
    if (!e || !e->rgb)
        return 0;
    const spm_rgb2spec_table *tab = spm_rgb2spec_srgb(err);
    if (!tab)
        return 1;
    int ncells = 3 * q * q, rc = 0;
    size_t n = (size_t)e->w * e->h;
    double (*sum)[4] = spm_xcalloc((size_t)ncells, sizeof *sum), (*uv)[2];
    int *cells = spm_xmalloc((size_t)ncells * sizeof *cells);
    for (size_t i = 0; i < n; i++) {
        const float *rgb = &e->rgb[3 * i];
        int c = cell_of(rgb, q);
        double y = c >= 0 ? luminance(rgb) : 0.0;
        if (!(y > 0.0))
            continue;
        float m = fmaxf(rgb[0], fmaxf(rgb[1], rgb[2]));
        for (int k = 0; k < 3; k++)
            sum[c][k] += y * rgb[k] / m;
        sum[c][3] += y;
    }
    uv = spm_xcalloc((size_t)ncells, sizeof *uv);
    e->first = s->ncolours;
    for (int c = 0; c < ncells && !rc; c++) {
        cells[c] = -1;
        if (sum[c][3] > 0.0) {
            cells[c] = s->ncolours;
            rc = add_colour(s, tab, c, sum[c], uv[s->ncolours - e->first], err);
        }
    }
    e->ncolours = s->ncolours - e->first;
    if (!rc) {
        e->colour = spm_xmalloc(n * sizeof *e->colour);
        e->lum = spm_xmalloc(n * sizeof *e->lum);
        assign(e, q, cells, (const double (*)[2])uv);
        free(e->rgb);
        e->rgb = NULL;
    }
    free(sum);
    free(uv);
    free(cells);
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

float *spm_envmap_tables(const spm_scene_envmap *e, size_t *n, double *mean)
{
    spm_u32 w = (spm_u32)e->w, h = (spm_u32)e->h;
    *n = SPM_ENV_FLOATS((size_t)w, (size_t)h);
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
        spm_u32 id = e->colour[i] >= 0 ? (spm_u32)e->colour[i] : SPM_NONE;
        memcpy(&t[SPM_ENV_ID((size_t)w, h) + i], &id, sizeof id);
    }
    free(f);
    free(rowint);
    *mean = total;
    return t;
}
