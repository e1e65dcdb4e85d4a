/* The spectral film: per-pixel spectral radiance in bins, summed beside the
 * XYZ film (film.h), and the host memory a spectral render takes. */
#ifndef SPM_FILM_SPECTRAL_H
#define SPM_FILM_SPECTRAL_H
#include <stddef.h>
#include "film.h"

/* Gives an initialised film nspec bins a pixel (zeroed). 0, or 1 with err
 * filled when they cannot be allocated. */
int spm_film_spectral_init(spm_film *f, int nspec, spm_error *err);
/* The bins so far: sum / samples into out[nspec * w * h] (pixel-major, zeros
 * before any pass). */
void spm_film_resolve_spectrum(const spm_film *f, float *out);

/* Host bytes a render of npix pixels with nspec spectral bins needs beyond
 * an XYZ-only one: the film's double sums, the pass images that may wait
 * for the film (window passes), and the float copy written out. */
size_t spm_film_spectral_bytes(size_t npix, int nspec, size_t window);
/* The machine's physical memory in bytes (0 if unknown). */
size_t spm_host_memory(void);
/* 0 if a spectral render of width x height pixels and nspec bins fits this
 * machine's memory, else fills err (how much it needs, how much there is,
 * what to do). */
int spm_film_spectral_check(int width, int height, int nspec, int nbackends, spm_error *err);
#endif
