/* Spectral tables: every scene colour prepared at every representation the
 * modes need, plus the pretest's levels and the device materials. */
#include "tables.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "csv.h"
#include "interrupt.h"
#include "materials.h"
#include "mlc_tables.h"
#include "fluor_tables.h"

static void fill_levels(const spm_spectrum *s, int c, spm_tables *t)
{
    double bins[SPM_TRUTH_BINS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        spm_spectrum_level(s, l, bins);
        for (int b = 0; b < nb; b++)
            t->lvl[l][(size_t)c * nb + b] = (float)bins[b];
    }
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        t->truth[(size_t)c * SPM_TRUTH_BINS + i] = (float)s->nm1[i];
}

/* rgb mode: a reflectance becomes its linear sRGB under D65, normalised so the
 * perfect white is (1,1,1); an emission becomes the linear sRGB of its XYZ. */
static void fill_rgb(const spm_spectrum *s, const spm_spectrum *d65, const double white_rgb[3],
                     float out[4])
{
    double xyz[3], rgb[3];
    if (s->kind == SPM_KIND_EMISSION) {
        spm_xyz_emission(s, xyz);
        spm_xyz_to_linear_srgb(xyz, rgb);
    } else {
        spm_xyz_reflectance(s, d65, xyz);
        spm_xyz_to_linear_srgb(xyz, rgb);
        for (int i = 0; i < 3; i++)
            rgb[i] /= white_rgb[i];
    }
    for (int i = 0; i < 3; i++)
        out[i] = (float)rgb[i];
    out[3] = 0.0f;
}

/* D65 (loaded once, colour.h spm_d65) and the linear sRGB of white under it. */
static int load_d65(const spm_spectrum **d65, double white_rgb[3], spm_error *err)
{
    spm_spectrum white;
    if (!(*d65 = spm_d65(err)))
        return 1;
    spm_spectrum_constant(1.0, SPM_KIND_REFLECTANCE, &white);
    double xyz[3];
    spm_xyz_reflectance(&white, *d65, xyz);
    spm_xyz_to_linear_srgb(xyz, white_rgb);
    return 0;
}

static void fill_cmf(spm_tables *t)
{
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            t->cmf_truth[c][i] = (float)w[c][i];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        double lw[3][SPM_TRUTH_BINS];
        spm_cmf_level(l, lw);
        for (int c = 0; c < 3; c++)
            for (int b = 0; b < SPM_TRUTH_BINS; b++)
                t->cmf_lvl[l][c][b] = b < SPM_LEVEL_BINS(l) ? (float)lw[c][b] : 0.0f;
    }
}

/* hero: pbrt-v4's visible-importance density p(l) ~ sech^2(a (l - c)),
 * a = 0.0072 / nm, c = 538 nm, truncated to 380-780 nm and renormalised.
 * Since d/dl tanh(a (l - c)) = a sech^2(a (l - c)), its CDF on [380, 780] is
 *   F(l) = (tanh(a (l - c)) - t0) / dt,  t0 = tanh(a (380 - c)),
 *                                        dt = tanh(a (780 - c)) - t0,
 * so u in [0, 1) maps to y = t0 + u dt, l = c + atanh(y) / a, and the
 * density there is exactly
 *   p(l) = F'(l) = a sech^2(a (l - c)) / dt = a (1 - y^2) / dt,
 * as tanh(a (l - c)) = y. (pbrt's constants 0.85691062 = -tanh(a (360 - c)),
 * 1.82750197 = its dt and 0.0039398042 = a / dt are this on 360-830 nm.)
 * F is monotone, so the 1 nm bin holding l is the one whose edges' tanh
 * bracket y: comparing y with the edges makes the bin exact whatever the
 * rounding of atanh. The kernel finds it without atanh: y is linear in u, so
 * the sample space is cut into SPM_HERO_CELLS cells of 1.75 / 4096 = 4.3e-4
 * in y, narrower than the narrowest bin (0.0072 (1 - 0.94^2) = 8.4e-4 at
 * 780 nm). A cell's entry is the bin of its start less 1e-6 in y: far above
 * the float rounding of y and of the edges (a few 1e-8), far below a bin.
 * So it is never past the bin of a sample in the cell, and the cell and
 * margin, shorter than a bin, hold at most one edge: the sample is in the
 * entry's bin or the next, and one comparison with an edge decides. */
