/* Fluorescence in the spectral tables (fluor_tables.h). */
#include "fluor_tables.h"
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "fluor.h"

void spm_fluor_tables_count(const spm_scene *sc, spm_tables *t)
{
    t->nfluor = 0;
    t->fluor_first = sc->ncolours;
    for (int m = 0; m < sc->nmaterials; m++)
        if (sc->materials[m].diag >= 0) {
            t->nfluor++;
            if (sc->materials[m].diag < t->fluor_first)
                t->fluor_first = sc->materials[m].diag;
        }
}

/* Level-l matrix (bins(l) squared, M[o][i]) from the 1 nm one. */
static void matrix_level(const double *F0, int l, double *out)
{
    int n = SPM_LEVEL_BINS(l), w = SPM_TRUTH_BINS / n;
    memset(out, 0, sizeof *out * (size_t)n * (size_t)n);
    for (int o = 0; o < SPM_TRUTH_BINS; o++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            out[(size_t)(o / w) * n + i / w] += F0[(size_t)o * SPM_TRUTH_BINS + i];
    for (size_t k = 0; k < (size_t)n * n; k++)
        out[k] /= w;
}

/* Every level of material sc->materials[m]'s matrix, as doubles, into M[l]. */
static void matrices(const spm_scene *sc, int m, double *M[SPM_NUM_LEVELS])
{
    spm_fluor_matrix_1nm(sc, &sc->materials[m], M[0]);
    for (int l = 1; l < SPM_NUM_LEVELS; l++)
        matrix_level(M[0], l, M[l]);
}

static void alloc_levels(double *M[SPM_NUM_LEVELS])
{
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        M[l] = spm_xcalloc((size_t)SPM_LEVEL_BINS(l) * SPM_LEVEL_BINS(l), sizeof *M[l]);
}

static void free_levels(double *M[SPM_NUM_LEVELS])
{
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        free(M[l]);
}

/* Linear sRGB of 1 nm bins x (an emission: XYZ by truth's weights). */
static void srgb_1nm(const double *x, double rgb[3])
{
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    double xyz[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < 3; c++)
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            xyz[c] += x[b] * w[c][b];
    spm_xyz_to_linear_srgb(xyz, rgb);
}

/* inv = a^-1 (adjugate over determinant); 0 if a is singular. */
static int invert3(const double a[3][3], double inv[3][3])
{
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (!(det != 0.0))
        return 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][c] = (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) / det;
        }
    return 1;
}

/* rgb mode's 3 x 3 (fluor_tables.h spm_fluor_rgb) from the 1 nm matrix F0. */
static void rgb_matrix(const double *F0, const spm_spectrum *d65, float *out)
{
    static const int edge[4] = {0, 110, 210, SPM_TRUTH_BINS}; /* 380, 490, 590, 780 nm */
    double in[3][3], res[3][3], inv[3][3], x[SPM_TRUTH_BINS], y[SPM_TRUTH_BINS];
    for (int c = 0; c < 3; c++) {
        double ri[3], ro[3];
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            x[b] = b >= edge[c] && b < edge[c + 1] ? d65->nm1[b] : 0.0;
        for (int o = 0; o < SPM_TRUTH_BINS; o++) {
            y[o] = 0.0;
            for (int i = 0; i < SPM_TRUTH_BINS; i++)
                y[o] += F0[(size_t)o * SPM_TRUTH_BINS + i] * x[i];
        }
        srgb_1nm(x, ri);
        srgb_1nm(y, ro);
        for (int k = 0; k < 3; k++)
            in[k][c] = ri[k], res[k][c] = ro[k];
    }
    memset(out, 0, 9 * sizeof *out);
    if (!invert3(in, inv))
        return;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double s = 0.0;
            for (int k = 0; k < 3; k++)
                s += res[r][k] * inv[k][c];
            out[r * 3 + c] = (float)s;
        }
}

void spm_fluor_rgb(const spm_tables *t, int f, float out[3][3])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out[r][c] = t->fluor_rgb[(size_t)f * 9 + (size_t)r * 3 + c];
}

void spm_fluor_tables_fill(const spm_scene *sc, const spm_spectrum *d65, spm_tables *t)
{
    if (!t->nfluor)
        return;
    double *M[SPM_NUM_LEVELS];
    alloc_levels(M);
    for (int m = 0; m < sc->nmaterials; m++) {
        int f = sc->materials[m].diag - t->fluor_first;
        if (sc->materials[m].diag < 0)
            continue;
        matrices(sc, m, M);
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            size_t nn = (size_t)SPM_LEVEL_BINS(l) * SPM_LEVEL_BINS(l);
            for (size_t k = 0; k < nn; k++)
                t->fluor[l][(size_t)f * nn + k] = (float)M[l][k];
        }
        rgb_matrix(M[0], d65, &t->fluor_rgb[(size_t)f * 9]);
    }
    free_levels(M);
}

/* y = D x + F x at level l (n bins); x, y bin means. */
static void apply(const double *D, const double *F, int n, const double *x, double *y)
{
    for (int o = 0; o < n; o++) {
        double s = D[o] * x[o];
        for (int i = 0; i < n; i++)
            s += F[(size_t)o * n + i] * x[i];
        y[o] = s;
    }
}

/* XYZ of level-l bins y (the level's weights: sums of truth's). */
static void xyz_level(const double *y, int l, double xyz[3])
{
    double w[3][SPM_TRUTH_BINS];
    spm_cmf_level(l, w);
    for (int c = 0; c < 3; c++) {
        xyz[c] = 0.0;
        for (int b = 0; b < SPM_LEVEL_BINS(l); b++)
            xyz[c] += y[b] * w[c][b];
    }
}

