/* Spectra on the host: the 1 nm truth representation every level derives from,
 * area-preserving resampling, spectral levels and bin-integrated CIE weights. */
#ifndef SPM_SPECTRUM_H
#define SPM_SPECTRUM_H
#include <stddef.h>
#include "spm_shared.h"
#include "util.h"
#include "csv.h"
#ifdef __cplusplus
extern "C" {
#endif

typedef enum { SPM_KIND_REFLECTANCE = 0, SPM_KIND_EMISSION = 1 } spm_kind;

/* A spectrum as its 1 nm truth bins: nm1[i] is the mean over [380+i, 381+i] nm of
 * the input's piecewise-linear reconstruction. Level 0 bin b is the mean of truth
 * bins 5b..5b+4; a level-l bin is the mean of the two level-(l-1) bins it covers. */
typedef struct {
    spm_kind kind;
    double nm1[SPM_TRUTH_BINS];
} spm_spectrum;

/* Build from samples (wavelengths strictly increasing, any spacing). Coverage:
 * no sample inside [380, 780] -> error; partial coverage -> extended by the end
 * values (reflectance) or zero (emission) with a warning naming `what`.
 * Rejects NaN/Inf, negative values, reflectance > 1 is allowed here (scales are
 * checked by the scene). Returns 0 or fills err (message starts with `what`). */
int spm_spectrum_from_samples(const double *wl, const double *val, size_t n, spm_kind kind,
                              const char *what, spm_spectrum *out, spm_error *err);
void spm_spectrum_constant(double value, spm_kind kind, spm_spectrum *out);
/* Planck radiator at `kelvin`, relative units (an emission). */
void spm_spectrum_blackbody(double kelvin, spm_spectrum *out);
void spm_spectrum_scale(spm_spectrum *s, double f);
void spm_spectrum_multiply(spm_spectrum *s, const spm_spectrum *by);

/* Level l bins (SPM_LEVEL_BINS(l) values: level 0 the 1 nm bins) of s, as
 * bin means. */
void spm_spectrum_level(const spm_spectrum *s, int level, double *out);
/* Mean of the spectrum over 380-780 nm (= mean of any level). */
double spm_spectrum_mean(const spm_spectrum *s);
double spm_spectrum_max(const spm_spectrum *s);

/* Load one value column (by name; NULL = the only value column, an error if
 * there are several) as a spectrum of the given kind: checks wavelengths strictly
 * increasing, finite values, no negative values; errors as "path:LINE: ...". */
int spm_spectrum_load(const char *path, const char *column, spm_kind kind,
                      spm_spectrum *out, spm_error *err);

/* Column `col` of a loaded table as a spectrum, with the checks of
 * spm_spectrum_load; `path` names the file in error messages. */
int spm_spectrum_from_csv(const spm_csv *csv, int col, const char *path, spm_kind kind,
                          spm_spectrum *out, spm_error *err);

/* CIE 1931 2-degree weights. cmf_truth[c][i] = integral over truth bin i of the
 * piecewise-linear CMF c (x, y, z), divided by the integral of y-bar over
 * 380-780 nm, so that XYZ of an emission = sum of bin mean * weight, and an
 * equal-energy emission of value 1 has Y = 1. Level weights are sums of truth
 * weights. spm_cmf_point gives the CMF at a wavelength (linear interpolation
 * of the 1 nm table, same normalisation per nm). Loaded once from
 * <data>/spectra/cie1931_2deg_cmf_1nm.csv; returns 0 or fills err. */
int spm_cmf_init(spm_error *err);
const double (*spm_cmf_truth(void))[SPM_TRUTH_BINS];
void spm_cmf_level(int level, double out[3][SPM_TRUTH_BINS]);
void spm_cmf_point(double lambda_nm, double out[3]);
/* The integral of the CIE 1931 y-bar over 380-780 nm, in nm: the weights are
 * the CMFs divided by it, so a spectrum of 1 per nm has Y = 1. */
double spm_cmf_y_integral(void);

#ifdef __cplusplus
}
#endif
#endif