void spm_tables_fill_hero(spm_tables *t)
{
    const double a = SPM_HERO_A, c = SPM_HERO_CENTER;
    double t0 = tanh(a * (SPM_LAMBDA_MIN - c)), dt = tanh(a * (SPM_LAMBDA_MAX - c)) - t0;
    double edge[SPM_TRUTH_BINS + 1];
    t->hero_t0 = (float)t0;
    t->hero_dt = (float)dt;
    t->hero_pdfk = (float)(a / dt);
    for (int i = 0; i <= SPM_TRUTH_BINS; i++) {
        edge[i] = tanh(a * (SPM_LAMBDA_MIN + i - c));
        t->hero_edge[i] = (float)edge[i];
    }
    int j = 0;
    for (int k = 0; k < SPM_HERO_CELLS; k++) {
        double y = t0 + dt * k / SPM_HERO_CELLS - 1e-6;
        while (j < SPM_TRUTH_BINS - 1 && y >= edge[j + 1])
            j++;
        t->hero_index[k] = (float)j;
    }
}

static void fill_materials(const spm_scene *sc, spm_tables *t)
{
    for (int m = 0; m < sc->nmaterials; m++)
        spm_material_fill(sc, &sc->materials[m], &t->materials[m]); /* by its descriptors */
    t->bg_up = sc->bg_up >= 0 ? (spm_u32)sc->bg_up : SPM_NONE;
    t->bg_down = sc->bg_down >= 0 ? (spm_u32)sc->bg_down : SPM_NONE;
    t->ndisp = sc->ndisp;
}

/* The pretest over the scene's colours. A conductor's eta and k are no
 * reflectances: they are left out of the set, and get the levels of their
 * Fresnel (spm_conductor_pretest; a colour two conductors share, the finer);
 * likewise a dielectric's absorption sigma, the levels of its transmittance
 * over the lengths inside (spm_dielectric_pretest).
 * 1 when interrupted (*done: colours done). */
static int pretest_colours(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t, int *done)
{
    int n = sc->ncolours;
    int *optical = spm_xcalloc((size_t)n + 1, sizeof *optical), *at = spm_xcalloc((size_t)n + 1, sizeof *at);
    for (int i = 0; i < sc->nmaterials; i++)
        if (sc->materials[i].type == SPM_MAT_CONDUCTOR) {
            if (sc->materials[i].refl >= 0)
                optical[sc->materials[i].refl] = 1;
            if (sc->materials[i].col2 >= 0)
                optical[sc->materials[i].col2] = 1;
        } else if (sc->materials[i].type == SPM_MAT_DIELECTRIC && sc->materials[i].col2 >= 0) {
            optical[sc->materials[i].col2] = 1;
        }
    /* a dye's absorption and emission shapes are judged, but are no factor of
     * the others' products (spm_fluor_ingredients) */
    unsigned char *ingr = spm_xcalloc((size_t)n + 1, 1), *skip = spm_xcalloc((size_t)n + 1, 1);
    spm_fluor_ingredients(sc, ingr);
    const spm_spectrum **set = spm_xcalloc((size_t)n + 1, sizeof *set);
    const spm_spectrum **factors = spm_xcalloc((size_t)n + 1, sizeof *factors);
    int m = 0, nf = 0;
    for (int c = 0; c < n; c++)
        if (!optical[c]) {
            skip[m] = ingr[c];
            if (!ingr[c])
                factors[nf++] = &sc->colours[c].s;
            at[m] = c, set[m++] = &sc->colours[c].s;
        }
    spm_pretest_result *res = spm_xcalloc((size_t)m + 1, sizeof *res);
    *done = spm_pretest_run_skip(set, m, skip, po, res);
    for (int i = 0; i < m; i++)
        t->pretest[at[i]] = res[i];
    int stopped = spm_stop_requested();
    for (int i = 0; i < sc->nmaterials && !stopped; i++) {
        const spm_scene_material *mt = &sc->materials[i];
        int diel = mt->type == SPM_MAT_DIELECTRIC && mt->col2 >= 0;
        if (!diel && (mt->type != SPM_MAT_CONDUCTOR || mt->refl < 0 || mt->col2 < 0))
            continue;
        spm_pretest_result r;
        if (diel)
            spm_dielectric_pretest(factors, nf, &sc->colours[mt->col2].s, mt->p[SPM_DIEL_P_LEN],
                                   n + i, po, &r);
        else
            spm_conductor_pretest(factors, nf, &sc->colours[mt->refl].s, &sc->colours[mt->col2].s,
                                  n + i, po, &r);
        for (int j = diel; j < 2; j++) {
            int c = j ? mt->col2 : mt->refl;
            if (optical[c] == 1)
                t->pretest[c] = r, optical[c] = 2; /* the first conductor that uses it */
            else
                for (int k = 0; k <= SPM_PRETEST_KMAX; k++) {
                    int *l = k < SPM_PRETEST_KMAX ? &t->pretest[c].level_k[k] : &t->pretest[c].level;
                    int rl = k < SPM_PRETEST_KMAX ? r.level_k[k] : r.level;
                    *l = rl < *l ? rl : *l;
                }
        }
        stopped = spm_stop_requested();
    }
    free(res);
    free(set);
    free(factors);
    free(ingr);
    free(skip);
    free(optical);
    free(at);
    return stopped;
}

