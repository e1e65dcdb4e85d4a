/* The daylight sky and its sun (sky.h): the statement, Preetham et al.'s
 * model, the palette of daylight spectra, the sun's spectrum and light. */
#include "sky.h"
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "csv.h"
#include "envmap.h"
#include "spm_shared.h"

#define BASIS_FILE "spectra/cie_daylight_basis.csv"
#define SOLAR_FILE "spectra/solar_astm_g173.csv"

void spm_sky_sun_dir(double elevation, double azimuth, double w[3])
{
    double e = elevation * M_PI / 180.0, a = azimuth * M_PI / 180.0;
    w[0] = cos(e) * sin(a);
    w[1] = sin(e);
    w[2] = -cos(e) * cos(a);
}

/* Perez et al.'s distribution of direction theta (from the zenith) at angle
 * gamma from the sun:
 *   F = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma),
 * the first factor 1 at the horizon (B < 0 for every turbidity allowed). */
static double perez(const double c[5], double cos_t, double gamma)
{
    double cg = cos(gamma);
    double a = cos_t > 0.0 ? 1.0 + c[0] * exp(c[1] / cos_t) : 1.0;
    return a * (1.0 + c[2] * exp(c[3] * gamma) + c[4] * cg * cg);
}

/* Preetham et al.'s appendix: A..E of Y, x, y, each u T + v */
static const double perez_uv[3][5][2] = {
    {{0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251}, {0.1206, -2.5771}, {-0.0670, 0.3703}},
    {{-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125}, {-0.0641, -0.8989}, {-0.0033, 0.0452}},
    {{-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102}, {-0.0441, -1.6537}, {-0.0109, 0.0529}}};

/* the zenith's chromaticity: (T^2, T, 1) M (ts^3, ts^2, ts, 1) */
static const double zenith_xy[2][3][4] = {
    {{0.00166, -0.00375, 0.00209, 0.0}, {-0.02903, 0.06377, -0.03202, 0.00394},
     {0.11693, -0.21196, 0.06052, 0.25886}},
    {{0.00275, -0.00610, 0.00317, 0.0}, {-0.04214, 0.08970, -0.04153, 0.00516},
     {0.15346, -0.26756, 0.06670, 0.26688}}};

/* Y, x, y at the zenith for the sun at zenith angle ts (radians):
 *   Y_z = (4.0453 T - 4.9710) tan chi - 0.2155 T + 2.4192 (kcd/m^2),
 *   chi = (4/9 - T/120) (pi - 2 ts) */
static void zenith(double T, double ts, double z[3])
{
    double chi = (4.0 / 9.0 - T / 120.0) * (M_PI - 2.0 * ts);
    z[0] = (4.0453 * T - 4.9710) * tan(chi) - 0.2155 * T + 2.4192;
    double tv[3] = {T * T, T, 1.0}, sv[4] = {ts * ts * ts, ts * ts, ts, 1.0};
    for (int c = 0; c < 2; c++) {
        z[1 + c] = 0.0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++)
                z[1 + c] += tv[i] * zenith_xy[c][i][j] * sv[j];
    }
}

/* each quantity: its zenith value times F(theta, gamma) / F(0, ts) */
void spm_sky_eval(const spm_sky *k, const double d[3], double *Y, double *x, double *y)
{
    double w[3], z[3], out[3];
    spm_sky_sun_dir(k->elevation, k->azimuth, w);
    double ts = (90.0 - k->elevation) * M_PI / 180.0, T = k->turbidity;
    double cg = fmin(1.0, fmax(-1.0, d[0] * w[0] + d[1] * w[1] + d[2] * w[2]));
    double gamma = acos(cg);
    zenith(T, ts, z);
    for (int q = 0; q < 3; q++) {
        double c[5];
        for (int i = 0; i < 5; i++)
            c[i] = perez_uv[q][i][0] * T + perez_uv[q][i][1];
        out[q] = z[q] * perez(c, d[1], gamma) / perez(c, 1.0, ts);
    }
    *Y = d[1] >= 0.0 && out[0] > 0.0 ? out[0] : 0.0;
    *x = out[1];
    *y = out[2];
}

