/* The film: per-pixel CIE XYZ accumulated in double over progressive passes. */
#ifndef SPM_FILM_H
#define SPM_FILM_H
#include "util.h"

typedef struct {
    int width, height;
    double *sum;          /* 3 per pixel (X, Y, Z), rows top to bottom */
    long long samples;    /* samples per pixel added so far */
    long long nonfinite;  /* pass values that were NaN/Inf, left out (see spm_film_add_pass) */
    /* Spectral film (film_spectral.h): nspec bins a pixel, summed in double
     * like XYZ; 0 and NULL without one. */
    int nspec;
    double *spec;
} spm_film;

/* 0, or fills err when the size is not positive or too large. */
int spm_film_init(spm_film *f, int width, int height, spm_error *err);
void spm_film_free(spm_film *f);
/* A copy of `from` (its sums, spectral ones too) into `to`, freed with spm_film_free. */
void spm_film_copy(spm_film *to, const spm_film *from);

/* Adds one pass: pass_xyz[3*(y*width+x) + c] holds the SUM over that pixel's
 * spp_in_pass samples (not their mean); with a spectral film a pixel is
 * 3 + nspec floats, XYZ then the bins. The caller adds passes in pass order, so
 * the double sums, and the image, do not depend on timing. A non-finite pixel value
 * is counted in f->nonfinite and that pixel's pass is left out (the renderer is
 * meant to exclude bad samples before; this keeps one from poisoning the image). */
void spm_film_add_pass(spm_film *f, const float *pass_xyz, int spp_in_pass);

/* The image so far: sum / samples per pixel into xyz[3*w*h] (zeros before any pass). */
void spm_film_resolve(const spm_film *f, float *xyz);
#endif
