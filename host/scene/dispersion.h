/* Dispersive glass: an index of refraction that depends on the wavelength,
 * n(lambda), as the dielectric type's 'ior SPEC', 'sellmeier', 'cauchy' or
 * 'glass NAME' give it (docs/SCENE_FORMAT.md), held as the index at the
 * centre of each 1 nm bin (the scene's index table, spm_scene disp). */
#ifndef SPM_DISPERSION_H
#define SPM_DISPERSION_H
#include <stddef.h>
#include "spm_shared.h"

/* Sellmeier: n^2 = 1 + sum_i B_i l^2 / (l^2 - C_i), l in micrometres, C in
 * micrometres^2. NaN where n^2 <= 0 or at a pole. */
double spm_disp_sellmeier(const double b[3], const double c[3], double lambda_nm);
/* Cauchy: n = A + B / l^2, l in micrometres, B in micrometres^2. */
double spm_disp_cauchy(double a, double b, double lambda_nm);

/* A catalogue glass: its Sellmeier coefficients (B1 B2 B3 C1 C2 C3). */
typedef struct {
    const char *name;
    double b[3], c[3];
} spm_glass;
/* The glass named (case-sensitive, as the catalogue spells it), or NULL. */
const spm_glass *spm_glass_find(const char *name);
/* "N-BK7, N-SF11" (the catalogue's names) into buf; returns buf. */
const char *spm_glass_list(char *buf, size_t size);

/* n at the centre of 1 nm bin b (380.5 + b nm), b < SPM_TRUTH_BINS. */
static inline double spm_disp_bin_nm(int b)
{
    return (double)SPM_LAMBDA_MIN + (double)b + 0.5;
}
#endif