int spm_tables_prepare(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                       spm_error *err)
{
    memset(t, 0, sizeof *t);
    if (sc->ncolours >= (int)SPM_NONE) {
        spm_errorf(err, "%s: too many colours (%d, at most %u)", sc->path, sc->ncolours,
                   SPM_NONE - 1);
        return 1;
    }
    for (int i = 0; i < sc->nmaterials; i++)
        if (spm_material_types[sc->materials[i].type].vertex_u32 &&
            sc->ncolours > (int)SPM_VX_MAX_COLOURS) {
            /* the vertex words keep a colour id in 14 bits (spm_vertex_ext) */
            spm_errorf(err, "%s: too many colours for a %s (%d, at most %u)", sc->path,
                       spm_material_types[sc->materials[i].type].keyword, sc->ncolours,
                       SPM_VX_MAX_COLOURS);
            return 1;
        }
    if (spm_cmf_init(err))
        return 1;
    double white_rgb[3];
    const spm_spectrum *d65;
    if (load_d65(&d65, white_rgb, err))
        return 1;
    int n = sc->ncolours;
    t->ncolours = n;
    t->nmaterials = sc->nmaterials;
    spm_fluor_tables_count(sc, t);
    spm_tables_alloc(t);
    for (int c = 0; c < n; c++) {
        fill_levels(&sc->colours[c].s, c, t);
        fill_rgb(&sc->colours[c].s, d65, white_rgb, &t->rgb[(size_t)c * 4]);
    }
    fill_cmf(t);
    spm_tables_fill_hero(t);
    fill_materials(sc, t);

    t->coarsest_level = po->coarsest_level;
    spm_fluor_tables_fill(sc, d65, t);
    return spm_mlc_tables_build(sc, po, t, 0, err);
}

int spm_tables_levels(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                      int composite, spm_error *err)
{
    if (t->levels_done[composite != 0])
        return 0;
    if (composite) {
        if (spm_mlc_tables_build(sc, po, t, 1, err))
            return 1;
        spm_fluor_pretest(sc, po, t, t->mlc_lvlk);
        if (spm_stop_requested()) {
            spm_errorf(err, "interrupted during the Composite Model pretests");
            return 1;
        }
    } else {
        /* ml levels: the pretest over the scene's whole set of colours */
        int done = 0, n = sc->ncolours;
        if (pretest_colours(sc, po, t, &done)) {
            spm_errorf(err, "interrupted during the pretests (%d of %d colours done)", done, n);
            return 1;
        }
        for (int c = 0; c < n; c++)
            for (int k = 0; k < SPM_PRETEST_KMAX; k++)
                t->lvlk[(size_t)c * SPM_PRETEST_KMAX + k] = (uint8_t)t->pretest[c].level_k[k];
        spm_fluor_pretest(sc, po, t, t->lvlk);
    }
    t->levels_done[composite != 0] = 1;
    return 0;
}

int spm_tables_build(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                     spm_error *err)
{
    return spm_tables_prepare(sc, po, t, err) || spm_tables_levels(sc, po, t, 0, err) ||
           spm_tables_levels(sc, po, t, 1, err);
}

/* The list (tables.h SPM_TABLES_ARRAYS) expanded: make, free, count. */
#define ALLOC_A(name, type, count) t->name = spm_xcalloc((count) + 1, sizeof(type));
#define ALLOC_L(name, type, count)                 \
    for (int l = 0; l < SPM_NUM_LEVELS; l++)       \
        t->name[l] = spm_xcalloc((count) + 1, sizeof(type));
void spm_tables_alloc(spm_tables *t)
{
    SPM_TABLES_ARRAYS(ALLOC_A, ALLOC_L)
}

#define BYTES_A(name, type, count) bytes += t->name ? (count) * sizeof(type) : 0;
#define BYTES_L(name, type, count)           \
    for (int l = 0; l < SPM_NUM_LEVELS; l++) \
        bytes += t->name[l] ? (count) * sizeof(type) : 0;
size_t spm_tables_bytes(const spm_tables *t)
{
    size_t bytes = 0;
    SPM_TABLES_ARRAYS(BYTES_A, BYTES_L)
    return bytes;
}

#define FREE_A(name, type, count) free(t->name);
#define FREE_L(name, type, count)            \
    for (int l = 0; l < SPM_NUM_LEVELS; l++) \
        free(t->name[l]);
void spm_tables_free(spm_tables *t)
{
    SPM_TABLES_ARRAYS(FREE_A, FREE_L)
    memset(t, 0, sizeof *t);
}