/* linear interpolation of column col of a table at lambda (inside it) */
static double table_at(const spm_csv *t, int col, double lambda)
{
    size_t i = 0;
    while (i + 2 < t->nrows && t->data[(i + 1) * t->ncols] <= lambda)
        i++;
    const double *a = &t->data[i * t->ncols], *b = &t->data[(i + 1) * t->ncols];
    double f = (lambda - a[0]) / (b[0] - a[0]);
    return a[col] + f * (b[col] - a[col]);
}

/* a bundled table with the columns it must have, covering 380-780 nm */
static int load_table(const char *rel, int ncols, spm_csv *t, spm_error *err)
{
    char path[4096];
    spm_data_path(rel, path, sizeof path);
    if (spm_csv_load(path, t, err))
        return 1;
    if (t->ncols < ncols || t->nrows < 2 || t->data[0] > 380.0 ||
        t->data[(t->nrows - 1) * t->ncols] < 780.0) {
        spm_errorf(err, "%s: expected %d columns covering 380-780 nm", path, ncols);
        spm_csv_free(t);
        return 1;
    }
    return 0;
}

/* Preetham et al.'s appendix (after Iqbal 1983), the sun's zenith angle ts:
 *   relative air mass m = 1 / (cos ts + 0.15 (93.885 - ts_deg)^-1.253),
 *   Rayleigh  tau_R = exp(-0.008735 m lambda_um^-4.08),
 *   aerosol   tau_a = exp(-beta m lambda_um^-1.3), beta = 0.04608 T - 0.04586,
 *   L = E0 tau_R tau_a / Omega, Omega = 2 pi (1 - cos alpha) the disc's
 * solid angle, E0 the extraterrestrial irradiance. */
int spm_sky_sun_radiance(const spm_sky *k, double L[401], spm_error *err)
{
    spm_csv t;
    if (load_table(SOLAR_FILE, 2, &t, err))
        return 1;
    double ts_deg = 90.0 - k->elevation, ts = ts_deg * M_PI / 180.0;
    double m = 1.0 / (cos(ts) + 0.15 * pow(93.885 - ts_deg, -1.253));
    double beta = 0.04608365822050 * k->turbidity - 0.04586025928522;
    double alpha = SPM_SUN_HALF_DEG * M_PI / 180.0, s = sin(0.5 * alpha);
    double omega = 4.0 * M_PI * s * s; /* 2 pi (1 - cos alpha) */
    for (int i = 0; i <= 400; i++) {
        double um = (380.0 + i) / 1000.0;
        double tau = exp(-0.008735 * m * pow(um, -4.08)) * exp(-beta * m * pow(um, -1.3));
        L[i] = table_at(&t, 1, 380.0 + i) * tau / omega;
    }
    spm_csv_free(&t);
    return 0;
}

