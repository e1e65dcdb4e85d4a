/* The pretest of a dielectric's absorption (tables.h spm_dielectric_pretest). */
#include "tables.h"
#include <math.h>
#include <stdlib.h>
#include "util.h"

/* The lengths the transmittance is judged at, as fractions of the longest
 * straight segment inside (dmax). exp(-sigma d) is linear in sigma for small
 * sigma d, where a bin's mean of sigma renders it exactly, and the error
 * grows with d as the exponential bends (then shrinks again once every lane
 * is dark); a factor of 2 apart from dmax / 32 to dmax holds its largest
 * value. Paths that cross the glass several times multiply their segments'
 * transmittances: the pretest's occurrence counts (context B: f^k) judge
 * those, as the level feeler counts the glass's vertices. */
const double spm_dielectric_fractions[SPM_DIELECTRIC_NLEN] = {1.0 / 32, 1.0 / 16, 1.0 / 8,
                                                             1.0 / 4,  1.0 / 2,  1.0};

static void merge(spm_pretest_result *out, const spm_pretest_result *r, int first)
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

void spm_dielectric_pretest(const spm_spectrum *const *set, int n, const spm_spectrum *sigma,
                            double dmax, int self, const spm_pretest_opts *o,
                            spm_pretest_result *out)
{
    double(*sl)[SPM_TRUTH_BINS] = spm_xcalloc(SPM_NUM_LEVELS, sizeof *sl);
    double(*fl)[SPM_TRUTH_BINS] = spm_xcalloc(SPM_NUM_LEVELS, sizeof *fl);
    double f0[SPM_TRUTH_BINS];
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        spm_spectrum_level(sigma, l, sl[l]);
    for (int a = 0; a < SPM_DIELECTRIC_NLEN; a++) {
        double d = spm_dielectric_fractions[a] * dmax;
        /* truth: exp(-sigma d) of the 1 nm sigma; level l: of the level's bin
         * means (what the shade stage computes), held at 1 nm */
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            f0[b] = exp(-sl[0][b] * d);
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
            for (int b = 0; b < SPM_TRUTH_BINS; b++)
                fl[l][b] = exp(-sl[l][b / w] * d);
        }
        spm_pretest_result r;
        spm_pretest_given(set, n, f0, (const double (*)[SPM_TRUTH_BINS])fl, self, o, &r);
        merge(out, &r, a == 0);
    }
    free(sl);
    free(fl);
}
