/* The Composite Model's pretest (mlc, docs/METHODS.md "Choosing levels"): a
 * colour's level from the error of its whole composite representation (smooth
 * part at the level plus the spike lanes) against its 1 nm truth. */
#ifndef SPM_MLC_PRETEST_H
#define SPM_MLC_PRETEST_H
#include "pretest.h"

/* One colour as mlc shades it. */
typedef struct {
    const spm_spectrum *full;    /* the colour as given: the truth it is measured against */
    const spm_spectrum *smooth;  /* the part sampled at each level (a reflectance: full) */
    const double *lane;          /* nlanes values: an emission's energy per lane (x nm), a
                                  * reflectance's value at each lane's wavelength */
    int no_factor;               /* judged, but no factor of the others' products (a
                                  * fluorescent dye's shapes: spm_fluor_ingredients) */
} spm_mlc_colour;

/* results[i] for cols[i], in the general pretest's terms (a conductor's eta
 * and k, conductors[j][0] and [1], are left out of the products and take
 * their pair's Fresnel's result; a dielectric's absorption sigma,
 * dielectrics[j], whose longest segment inside is diel_len[j], likewise
 * takes its transmittance's, mlc_pretest.c): err[l] and err_k[k-1][l]
 * (l = 0 included: the representation's own floor) are ΔE of products with
 * colour i in composite form at level l, the other factors in composite form at
 * level 0, against the same products of 1 nm truth spectra; contexts A, B
 * (k = 1..SPM_PRETEST_KMAX) and C and the level_k rule as the general pretest.
 * lane_cmf: the XYZ weights of the lanes (the CMFs at their wavelengths, per nm).
 * Returns the number of colours done (fewer when interrupted). */
int spm_mlc_pretest_run(const spm_mlc_colour *cols, int n, int nlanes,
                        const double lane_cmf[3][SPM_MAX_SPIKES], const int (*conductors)[2],
                        int nconductors, const int *dielectrics, const double *diel_len,
                        int ndielectrics, const spm_pretest_opts *o, spm_pretest_result *results);
#endif
