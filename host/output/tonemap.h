/* Tone mapping of an XYZ image to 8-bit sRGB for display formats (PNG, PPM).
 * Operators work on luminance Y and scale X, Y, Z alike, so chromaticity is kept:
 *   linear  display Y = e * Y; exposure e automatic by default: the 99th percentile
 *           of Y maps to display white (1% of pixels, typically emitters, clip);
 *   thesis  the thesis' operator (its appendix A.1): scale = 1 / (a + L), L = e * Y,
 *           a = 5; e defaults to 1 here (the thesis had no exposure).
 * Then: linear sRGB, negative channels to 0, a pixel whose largest channel exceeds 1
 * divided by it (hue kept, not clipped per channel), sRGB transfer, rounded to 8 bits.
 * White balance (render --white) belongs to the same display transform: XYZ is
 * first adapted from the chosen white to the display's D65 (a Bradford matrix,
 * colour.h spm_cat_bradford), for every format but the spectral EXR. */
#ifndef SPM_TONEMAP_H
#define SPM_TONEMAP_H
#include <stddef.h>
#include "util.h"

#define SPM_TONEMAP_AUTO_PERCENTILE 99.0
#define SPM_TONEMAP_THESIS_A 5.0

typedef enum { SPM_TONE_LINEAR = 0, SPM_TONE_THESIS = 1 } spm_tone_op;

typedef struct {
    spm_tone_op op;
    double exposure;  /* > 0: given; 0: automatic (linear) or 1 (thesis) */
    double a;         /* thesis operator constant */
    int adapt;        /* 1: XYZ' = cat XYZ before anything else (white balance) */
    double cat[3][3];
} spm_tonemap;

void spm_tonemap_default(spm_tonemap *tm);  /* linear, automatic exposure */
/* Operator by name: "linear" (alias "auto") or "thesis". 0, or fills err listing the names. */
int spm_tonemap_select(spm_tonemap *tm, const char *name, spm_error *err);
/* Exposure from text: "auto" or a positive finite number. 0, or fills err. */
int spm_tonemap_set_exposure(spm_tonemap *tm, const char *text, spm_error *err);

/* The exposure that will be used for this image (resolves "automatic"). */
double spm_tonemap_exposure(const spm_tonemap *tm, const float *xyz, size_t npix);
/* The white balance applied in place to xyz[3*npix] (nothing without one). */
void spm_tonemap_white_balance(const spm_tonemap *tm, float *xyz, size_t npix);
/* xyz[3*npix] -> rgb8[3*npix] display-encoded sRGB (xyz already white-balanced). */
void spm_tonemap_apply(const spm_tonemap *tm, const float *xyz, size_t npix, unsigned char *rgb8);
#endif