/* background sky elevation E turbidity T [azimuth A] [scale S] [sky F] [sun F] */
int spm_sky_statement(spm_scene *s, spm_lexer *lx, spm_error *err)
{
    static const struct {
        const char *kw, *what;
        double lo, hi;
        size_t off;
    } opt[] = {
        {"elevation", "the sun's elevation in degrees", 0.0, 90.0,
         offsetof(spm_sky, elevation)},
        {"turbidity", "a turbidity", 1.7, 10.0, offsetof(spm_sky, turbidity)},
        {"azimuth", "the sun's azimuth in degrees", -360.0, 360.0, offsetof(spm_sky, azimuth)},
        {"scale", "a scale", 0.0, 1e30, offsetof(spm_sky, scale)},
        {"sky", "the sky's factor", 0.0, 1e30, offsetof(spm_sky, sky)},
        {"sun", "the sun's factor", 0.0, 1e30, offsetof(spm_sky, sun)}};
    enum { NOPT = sizeof opt / sizeof opt[0] };
    char where[600];
    spm_lex_where(lx, where, sizeof where);
    if (spm_lex_next(lx, err))
        return 1;
    spm_sky k = {.azimuth = 0.0, .scale = 1.0, .sky = 1.0, .sun = 1.0};
    int seen[NOPT] = {0};
    while (lx->type != SPM_TOK_NEWLINE && lx->type != SPM_TOK_EOF) {
        int i = 0;
        while (i < NOPT && !(spm_lex_is(lx, opt[i].kw) && !seen[i]))
            i++;
        if (i == NOPT)
            return spm_lex_expected(lx, err, "'elevation', 'turbidity', 'azimuth', 'scale', "
                                             "'sky' or 'sun' (each once) or the end of the line");
        seen[i] = 1;
        if (spm_lex_next(lx, err) || spm_lex_number(lx, opt[i].what, opt[i].lo, opt[i].hi,
                                                    (double *)((char *)&k + opt[i].off), err))
            return 1;
    }
    if (!seen[0] || !seen[1]) {
        spm_errorf(err, "%s: a sky needs 'elevation DEG' and 'turbidity T'", where);
        return 1;
    }
    spm_scene_envmap *e = spm_xcalloc(1, sizeof *e);
    e->w = SPM_SKY_W;
    e->h = SPM_SKY_H;
    e->scale = 1.0;
    e->first = -1;
    e->sky = spm_xmalloc(sizeof *e->sky);
    *e->sky = k;
    snprintf(e->where, sizeof e->where, "%.127s", where);
    spm_envmap_free(s->env);
    s->env = e;
    return spm_lex_end_of_statement(lx, err);
}

/* a colour of the scene: samples (380 + i nm, i < n at step nm) made an
 * emission of Y = 1; *Y its Y before */
static int add_colour(spm_scene *s, const char *name, const double *wl, const double *v, size_t n,
                      double *Y, double uv[2], spm_error *err)
{
    spm_colour col;
    double xyz[3];
    memset(&col, 0, sizeof col);
    snprintf(col.name, sizeof col.name, "%s", name);
    if (spm_spectrum_from_samples(wl, v, n, SPM_KIND_EMISSION, name, &col.s, err))
        return 1;
    spm_xyz_emission(&col.s, xyz);
    if (!(xyz[1] > 0.0)) {
        spm_errorf(err, "%s: %s has no luminance", s->env->where, name);
        return 1;
    }
    spm_spectrum_scale(&col.s, 1.0 / xyz[1]);
    *Y = xyz[1];
    if (uv) { /* CIE 1976 u', v' */
        double den = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
        uv[0] = 4.0 * xyz[0] / den;
        uv[1] = 9.0 * xyz[1] / den;
    }
    s->colours = spm_xrealloc(s->colours, ((size_t)s->ncolours + 1) * sizeof *s->colours);
    s->colours[s->ncolours++] = col;
    return 0;
}

/* The sun: its spectral radiance as a colour of luminance 1 and its light,
 * p[DIR] toward it, p[SCALE] its luminance in kcd/m^2 (683 lm/W times the
 * y-bar integral, over 1000) times the factors, p[B] = 1 - cos alpha and
 * p[C] = sin^2 alpha of its angular radius alpha. */
