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
