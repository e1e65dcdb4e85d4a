/* The film: double sums of pass images, divided by the sample count on demand. */
#include "film.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Same bound as image reading: 2^28 pixels, 6 GiB of sums. */
#define SPM_FILM_MAX_PIXELS (1LL << 28)

int spm_film_init(spm_film *f, int width, int height, spm_error *err)
{
    f->sum = NULL;
    if (width <= 0 || height <= 0 || (long long)width * height > SPM_FILM_MAX_PIXELS) {
        spm_errorf(err, "image size %dx%d is not supported (1 to %lld pixels)", width, height,
                   SPM_FILM_MAX_PIXELS);
        return 1;
    }
    f->width = width;
    f->height = height;
    f->sum = spm_xcalloc((size_t)width * height * 3, sizeof(double));
    f->samples = 0;
    f->nonfinite = 0;
    f->nspec = 0;
    f->spec = NULL;
    return 0;
}

void spm_film_free(spm_film *f)
{
    free(f->sum);
    f->sum = NULL;
    free(f->spec);
    f->spec = NULL;
}

void spm_film_copy(spm_film *to, const spm_film *from)
{
    size_t npix = (size_t)from->width * from->height;
    *to = *from;
    to->sum = spm_xmalloc(npix * 3 * sizeof *to->sum);
    memcpy(to->sum, from->sum, npix * 3 * sizeof *to->sum);
    to->spec = NULL;
    if (from->spec) {
        to->spec = spm_xmalloc(npix * (size_t)from->nspec * sizeof *to->spec);
        memcpy(to->spec, from->spec, npix * (size_t)from->nspec * sizeof *to->spec);
    }
}

void spm_film_add_pass(spm_film *f, const float *pass_xyz, int spp_in_pass)
{
    if (spp_in_pass <= 0)
        return;
    size_t npix = (size_t)f->width * f->height, ch = 3 + (size_t)f->nspec;
    for (size_t i = 0; i < npix; i++) {
        const float *p = pass_xyz + ch * i;
        int bad = !isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]);
        for (int b = 0; b < f->nspec && !bad; b++)
            bad = !isfinite(p[3 + b]);
        if (bad) {
            f->nonfinite++;
            continue;
        }
        for (int c = 0; c < 3; c++)
            f->sum[3 * i + c] += p[c];
        for (int b = 0; b < f->nspec; b++)
            f->spec[(size_t)f->nspec * i + (size_t)b] += p[3 + b];
    }
    f->samples += spp_in_pass;
}

void spm_film_resolve(const spm_film *f, float *xyz)
{
    size_t n = (size_t)f->width * f->height * 3;
    double inv = f->samples > 0 ? 1.0 / (double)f->samples : 0.0;
    for (size_t i = 0; i < n; i++)
        xyz[i] = (float)(f->sum[i] * inv);
}
