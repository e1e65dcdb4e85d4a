/* Pretests: the coarsest spectral level each spectrum may use under a
 * colour-difference threshold (docs/METHODS.md "Choosing levels"). */
#ifndef SPM_PRETEST_H
#define SPM_PRETEST_H
#include "spectrum.h"
#include <stdint.h>

typedef enum { SPM_METRIC_DE00 = 0, SPM_METRIC_DEAB = 1 } spm_metric;

typedef struct {
    spm_metric metric;     /* default SPM_METRIC_DE00 */
    double threshold;      /* default 2.0 */
    unsigned seed;         /* context C sequences; default 1 */
    int nsequences;        /* context C: random sequences per spectrum; default 64 */
    int coarsest_level;    /* coarsest level allowed (SPM_DEFAULT_COARSEST, 20 bins, by default;
                            * 4 enables the 10-bin level) */
} spm_pretest_opts;

typedef struct {
    int level;  /* coarsest admissible level over all contexts (A, B for k = 1..KMAX, C) */
    /* level_k[k-1]: coarsest admissible level for contexts A, C and B with at most k
     * occurrences (non-increasing in k); the level feeler uses it per occurrence count. */
    int level_k[SPM_PRETEST_KMAX];
    double err[SPM_NUM_LEVELS];                     /* worst error per level, all contexts */
    double err_k[SPM_PRETEST_KMAX][SPM_NUM_LEVELS]; /* context B, per k */
} spm_pretest_result;

void spm_pretest_defaults(spm_pretest_opts *o);

/* What the general pretest and the Composite Model's (mlc_pretest.h) share.
 * Context C's sequences: a colour's generator state from the seed, then 1 to
 * SPM_PRETEST_SEQ_OTHERS other reflectances drawn with spm_pretest_pick
 * (an index below n). */
#define SPM_PRETEST_SEQ_OTHERS 4
uint64_t spm_pretest_seq_state(const spm_pretest_opts *o, int self);
int spm_pretest_pick(uint64_t *state, int n);
/* The level pick and the error fold both pretests end with: level_k[k-1],
 * the coarsest level up to `coarsest` that no context fails (fail_ac: A and
 * C; fail_k[j]: B with j + 1 occurrences, for every j < k), level 0 when none
 * passes; err[l], the worst of err_ac[l] and every err_k[j][l] (res->err_k
 * filled before). */
void spm_pretest_fold(const unsigned char fail_ac[SPM_NUM_LEVELS],
                      const unsigned char fail_k[SPM_PRETEST_KMAX][SPM_NUM_LEVELS],
                      const double err_ac[SPM_NUM_LEVELS], int coarsest,
                      spm_pretest_result *res);
/* The colour difference of a test product from its reference, given their
 * XYZ: both scaled by the factor taking the reference to Y = 50, against a D65
 * white of Y = 100, so a luminance error counts. A reference without
 * luminance cannot be seen (0); a test without it is as far as black from
 * white (100). */
double spm_pretest_xyz_error(const double ref[3], const double test[3], spm_metric metric);
/* spectra[0..n-1]: the set (reflectances and emissions); lights are the set's
 * emissions (if it has none, an equal-energy light stands in). Deterministic
 * for a given seed. results[i] belongs to spectra[i]. Returns the number of
 * spectra done: n, or fewer when an interruption (spm_stop_requested) ended
 * the run early, the results not reached left as they were. */
int spm_pretest_run(const spm_spectrum *const *spectra, int n, const spm_pretest_opts *o,
                    spm_pretest_result *results);
/* The same, but a spectrum i with skip[i] set is judged without being a factor
 * of any product that judges the others (skip NULL: none): a fluorescent dye's
 * absorption and emission shapes, which no path multiplies element-wise. */
int spm_pretest_run_skip(const spm_spectrum *const *spectra, int n, const unsigned char *skip,
                         const spm_pretest_opts *o, spm_pretest_result *results);
/* A reflectance the renderer computes at each level rather than averaging
 * its 1 nm data (a conductor's Fresnel from each level's eta and k): f0 its
 * 1 nm values, fl[l] what level l renders, held at 1 nm (fl[0] unused),
 * judged in contexts A, B and C against the set spectra[0..n-1] as
 * spm_pretest_run judges a reflectance; self seeds its context-C sequences
 * (a number no spectrum of the set has: none of them is "itself"). */
void spm_pretest_given(const spm_spectrum *const *spectra, int n, const double *f0,
                       const double (*fl)[SPM_TRUTH_BINS], int self, const spm_pretest_opts *o,
                       spm_pretest_result *res);
/* Print the decision table (one row per spectrum and level) to f. */
#include <stdio.h>
void spm_pretest_print(FILE *f, const char *const *names, const spm_pretest_result *r, int n,
                       const spm_pretest_opts *o);
#endif
