/* Spectral tables for the device and the CPU reference: every scene colour at
 * every level, in truth, as RGB, with the pretest's per-occurrence levels,
 * plus the Composite Model's spike lanes and the hero-wavelength density. */
#ifndef SPM_TABLES_H
#define SPM_TABLES_H
#include <stddef.h>
#include <stdint.h>
#include "scene.h"
#include "pretest.h"

/* The tables' arrays, listed once. Every array of spm_tables is an entry
 * here, and nowhere else by hand: the struct declares them from this list,
 * spm_tables_build allocates them (zeroed, one spare element), spm_tables_free
 * frees them, the MPI block (host/mpi/prepared.c) packs and unpacks them and
 * spm_tables_bytes adds them up, all from the list. Each builder (a mode's,
 * the pretest's, the materials') only fills its arrays.
 *   A(name, element type, element count)          one array
 *   L(name, element type, element count at l)     one array per level l
 * Counts are expressions in t (the tables: ncolours, nmaterials are set
 * before the arrays are made) and, for L, in l. A struct pointer added
 * outside this list would travel to the other ranks as a raw address. */
#define SPM_TABLES_ARRAYS(A, L)                                                   \
    L(lvl, float, (size_t)(t)->ncolours * SPM_LEVEL_BINS(l))                     \
    A(truth, float, (size_t)(t)->ncolours * SPM_TRUTH_BINS)                      \
    A(rgb, float, (size_t)(t)->ncolours * 4)                                     \
    A(lvlk, uint8_t, (size_t)(t)->ncolours * SPM_PRETEST_KMAX)                   \
    A(pretest, spm_pretest_result, (size_t)(t)->ncolours)                        \
    L(mlc_lvl, float, (size_t)(t)->ncolours * SPM_MLC_STRIDE(l))                 \
    A(mlc_lvlk, uint8_t, (size_t)(t)->ncolours * SPM_PRETEST_KMAX)               \
    A(mlc_pretest, spm_pretest_result, (size_t)(t)->ncolours)                    \
    A(materials, spm_material, (size_t)(t)->nmaterials)                          \
    L(fluor, float, (size_t)(t)->nfluor * SPM_LEVEL_BINS(l) * SPM_LEVEL_BINS(l))  \
    A(fluor_rgb, float, (size_t)(t)->nfluor * 9)                                 \
    SPM_TABLES_TEST_ARRAYS(A, L)

/* A test build (tests/test_tables_list.c) appends an array to the list
 * (last, so every other field keeps its offset) and sees it arrive. */
#ifdef SPM_TABLES_TEST_ARRAY
#define SPM_TABLES_TEST_ARRAYS(A, L) A(test_extra, double, (size_t)(t)->ncolours * 3 + 1)
#else
#define SPM_TABLES_TEST_ARRAYS(A, L)
#endif

#define SPM_TABLES_DECL_A(name, type, count) type *name;
#define SPM_TABLES_DECL_L(name, type, count) type *name[SPM_NUM_LEVELS];

typedef struct {
    int ncolours;
    int nmaterials;
    /* Fluorescent materials (fluor_tables.h): their diagonal colours are
     * colours fluor_first .. fluor_first + nfluor - 1, the last ones. */
    int nfluor, fluor_first;
    /* Dispersive glasses (the scene's ndisp): their paths shade from the 1 nm
     * rows (modes.h spm_shade_table nm1) */
    int ndisp;
    /* lvl[l]: ncolours x SPM_LEVEL_BINS(l), bin means (lvl[0]: truth's)
     * truth: ncolours x SPM_TRUTH_BINS
     * rgb: ncolours x 4: linear sRGB (reflectance D65-referred, white = 1)
     * lvlk (ml): level for a colour met k times on a path: lvlk[c * SPM_PRETEST_KMAX + (k-1)]
     * pretest: per colour
     * mlc_lvl[l]: ncolours x (SPM_LEVEL_BINS(l) + SPM_MAX_SPIKES): smooth bins then spike lanes
     * mlc_lvlk: as lvlk, from the composite representation's error
     * mlc_pretest: per colour (mlc_pretest.h)
     * materials: per scene material
     * fluor[l]: nfluor x bins(l) x bins(l), the fluorescent part of each
     *   re-radiation matrix at level l as M[o][i] (row o output, column i input)
     * fluor_rgb: nfluor x 3 x 3, rgb mode's M[o][i] (fluor_tables.h) */
    float cmf_lvl[SPM_NUM_LEVELS][3][SPM_TRUTH_BINS];  /* XYZ weights per level (bins(l) used) */
    float cmf_truth[3][SPM_TRUTH_BINS];
    int coarsest_level;            /* the coarsest level the pretest could pick */
    int levels_done[2];            /* lvlk, mlc_lvlk hold their pretest's levels (else 0: finest) */

    /* mlc (Composite Model): nspikes lanes shared by the scene. */
    int nspikes;
    float spike_wl[SPM_MAX_SPIKES];
    float spike_cmf[3][SPM_MAX_SPIKES];

    /* hero: the wavelength density's constants (spm_shared.h SPM_HERO_*) */
    float hero_t0, hero_dt, hero_pdfk;
    float hero_edge[SPM_TRUTH_BINS + 1];
    float hero_index[SPM_HERO_CELLS];

    spm_u32 bg_up, bg_down;        /* background colour ids (SPM_NONE: none), for spm_trace_params */

    /* the arrays (the list above), last */
    SPM_TABLES_ARRAYS(SPM_TABLES_DECL_A, SPM_TABLES_DECL_L)
} spm_tables;