static int add_sun(spm_scene *s, const spm_sky *k, spm_error *err)
{
    double L[401], wl[401], Y, w[3];
    if (!(k->scale * k->sun > 0.0))
        return 0;
    if (spm_sky_sun_radiance(k, L, err))
        return 1;
    for (int i = 0; i <= 400; i++)
        wl[i] = 380.0 + i;
    if (add_colour(s, "sun", wl, L, 401, &Y, NULL, err))
        return 1;
    spm_scene_light l;
    memset(&l, 0, sizeof l);
    l.kind = SPM_LIGHT_SUN;
    l.colour = s->ncolours - 1;
    spm_sky_sun_dir(k->elevation, k->azimuth, w);
    double a = SPM_SUN_HALF_DEG * M_PI / 180.0, h = sin(0.5 * a);
    for (int i = 0; i < 3; i++)
        l.p[SPM_LIGHT_P_DIR + i] = (float)w[i];
    l.p[SPM_LIGHT_P_SCALE] = (float)(0.683 * spm_cmf_y_integral() * Y * k->scale * k->sun);
    l.p[SPM_LIGHT_P_B] = (float)(2.0 * h * h);
    l.p[SPM_LIGHT_P_C] = (float)(sin(a) * sin(a));
    snprintf(l.where, sizeof l.where, "%s", s->env->where);
    s->lights = spm_xrealloc(s->lights, ((size_t)s->nlights + 1) * sizeof *s->lights);
    s->lights[s->nlights++] = l;
    return 0;
}

/* the CIE daylight weights of chromaticity x, y (CIE 015:2018 eq. 4.7-4.9):
 *   M = 0.0241 + 0.2562 x - 0.7341 y,
 *   M1 = (-1.3515 - 1.7703 x + 5.9114 y) / M,
 *   M2 = (0.0300 - 31.4424 x + 30.0717 y) / M */
static void daylight_m(double x, double y, double m[2])
{
    double den = 0.0241 + 0.2562 * x - 0.7341 * y;
    m[0] = (-1.3515 - 1.7703 * x + 5.9114 * y) / den;
    m[1] = (0.0300 - 31.4424 * x + 30.0717 * y) / den;
}

/* the texel's direction, at its centre: theta = pi (j + 1/2) / h, phi = 2 pi
 * (i + 1/2) / w, d = (sin t sin phi, cos t, -sin t cos phi) (envmap.h) */
static void texel_dir(const spm_scene_envmap *e, size_t t, double d[3])
{
    double th = M_PI * ((double)(t / e->w) + 0.5) / e->h, ph = 2.0 * M_PI * ((double)(t % e->w) + 0.5) / e->w;
    d[0] = sin(th) * sin(ph);
    d[1] = cos(th);
    d[2] = -sin(th) * cos(ph);
}

typedef struct {
    double *Y, (*m)[2], (*uv)[2], lo[2], hi[2];
} sky_texels;

/* the model at every texel: Y, (M1, M2), u'v', and the (M1, M2) box */
static void eval_texels(const spm_scene_envmap *e, sky_texels *tx)
{
    size_t n = (size_t)e->w * e->h;
    tx->Y = spm_xmalloc(n * sizeof *tx->Y);
    tx->m = spm_xmalloc(n * sizeof *tx->m);
    tx->uv = spm_xmalloc(n * sizeof *tx->uv);
    tx->lo[0] = tx->lo[1] = HUGE_VAL;
    tx->hi[0] = tx->hi[1] = -HUGE_VAL;
    for (size_t t = 0; t < n; t++) {
        double d[3], x, y;
        texel_dir(e, t, d);
        spm_sky_eval(e->sky, d, &tx->Y[t], &x, &y);
        daylight_m(x, y, tx->m[t]);
        double den = -2.0 * x + 12.0 * y + 3.0;
        tx->uv[t][0] = 4.0 * x / den;
        tx->uv[t][1] = 9.0 * y / den;
        if (!(tx->Y[t] > 0.0))
            continue;
        for (int k = 0; k < 2; k++) {
            tx->lo[k] = fmin(tx->lo[k], tx->m[t][k]);
            tx->hi[k] = fmax(tx->hi[k], tx->m[t][k]);
        }
    }
}

static int cell_of(const sky_texels *tx, size_t t)
{
    int c[2];
    for (int k = 0; k < 2; k++) {
        double span = tx->hi[k] - tx->lo[k];
        c[k] = span > 0.0 ? (int)((tx->m[t][k] - tx->lo[k]) / span * SPM_SKY_GRID) : 0;
        c[k] = c[k] < SPM_SKY_GRID ? c[k] : SPM_SKY_GRID - 1;
    }
    return c[0] * SPM_SKY_GRID + c[1];
}

