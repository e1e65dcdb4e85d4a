/* Composite Model tables (mlc): every emission is split into a smooth part and
 * spikes; the scene's spikes share a pattern table of at most SPM_MAX_SPIKES
 * lanes. Per colour and level a row holds the smooth bins, then the lanes:
 * an emission's energy in each lane, a reflectance's value at each lane's
 * wavelength. The lane XYZ weights are the CMFs at those wavelengths, so a
 * spike is a delta of the given area and the shade arithmetic stays one fused
 * vector multiply-add. */
#include "mlc_tables.h"
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "spikes.h"

#define MERGE_NM 1.0  /* spikes of different lights closer than this share a lane */

/* Reflectance at a lane wavelength: the 1 nm bin holding it. */
static double value_at(const spm_spectrum *s, double wl)
{
    int i = (int)(wl - SPM_LAMBDA_MIN);
    i = i < 0 ? 0 : i >= SPM_TRUTH_BINS ? SPM_TRUTH_BINS - 1 : i;
    return s->nm1[i];
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
                         spm_error *err)
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
    for (int k = 0; k < SPM_MAX_SPIKES; k++) {
        double cmf[3] = {0, 0, 0};
        if (k < t->nspikes)
            spm_cmf_point(lane_wl[k], cmf);
        t->spike_wl[k] = k < t->nspikes ? (float)lane_wl[k] : 0.0f;
        for (int i = 0; i < 3; i++)
            t->spike_cmf[i][k] = (float)cmf[i];
    }
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        t->mlc_lvl[l] = spm_xcalloc((size_t)n * SPM_MLC_STRIDE(l) + 1, sizeof(float));
    /* the sharp part each smooth part's pretest keeps at full resolution */
    spm_spectrum *sharp = spm_xcalloc((size_t)n + 1, sizeof *sharp);
    const spm_spectrum **set = spm_xcalloc((size_t)n + 1, sizeof *set);
    const spm_spectrum **sharp_of = spm_xcalloc((size_t)n + 1, sizeof *sharp_of);
    for (int c = 0; c < n; c++) {
        double lanes[SPM_MAX_SPIKES] = {0};
        const spm_spectrum *in = &sc->colours[c].s;
        if (light_of[c] >= 0) {
            memcpy(lanes, lights[light_of[c]].lane_area, sizeof lanes);
            sharp[c] = *in;
            for (int i = 0; i < SPM_TRUTH_BINS; i++)
                sharp[c].nm1[i] -= smooth[c].nm1[i];
            sharp_of[c] = &sharp[c];
        } else {
            for (int k = 0; k < t->nspikes; k++)
                lanes[k] = value_at(in, lane_wl[k]);
        }
        fill_row(&smooth[c], lanes, c, t);
        set[c] = &smooth[c];
    }
    spm_pretest_result *res = spm_xcalloc((size_t)n + 1, sizeof *res);
    spm_pretest_run_sharp(set, sharp_of, n, po, res);
    t->mlc_lvlk = spm_xcalloc((size_t)n * SPM_PRETEST_KMAX + 1, 1);
    for (int c = 0; c < n; c++)
        for (int k = 0; k < SPM_PRETEST_KMAX; k++)
            t->mlc_lvlk[(size_t)c * SPM_PRETEST_KMAX + k] = (uint8_t)res[c].level_k[k];
    free(res);
    free(sharp_of);
    free(set);
    free(sharp);
    free(light_of);
    free(lights);
    free(spikes);
    free(smooth);
    return 0;
}