/* A conductor's pretest: its Fresnel F(eta, k, c) as each level renders it
 * (F of the level's bins of eta and k) against F of the 1 nm eta and k,
 * judged as a reflectance (spm_pretest_given) against set[0..n-1] (the
 * scene's colours other than optical constants) at six incidence cosines
 * from 1 to 0.05, the worst of them kept (conductor_pretest.c says why). */
void spm_conductor_pretest(const spm_spectrum *const *set, int n, const spm_spectrum *eta,
                           const spm_spectrum *k, int self, const spm_pretest_opts *o,
                           spm_pretest_result *out);
/* The incidence cosines a conductor's Fresnel is judged at (both pretests),
 * and the fold of one cosine's result r into out (first: out = r): the worst
 * error and the finest level of the two. */
#define SPM_CONDUCTOR_NCOS 6
extern const double spm_conductor_cosines[SPM_CONDUCTOR_NCOS];
void spm_conductor_pretest_merge(spm_pretest_result *out, const spm_pretest_result *r, int first);
/* A dielectric's pretest: its transmittance exp(-sigma d) as each level
 * renders it (exp of the level's bin means of sigma) against exp of the 1 nm
 * sigma, judged as a reflectance (spm_pretest_given) against set[0..n-1] at
 * six lengths d from dmax / 32 to dmax, the worst kept
 * (dielectric_pretest.c says why). */
void spm_dielectric_pretest(const spm_spectrum *const *set, int n, const spm_spectrum *sigma,
                            double dmax, int self, const spm_pretest_opts *o,
                            spm_pretest_result *out);
/* The lengths a dielectric's transmittance is judged at (both pretests), as
 * fractions of the longest segment inside. */
#define SPM_DIELECTRIC_NLEN 6
extern const double spm_dielectric_fractions[SPM_DIELECTRIC_NLEN];
/* Every table with both pretests' levels (spm_tables_prepare, then
 * spm_tables_levels for ml and for mlc). */
int spm_tables_build(const spm_scene *scene, const spm_pretest_opts *po, spm_tables *t,
                     spm_error *err);
/* Every table but the pretests' levels: lvlk and mlc_lvlk stay 0 (the finest
 * level), which only a levelled mode reads. */
int spm_tables_prepare(const spm_scene *scene, const spm_pretest_opts *po, spm_tables *t,
                       spm_error *err);
/* The pretest a levelled mode reads (composite: mlc's, else ml's), run once:
 * the pretests are most of a small render's set-up, and truth, ref, hero and
 * rgb need neither. */
int spm_tables_levels(const spm_scene *scene, const spm_pretest_opts *po, spm_tables *t,
                      int composite, spm_error *err);
void spm_tables_free(spm_tables *t);
/* Makes every listed array for t's ncolours and nmaterials, zeroed (with one
 * spare element, so a count of 0 is a valid pointer); spm_tables_build calls
 * it before the builders fill them. */
void spm_tables_alloc(spm_tables *t);
/* The bytes of every listed array (the tables' host footprint). */
size_t spm_tables_bytes(const spm_tables *t);
/* Fills the hero fields: needs nothing else of the tables. */
void spm_tables_fill_hero(spm_tables *t);
#endif
