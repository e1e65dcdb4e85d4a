#include "bench_image.h"
#include <stdlib.h>
#include <string.h>
#include "colour.h"

void spm_bench_film_image(const spm_film *film, spm_image *out)
{
    size_t n = (size_t)film->width * (size_t)film->height;
    float *xyz = spm_xmalloc(3 * n * sizeof *xyz);
    spm_film_resolve(film, xyz);
    out->width = film->width;
    out->height = film->height;
    out->rgb = spm_xmalloc(3 * n * sizeof *out->rgb);
    for (size_t i = 0; i < n; i++) {
        double v[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, rgb[3];
        spm_xyz_to_linear_srgb(v, rgb);
        for (int c = 0; c < 3; c++)
            out->rgb[3 * i + c] = (float)rgb[c];
    }
    free(xyz);
}

static spm_image copy_image(const spm_image *a)
{
    size_t bytes = 3 * (size_t)a->width * (size_t)a->height * sizeof *a->rgb;
    spm_image c = {a->width, a->height, spm_xmalloc(bytes), a->encoded};
    memcpy(c.rgb, a->rgb, bytes);
    return c;
}

int spm_bench_delta_e(const spm_image *ref, const spm_image *img, int blur, spm_de_stats *out,
                      spm_error *err)
{
    spm_image a = copy_image(ref), b = copy_image(img);
    spm_compare_opts o = {blur, 0.0};
    spm_compare_result r;
    int rc = spm_compare_images(&a, &b, &o, &r, err);
    if (!rc) {
        *out = r.de00;
        spm_compare_result_free(&r);
    }
    spm_image_free(&a);
    spm_image_free(&b);
    return rc;
}
