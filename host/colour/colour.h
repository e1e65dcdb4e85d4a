/* Colour science: spectrum -> XYZ, CIELAB, sRGB, colour differences. */
#ifndef SPM_COLOUR_H
#define SPM_COLOUR_H
#include "spectrum.h"
#ifdef __cplusplus
extern "C" {
#endif

/* XYZ of an emission (Y = luminance per the weights in spectrum.h), or of a
 * reflectance under `illum` scaled so the perfect white under it has Y = 100.
 * Computed from the 1 nm truth bins. */
void spm_xyz_emission(const spm_spectrum *s, double xyz[3]);
void spm_xyz_reflectance(const spm_spectrum *r, const spm_spectrum *illum, double xyz[3]);
/* Same at a spectral level (bins as from spm_spectrum_level). */
void spm_xyz_bins(const double *bins, int level, double xyz[3]);

void spm_xyz_to_lab(const double xyz[3], const double white[3], double lab[3]);
void spm_lab_to_xyz(const double lab[3], const double white[3], double xyz[3]);
/* IEC 61966-2-1 matrices (D65). */
void spm_xyz_to_linear_srgb(const double xyz[3], double rgb[3]);
void spm_linear_srgb_to_xyz(const double rgb[3], double xyz[3]);
/* Bradford chromatic adaptation (Lam 1985; ICC.1 v4 Annex E): the matrix that
 * takes XYZ seen under the white `src` to XYZ that looks the same under `dst`,
 * M = B^-1 diag(B dst / B src) B. Whites are XYZ of any scale (only their
 * chromaticities count: each is normalised to Y = 1). */
void spm_cat_bradford(const double src[3], const double dst[3], double m[3][3]);
double spm_srgb_encode(double linear);  /* transfer function, input clamped to [0, 1] */
double spm_srgb_decode(double encoded);

double spm_delta_e_ab(const double lab1[3], const double lab2[3]);
double spm_delta_e_2000(const double lab1[3], const double lab2[3]);

/* CIE D65 (relative spectral power, spectra/illuminant_D65_1nm.csv), loaded
 * once; NULL with err filled if missing. */
const spm_spectrum *spm_d65(spm_error *err);
/* D65 white point XYZ with Y = 1 (from the 1 nm observer and spectra/illuminant_D65_1nm.csv). */
void spm_white_d65(double xyz[3]);
#ifdef __cplusplus
}
#endif
#endif
