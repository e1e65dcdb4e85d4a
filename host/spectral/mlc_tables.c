/* Composite Model tables (mlc): every emission is split into a smooth part and
 * spikes; the scene's spikes share a pattern table of at most SPM_MAX_SPIKES
 * lanes. Per colour and level a row holds the smooth bins, then the lanes:
 * an emission's energy in each lane, a reflectance's mean over each lane's
 * spike profile. The lane XYZ weights are the CMFs' means over the same
 * profiles, so a spike is a delta of the given area and the shade arithmetic
 * stays one fused vector multiply-add. The levels come from the composite's
 * error against truth (mlc_pretest.c). */
#include "mlc_tables.h"
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "mlc_pretest.h"
#include "spikes.h"
#include "fluor_tables.h"

#define MERGE_NM 1.0  /* spikes of different lights closer than this share a lane */

/* A lane's profile: the 1 nm energy of the spikes it carries, each light's
 * divided by the norm that ranks its spikes (so the lane's wavelength, the
 * area-weighted centroid, is the profile's centroid). A lane's XYZ weight and
 * a reflectance's lane value are means over it, not point values at the
 * centroid: a 5 nm-sampled line is ~10 nm wide at 1 nm with feet further out,
 * and across that width the CMFs curve and a reflectance's edge may pass.
 * With the means, one light's spikes on their own give truth's XYZ exactly. */
typedef struct {
    double g[SPM_MAX_SPIKES][SPM_TRUTH_BINS];
    double sum[SPM_MAX_SPIKES];
} lane_profile;

static void lane_profiles(const spm_spike_light *lights, int nlights, lane_profile *p)
{
    memset(p, 0, sizeof *p);
    for (int l = 0; l < nlights; l++) {
        const spm_spike_light *L = &lights[l];
        for (int s = 0; s < L->nspikes; s++) {
            int k = L->spike_lane[s];
            if (k < 0)
                continue;
            for (int i = L->spikes[s].first; i <= L->spikes[s].last; i++) {
                double e = (L->in->nm1[i] - L->smooth->nm1[i]) / L->norm;
                p->g[k][i] += e;
                p->sum[k] += e;
            }
        }
    }
}

/* Mean of v over lane k's profile; at the lane's 1 nm bin if it has no energy. */
static double lane_mean(const lane_profile *p, int k, double wl, const double *v)
{
    if (!(p->sum[k] > 0.0)) {
        int i = (int)(wl - SPM_LAMBDA_MIN);
        return v[i < 0 ? 0 : i >= SPM_TRUTH_BINS ? SPM_TRUTH_BINS - 1 : i];
    }
    double s = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        s += p->g[k][i] * v[i];
    return s / p->sum[k];
}

static void fill_row(const spm_spectrum *smooth, const double lanes[SPM_MAX_SPIKES], int c,
                     spm_tables *t)
{
    double bins[SPM_TRUTH_BINS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        float *row = &t->mlc_lvl[l][(size_t)c * SPM_MLC_STRIDE(l)];
        spm_spectrum_level(smooth, l, bins);
        for (int b = 0; b < SPM_LEVEL_BINS(l); b++)
            row[b] = (float)bins[b];
        for (int k = 0; k < SPM_MAX_SPIKES; k++)
            row[SPM_LEVEL_BINS(l) + k] = (float)lanes[k];
    }
}

