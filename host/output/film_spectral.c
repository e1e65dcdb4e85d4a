/* The spectral film and its host memory (film_spectral.h). */
#include "film_spectral.h"
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/* The render loop's bound on pass images waiting for the film (render_run.c). */
#define WAITING_BYTES ((size_t)256 << 20)

int spm_film_spectral_init(spm_film *f, int nspec, spm_error *err)
{
    size_t n = (size_t)f->width * (size_t)f->height * (size_t)nspec;
    free(f->spec);
    f->spec = calloc(n ? n : 1, sizeof *f->spec);
    if (!f->spec) {
        spm_errorf(err, "no memory for a %dx%d spectral film of %d bins (%.1f GB)", f->width,
                   f->height, nspec, (double)n * sizeof(double) / 1e9);
        f->nspec = 0;
        return 1;
    }
    f->nspec = nspec;
    return 0;
}

void spm_film_resolve_spectrum(const spm_film *f, float *out)
{
    size_t n = (size_t)f->width * f->height * (size_t)f->nspec;
    double inv = f->samples > 0 ? 1.0 / (double)f->samples : 0.0;
    for (size_t i = 0; i < n; i++)
        out[i] = (float)(f->spec[i] * inv);
}

size_t spm_film_spectral_bytes(size_t npix, int nspec, size_t window)
{
    size_t bins = npix * (size_t)nspec;
    return bins * sizeof(double)                                  /* film sums */
           + window * npix * (3 + (size_t)nspec) * sizeof(float) /* pass images */
           + 2 * (bins + 3 * npix) * sizeof(float);              /* resolved copy, written */
}

size_t spm_host_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? (size_t)pages * (size_t)size : 0;
}

int spm_film_spectral_check(int width, int height, int nspec, int nbackends, spm_error *err)
{
    size_t npix = (size_t)width * (size_t)height;
    size_t img = npix * (3 + (size_t)nspec) * sizeof(float);
    /* passes waiting (at most the byte bound, but always two per device)
     * and one in flight per device */
    size_t waiting = WAITING_BYTES / img > (size_t)(2 * nbackends) ? WAITING_BYTES / img
                                                                   : (size_t)(2 * nbackends);
    size_t need = spm_film_spectral_bytes(npix, nspec, waiting + (size_t)nbackends);
    size_t have = spm_host_memory();
    if (have && need > have) {
        spm_errorf(err,
                   "a %dx%d spectral image of %d bins needs %.1f GB of host memory (the film in "
                   "double, pass images, the written copy); this machine has %.1f GB: render "
                   "a smaller image%s",
                   width, height, nspec, (double)need / 1e9, (double)have / 1e9,
                   nspec > 80 ? " or use 5 nm bins (--spectral-nm 5)" : "");
        return 1;
    }
    return 0;
}
