/* RGB to spectrum: linear sRGB reflectances lifted to smooth bounded spectra by
 * Jakob & Hanika's sigmoid-of-a-quadratic model (2019), fitted per colour, and
 * RGB emissions as such a shape times D65 (so an RGB white light stays D65). */
#ifndef SPM_RGB2SPEC_H
#define SPM_RGB2SPEC_H
#include "colour.h" /* spm_d65 */
#include "spectrum.h"

/* The model: s(lambda) = S(c0 x^2 + c1 x + c2), x = (lambda - 380 nm) / 400 nm,
 * S(z) = 1/2 + z / (2 sqrt(1 + z^2)); values stay strictly inside (0, 1). */
void spm_rgb2spec_eval(const double coef[3], spm_spectrum *out);

/* Fits coef so that the spectrum under D65 matches linear sRGB `rgb` (clamped
 * to [0, 1]) in CIELAB. Returns the CIEDE2000 difference reached. */
double spm_rgb2spec_fit(const double rgb[3], double coef[3]);

/* The fit's objective through precomputed weights, for many colours (the
 * coefficient table, rgb2spec_table.h): w[k][i] = D65 times CMF k over truth
 * bin i, scaled so that white has Y = 100. */
void spm_rgb2spec_weights(double w[3][SPM_TRUTH_BINS]);
/* Fits coef (updated in place, the start) to linear sRGB rgb (clamped to
 * [0, 1]) by the same Levenberg-Marquardt as spm_rgb2spec_fit, the target
 * moving in `steps` steps from the colour `from` (the colour coef has). */
void spm_rgb2spec_refine(const double w[3][SPM_TRUTH_BINS], const double from[3],
                         const double rgb[3], int steps, double coef[3]);

/* CIEDE2000 between the model's spectrum for coef under D65 (through w) and
 * linear sRGB rgb (clamped to [0, 1]). */
double spm_rgb2spec_delta_e_w(const double w[3][SPM_TRUTH_BINS], const double coef[3],
                              const double rgb[3]);

/* A reflectance for linear sRGB `rgb` (clamped to [0, 1]): greys, black and
 * white are exact constants, other colours the fitted model. *de00 (may be
 * NULL) receives the colour difference reached. Returns 0 or fills err
 * (bundled data missing). */
int spm_rgb_to_reflectance(const double rgb[3], spm_spectrum *out, double *de00,
                           spm_error *err);
/* An emission for a non-negative RGB radiance with some component > 0: the
 * reflectance of rgb / max(rgb) times D65, scaled to the luminance of `rgb`
 * (Y of the linear sRGB triple). */
int spm_rgb_to_emission(const double rgb[3], spm_spectrum *out, double *de00, spm_error *err);

/* CIEDE2000 between reflectance r under D65 and linear sRGB rgb (D65 white). */
double spm_rgb2spec_delta_e(const spm_spectrum *r, const double rgb[3]);
#endif
