/* Spectral tables for the device and the CPU reference: every scene colour at
 * every level, in truth, as RGB, with the pretest's per-occurrence levels,
 * plus the Composite Model's spike lanes and the hero-wavelength density. */
#ifndef SPM_TABLES_H
#define SPM_TABLES_H
#include <stdint.h>
#include "scene.h"
#include "pretest.h"

typedef struct {
    int ncolours;
    float *lvl[SPM_NUM_LEVELS];    /* ncolours x SPM_LEVEL_BINS(l), bin means (lvl[0]: truth's) */
    float *truth;                  /* ncolours x SPM_TRUTH_BINS */
    float *rgb;                    /* ncolours x 4: linear sRGB (reflectance D65-referred, white = 1) */
    float cmf_lvl[SPM_NUM_LEVELS][3][SPM_TRUTH_BINS];  /* XYZ weights per level (bins(l) used) */
    float cmf_truth[3][SPM_TRUTH_BINS];
    /* ml: level for a colour met k times on a path: lvlk[c * SPM_PRETEST_KMAX + (k-1)] */
    uint8_t *lvlk;
    int coarsest_level;            /* the coarsest level the pretest could pick */
    spm_pretest_result *pretest;   /* per colour */

    /* mlc (Composite Model): nspikes lanes shared by the scene. */
    int nspikes;
    float spike_wl[SPM_MAX_SPIKES];
    float *mlc_lvl[SPM_NUM_LEVELS];  /* ncolours x (SPM_LEVEL_BINS(l) + SPM_MAX_SPIKES): smooth bins then spike lanes */
    float spike_cmf[3][SPM_MAX_SPIKES];
    uint8_t *mlc_lvlk;             /* as lvlk, from the composite representation's error */
    spm_pretest_result *mlc_pretest;  /* per colour (mlc_pretest.h) */

    /* hero: the wavelength density's constants (spm_shared.h SPM_HERO_*) */
    float hero_t0, hero_dt, hero_pdfk;
    float hero_edge[SPM_TRUTH_BINS + 1];
    float hero_index[SPM_HERO_CELLS];

    spm_material *materials;       /* per scene material */
    int nmaterials;
    spm_u32 bg_up, bg_down;        /* background colour ids (SPM_NONE: none), for spm_trace_params */
} spm_tables;

int spm_tables_build(const spm_scene *scene, const spm_pretest_opts *po, spm_tables *t,
                     spm_error *err);
void spm_tables_free(spm_tables *t);
/* Fills the hero fields: needs nothing else of the tables. */
void spm_tables_fill_hero(spm_tables *t);
#endif