/* The worst error at level l over the contexts (x: nctx lights at 1 nm),
 * with `times` products (1 or 2). */
static double level_error(const double *const M[SPM_NUM_LEVELS], const spm_spectrum *D,
                          const spm_spectrum *ctx, int nctx, int l, int times, spm_metric metric)
{
    int n = SPM_LEVEL_BINS(l);
    double Dl[SPM_TRUTH_BINS], D0[SPM_TRUTH_BINS], x0[SPM_TRUTH_BINS], xl[SPM_TRUTH_BINS];
    double y0[SPM_TRUTH_BINS], yl[SPM_TRUTH_BINS], worst = 0.0;
    spm_spectrum_level(D, l, Dl);
    spm_spectrum_level(D, 0, D0);
    for (int c = 0; c < nctx; c++) {
        spm_spectrum_level(&ctx[c], 0, x0);
        spm_spectrum_level(&ctx[c], l, xl);
        for (int k = 0; k < times; k++) {
            apply(D0, M[0], SPM_TRUTH_BINS, x0, y0);
            apply(Dl, M[l], n, xl, yl);
            memcpy(x0, y0, sizeof x0);
            memcpy(xl, yl, sizeof xl);
        }
        double r[3], e[3];
        xyz_level(y0, 0, r);
        xyz_level(yl, l, e);
        double err = spm_pretest_xyz_error(r, e, metric);
        worst = err > worst ? err : worst;
    }
    return worst;
}

static int is_fluor(const spm_scene_material *m)
{
    return m->type == (int)SPM_MAT_FLUOR || m->type == (int)SPM_MAT_DONALDSON;
}

void spm_fluor_ingredients(const spm_scene *sc, unsigned char *ingr)
{
    int n = sc->ncolours;
    memset(ingr, 0, (size_t)n);
    for (int m = 0; m < sc->nmaterials; m++) {
        const spm_scene_material *mt = &sc->materials[m];
        const int c[3] = {mt->refl, mt->col2, mt->col3};
        if (is_fluor(mt))
            for (int j = 0; j < 3; j++)
                if (c[j] >= 0 && c[j] < n)
                    ingr[c[j]] = 1;
    }
    /* a colour another material, an emitter or a background also uses is on paths */
    for (int m = 0; m < sc->nmaterials; m++) {
        const spm_scene_material *mt = &sc->materials[m];
        const int c[4] = {mt->refl, mt->col2, mt->col3, mt->emit};
        for (int j = 0; j < 4; j++)
            if (c[j] >= 0 && c[j] < n && (j == 3 || !is_fluor(mt)))
                ingr[c[j]] = 0;
    }
    const int bg[2] = {sc->bg_up, sc->bg_down};
    for (int j = 0; j < 2; j++)
        if (bg[j] >= 0 && bg[j] < n)
            ingr[bg[j]] = 0;
}

/* The contexts: every emission colour and background, and each times every
 * reflectance a path records (the dye lit by light another surface
 * reflected; a dye's absorption and emission shapes are no such factor). */
static int contexts(const spm_scene *sc, spm_spectrum **out)
{
    int ne = 0, nr = 0, n = 0;
    unsigned char *ingr = spm_xcalloc((size_t)sc->ncolours + 1, 1);
    spm_fluor_ingredients(sc, ingr);
    for (int c = 0; c < sc->ncolours; c++)
        sc->colours[c].s.kind == SPM_KIND_EMISSION ? ne++ : nr++;
    spm_spectrum *x = spm_xcalloc((size_t)ne * (size_t)(nr + 1) + 1, sizeof *x);
    for (int c = 0; c < sc->ncolours; c++) {
        if (sc->colours[c].s.kind != SPM_KIND_EMISSION)
            continue;
        x[n++] = sc->colours[c].s;
        for (int r = 0; r < sc->ncolours; r++)
            if (sc->colours[r].s.kind != SPM_KIND_EMISSION && !ingr[r]) {
                x[n] = sc->colours[c].s;
                spm_spectrum_multiply(&x[n++], &sc->colours[r].s);
            }
    }
    free(ingr);
    *out = x;
    return n;
}

void spm_fluor_pretest(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                       uint8_t *lvlk)
{
    if (!t->nfluor || !lvlk)
        return;
    spm_spectrum *ctx;
    int nctx = contexts(sc, &ctx);
    double *M[SPM_NUM_LEVELS];
    alloc_levels(M);
    for (int m = 0; m < sc->nmaterials; m++) {
        int d = sc->materials[m].diag;
        if (d < 0)
            continue;
        matrices(sc, m, M);
        int lv[2] = {0, 0}; /* one product, two */
        for (int k = 0; k < 2; k++)
            for (int l = 1; l <= po->coarsest_level && l < SPM_NUM_LEVELS; l++) {
                if (level_error((const double *const *)M, &sc->colours[d].s, ctx, nctx, l, k + 1,
                                po->metric) > po->threshold)
                    break;
                lv[k] = l;
            }
        lv[1] = lv[1] < lv[0] ? lv[1] : lv[0];
        for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
            uint8_t *e = &lvlk[(size_t)d * SPM_PRETEST_KMAX + k];
            int want = lv[k ? 1 : 0];
            *e = (uint8_t)(want < *e ? want : *e);
        }
    }
    free_levels(M);
    free(ctx);
}
