/* The pretest of a conductor's colours (tables.h spm_conductor_pretest). */
#include "tables.h"
#include <stdlib.h>
#include <string.h>
#include "util.h"
#include "materials.h"

/* The incidence cosines the conductor's Fresnel is judged at. Bin-averaging
 * eta and k before the (non-linear) Fresnel errs most from normal to middle
 * incidence, where F depends most on eta and k, and not at all at grazing,
 * where F -> 1 whatever they are; the error is smooth in the angle, so six
 * cosines from 1 to 0.05 hold its largest value. */
const double spm_conductor_cosines[SPM_CONDUCTOR_NCOS] = {1.0, 0.8, 0.6, 0.4, 0.2, 0.05};

void spm_conductor_pretest_merge(spm_pretest_result *out, const spm_pretest_result *r, int first)
{
    if (first) {
        *out = *r;
        return;
    }
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        out->err[l] = out->err[l] > r->err[l] ? out->err[l] : r->err[l];
        for (int k = 0; k < SPM_PRETEST_KMAX; k++)
            out->err_k[k][l] = out->err_k[k][l] > r->err_k[k][l] ? out->err_k[k][l] : r->err_k[k][l];
    }
    for (int k = 0; k < SPM_PRETEST_KMAX; k++)
        out->level_k[k] = out->level_k[k] < r->level_k[k] ? out->level_k[k] : r->level_k[k];
    out->level = out->level < r->level ? out->level : r->level;
}

void spm_conductor_pretest(const spm_spectrum *const *set, int n, const spm_spectrum *eta,
                           const spm_spectrum *k, int self, const spm_pretest_opts *o,
                           spm_pretest_result *out)
{
    double(*el)[SPM_TRUTH_BINS] = spm_xcalloc(SPM_NUM_LEVELS, sizeof *el);
    double(*kl)[SPM_TRUTH_BINS] = spm_xcalloc(SPM_NUM_LEVELS, sizeof *kl);
    double(*fl)[SPM_TRUTH_BINS] = spm_xcalloc(SPM_NUM_LEVELS, sizeof *fl);
    double f0[SPM_TRUTH_BINS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        spm_spectrum_level(eta, l, el[l]);
        spm_spectrum_level(k, l, kl[l]);
    }
    for (int a = 0; a < SPM_CONDUCTOR_NCOS; a++) {
        double c = spm_conductor_cosines[a];
        /* truth: F of the 1 nm eta, k; level l: F of the level's bin eta, k
         * (what the shade stage computes), held at 1 nm */
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            f0[b] = spm_conductor_fresnel(el[0][b], kl[0][b], c);
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
            for (int b = 0; b < SPM_TRUTH_BINS; b++)
                fl[l][b] = spm_conductor_fresnel(el[l][b / w], kl[l][b / w], c);
        }
        spm_pretest_result r;
        spm_pretest_given(set, n, f0, (const double (*)[SPM_TRUTH_BINS])fl, self, o, &r);
        spm_conductor_pretest_merge(out, &r, a == 0);
    }
    free(el);
    free(kl);
    free(fl);
}
