/* The diffuse fluorescent surface (material type SPM_MAT_FLUOR) at 1 nm:
 * Wilkie, Weidlich, Larboulette and Purgathofer, "A reflectance model for
 * diffuse fluorescent surfaces" (GRAPHITE 2006), written as a re-radiation
 * matrix M[o][i] (rows: output wavelength, columns: input) over the 1 nm bins
 * (docs/METHODS.md "Fluorescence"). */
#ifndef SPM_FLUOR_H
#define SPM_FLUOR_H
#include "scene.h"

/* p[] slot of the energy yield */
#define SPM_FLUOR_P_YIELD 0

/* The fluorescent (off-diagonal) part of material m's matrix at 1 nm, into
 * F[o * SPM_TRUTH_BINS + i] (400 x 400 doubles):
 *   F[o][i] = YIELD A(i) e(o) / Z(i) for o > i, Z(i) = sum over o > i of e(o),
 * 0 elsewhere and in every column with Z(i) = 0 (nothing of the emission lies
 * above bin i: no fluorescent part). A is the absorption (col2), e the
 * emission shape (col3), both as 1 nm bin means. Each column sums to
 * YIELD A(i): the light absorbed at bin i re-emitted at longer wavelengths.
 * The diagonal, the light not absorbed, is the colour spm_fluor_diagonal
 * gives: D(i) = SPEC(i) (1 - A(i)). */
void spm_fluor_matrix_1nm(const spm_scene *sc, const spm_scene_material *m, double *F);
/* D = SPEC (1 - A) of material m, a reflectance. */
void spm_fluor_diagonal(const spm_scene *sc, const spm_scene_material *m, spm_spectrum *out);
/* The mean over the 1 nm input bins of the matrix's column sums, D(i) +
 * YIELD A(i) (where Z(i) > 0): the surface's albedo to light of equal energy,
 * Russian roulette's survival probability. */
double spm_fluor_albedo(const spm_scene *sc, const spm_scene_material *m);
#endif