/* cell c's colour: the basis spectrum S0 + M1 S1 + M2 S2 of its texels'
 * luminance-weighted mean (M1, M2) (sum[1..2] / sum[0]), negative values 0 */
static int cell_colour(spm_scene *s, const spm_csv *b, int c, const double sum[3], double uv[2],
                       spm_error *err)
{
    double *wl = spm_xmalloc(b->nrows * sizeof *wl), *v = spm_xmalloc(b->nrows * sizeof *v), Y;
    for (size_t i = 0; i < b->nrows; i++) {
        const double *r = &b->data[i * b->ncols];
        wl[i] = r[0];
        v[i] = fmax(0.0, r[1] + sum[1] / sum[0] * r[2] + sum[2] / sum[0] * r[3]);
    }
    char name[32];
    snprintf(name, sizeof name, "sky %d", c);
    int rc = add_colour(s, name, wl, v, b->nrows, &Y, uv, err);
    free(wl);
    free(v);
    return rc;
}

/* the palette: a colour per occupied (M1, M2) cell; each texel its cell's
 * colour and its Y times the factors; the chromaticity error of each texel's
 * model u'v' from its colour's */
static int make_palette(spm_scene *s, const spm_csv *b, const sky_texels *tx, spm_error *err)
{
    spm_scene_envmap *e = s->env;
    enum { NC = SPM_SKY_GRID * SPM_SKY_GRID };
    size_t n = (size_t)e->w * e->h;
    double sum[NC][3] = {{0}}, uv[NC][2], wsum = 0.0, dsum = 0.0, f = e->sky->scale * e->sky->sky;
    int cells[NC];
    for (size_t t = 0; t < n; t++)
        if (tx->Y[t] > 0.0 && f > 0.0) {
            int c = cell_of(tx, t);
            sum[c][0] += tx->Y[t];
            sum[c][1] += tx->Y[t] * tx->m[t][0];
            sum[c][2] += tx->Y[t] * tx->m[t][1];
        }
    e->first = s->ncolours;
    for (int c = 0; c < NC; c++) {
        cells[c] = -1;
        if (sum[c][0] > 0.0) {
            cells[c] = s->ncolours;
            if (cell_colour(s, b, c, sum[c], uv[c], err))
                return 1;
        }
    }
    e->ncolours = s->ncolours - e->first;
    e->colour = spm_xmalloc(n * sizeof *e->colour);
    e->lum = spm_xmalloc(n * sizeof *e->lum);
    e->duv_max = 0.0;
    for (size_t t = 0; t < n; t++) {
        int c = tx->Y[t] > 0.0 && f > 0.0 ? cell_of(tx, t) : -1;
        e->colour[t] = c >= 0 ? cells[c] : -1;
        e->lum[t] = c >= 0 ? (float)(tx->Y[t] * f) : 0.0f;
        if (c < 0)
            continue;
        double dd = hypot(tx->uv[t][0] - uv[c][0], tx->uv[t][1] - uv[c][1]);
        e->duv_max = fmax(e->duv_max, dd);
        dsum += dd * tx->Y[t];
        wsum += tx->Y[t];
    }
    e->duv_mean = wsum > 0.0 ? dsum / wsum : 0.0;
    return 0;
}

int spm_sky_palette(spm_scene *s, spm_error *err)
{
    if (!s->env || !s->env->sky || s->env->first >= 0)
        return 0;
    spm_csv b;
    if (load_table(BASIS_FILE, 4, &b, err))
        return 1;
    sky_texels tx;
    eval_texels(s->env, &tx);
    int rc = make_palette(s, &b, &tx, err) || add_sun(s, s->env->sky, err);
    free(tx.Y);
    free(tx.m);
    free(tx.uv);
    spm_csv_free(&b);
    return rc;
}
