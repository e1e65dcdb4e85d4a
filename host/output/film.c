/* The film: double sums of pass images, divided by the sample count on demand. */
#include "film.h"
#include <math.h>
#include <stdlib.h>

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
    return 0;
}

void spm_film_free(spm_film *f)
{
    free(f->sum);
    f->sum = NULL;
}

void spm_film_add_pass(spm_film *f, const float *pass_xyz, int spp_in_pass)
{
    if (spp_in_pass <= 0)
        return;
    size_t npix = (size_t)f->width * f->height;
    for (size_t i = 0; i < npix; i++) {
        const float *p = pass_xyz + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            f->nonfinite++;
            continue;
        }
        for (int c = 0; c < 3; c++)
            f->sum[3 * i + c] += p[c];
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