int spm_mlc_tables_build(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                         int levels, spm_error *err)
{
    (void)err;
    int n = sc->ncolours;
    spm_spectrum *smooth = spm_xcalloc((size_t)n + 1, sizeof *smooth);
    spm_spike *spikes = spm_xcalloc((size_t)n * SPM_MAX_SPIKES + 1, sizeof *spikes);
    spm_spike_light *lights = spm_xcalloc((size_t)n + 1, sizeof *lights);
    int *light_of = spm_xcalloc((size_t)n + 1, sizeof *light_of);
    int nlights = 0;
    for (int c = 0; c < n; c++) {
        const spm_spectrum *in = &sc->colours[c].s;
        smooth[c] = *in;
        light_of[c] = -1;
        if (in->kind != SPM_KIND_EMISSION)
            continue;
        int ns = 0;
        spm_spike_split(in, &smooth[c], &spikes[(size_t)c * SPM_MAX_SPIKES], SPM_MAX_SPIKES, &ns,
                        NULL);
        spm_spike_light *L = &lights[nlights];
        double xyz[3];
        spm_xyz_emission(in, xyz);
        L->in = in;
        L->smooth = &smooth[c];
        L->spikes = &spikes[(size_t)c * SPM_MAX_SPIKES];
        L->nspikes = ns;
        L->luminance = xyz[1];
        light_of[c] = nlights++;
    }
    double lane_wl[SPM_MAX_SPIKES] = {0};
    t->nspikes = nlights ? spm_spike_pattern_merge(lights, nlights, MERGE_NM, SPM_MAX_SPIKES, lane_wl)
                         : 0;
    lane_profile *prof = spm_xcalloc(1, sizeof *prof);
    lane_profiles(lights, nlights, prof);
    /* truth's weights are per 1 nm bin, so their mean is a weight per nm, as an
     * area (value x nm) needs */
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int k = 0; k < SPM_MAX_SPIKES; k++) {
        t->spike_wl[k] = k < t->nspikes ? (float)lane_wl[k] : 0.0f;
        for (int i = 0; i < 3; i++)
            t->spike_cmf[i][k] = k < t->nspikes ? (float)lane_mean(prof, k, lane_wl[k], w[i]) : 0.0f;
    }
    double *lanes = spm_xcalloc((size_t)n * SPM_MAX_SPIKES + 1, sizeof *lanes);
    spm_mlc_colour *cols = spm_xcalloc((size_t)n + 1, sizeof *cols);
    unsigned char *ingr = spm_xcalloc((size_t)n + 1, 1);
    spm_fluor_ingredients(sc, ingr);
    for (int c = 0; c < n; c++) {
        double *lane = &lanes[(size_t)c * SPM_MAX_SPIKES];
        const spm_spectrum *in = &sc->colours[c].s;
        if (light_of[c] >= 0)
            memcpy(lane, lights[light_of[c]].lane_area, SPM_MAX_SPIKES * sizeof *lane);
        else
            for (int k = 0; k < t->nspikes; k++)
                lane[k] = lane_mean(prof, k, lane_wl[k], in->nm1);
        fill_row(&smooth[c], lane, c, t);
        cols[c] = (spm_mlc_colour){in, &smooth[c], lane, ingr[c]};
    }
    double lane_cmf[3][SPM_MAX_SPIKES];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < SPM_MAX_SPIKES; k++)
            lane_cmf[i][k] = t->spike_cmf[i][k];
    int(*cond)[2] = spm_xcalloc((size_t)sc->nmaterials + 1, sizeof *cond), ncond = 0;
    int *diel = spm_xcalloc((size_t)sc->nmaterials + 1, sizeof *diel), ndiel = 0;
    double *diel_len = spm_xcalloc((size_t)sc->nmaterials + 1, sizeof *diel_len);
    for (int m = 0; m < sc->nmaterials; m++) {
        const spm_scene_material *mt = &sc->materials[m];
        if (mt->type == SPM_MAT_CONDUCTOR && mt->refl >= 0 && mt->col2 >= 0)
            cond[ncond][0] = mt->refl, cond[ncond++][1] = mt->col2;
        if (mt->type == SPM_MAT_DIELECTRIC && mt->col2 >= 0) /* col2: sigma */
            diel_len[ndiel] = mt->p[SPM_DIEL_P_LEN], diel[ndiel++] = mt->col2;
    }
    if (levels) {
        spm_mlc_pretest_run(cols, n, t->nspikes, lane_cmf, (const int(*)[2])cond, ncond, diel,
                            diel_len, ndiel, po, t->mlc_pretest);
        for (int c = 0; c < n; c++)
            for (int k = 0; k < SPM_PRETEST_KMAX; k++)
                t->mlc_lvlk[(size_t)c * SPM_PRETEST_KMAX + k] =
                    (uint8_t)t->mlc_pretest[c].level_k[k];
    }
    free(cond);
    free(diel);
    free(diel_len);
    free(cols);
    free(ingr);
    free(lanes);
    free(prof);
    free(light_of);
    free(lights);
    free(spikes);
    free(smooth);
    return 0;
}
