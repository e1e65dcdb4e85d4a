/* The diffuse fluorescent surface (material type SPM_MAT_FLUOR) at 1 nm:
 * Wilkie, Weidlich, Larboulette and Purgathofer, "A reflectance model for
 * diffuse fluorescent surfaces" (GRAPHITE 2006), written as a re-radiation
 * matrix M[o][i] (rows: output wavelength, columns: input) over the 1 nm bins
 * (docs/METHODS.md "Fluorescence"). */
#ifndef SPM_FLUOR_H
#define SPM_FLUOR_H
#include "scene.h"

/* p[] slots: the energy yield; a measured matrix's index in the scene */
#define SPM_FLUOR_P_YIELD 0
#define SPM_FLUOR_P_MATRIX 1

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
/* A measured material (SPM_MAT_DONALDSON): its matrix is the scene's
 * rerad[p[SPM_FLUOR_P_MATRIX]] and its diagonal its refl colour. */

/* A Donaldson matrix file (docs/SCENE_FORMAT.md "Re-radiation matrices"):
 * rows excitation wavelengths, columns em<nm> emission wavelengths, the same
 * wavelengths both ways; the diagonal a reflectance (into *diag, resampled as
 * any spectrum), the rest the fluorescent part per nm of input, read at the
 * 1 nm bin centres (bilinear between the samples, 0 outside them and at
 * o <= i) into F (SPM_TRUTH_BINS^2 doubles). Errors name file and line:
 * a badly named column, a matrix that is not square, a negative entry, light
 * below its excitation (anti-Stokes), an excitation that puts out more than
 * it takes in. Returns 0 or fills err. */
int spm_fluor_load_donaldson(const char *path, spm_spectrum *diag, double *F, spm_error *err);
/* D = SPEC (1 - A) of material m, a reflectance. */
void spm_fluor_diagonal(const spm_scene *sc, const spm_scene_material *m, spm_spectrum *out);
/* The mean over the 1 nm input bins of the matrix's column sums, D(i) +
 * YIELD A(i) (where Z(i) > 0): the surface's albedo to light of equal energy,
 * Russian roulette's survival probability. */
double spm_fluor_albedo(const spm_scene *sc, const spm_scene_material *m);
#endif
