/* Image comparison: blur, common white, per-pixel Delta E and statistics. */
#include "compare.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "percentile.h"

/* One 1-D pass over `count` lines of `len` RGB pixels each, `stride` floats apart
 * along the line: mean over the window part inside [0, len). */
static void blur_lines(float *px, int len, int count, size_t line_step, size_t stride, int r,
                       double *prefix)
{
    for (int l = 0; l < count; l++) {
        float *line = px + (size_t)l * line_step;
        for (int c = 0; c < 3; c++) {
            prefix[0] = 0.0;
            for (int i = 0; i < len; i++)
                prefix[i + 1] = prefix[i] + line[(size_t)i * stride + c];
            for (int i = 0; i < len; i++) {
                int lo = i - r < 0 ? 0 : i - r, hi = i + r + 1 > len ? len : i + r + 1;
                line[(size_t)i * stride + c] = (float)((prefix[hi] - prefix[lo]) / (hi - lo));
            }
        }
    }
}

void spm_box_blur(spm_image *img, int n)
{
    if (n <= 1)
        return;
    int w = img->width, h = img->height, r = n / 2;
    double *prefix = spm_xmalloc(((size_t)(w > h ? w : h) + 1) * sizeof *prefix);
    /* Separable: the inside part of a window is a rectangle, so a mean over rows of
     * row means equals the mean over that rectangle. */
    blur_lines(img->rgb, w, h, (size_t)w * 3, 3, r, prefix);
    blur_lines(img->rgb, h, w, 3, (size_t)w * 3, r, prefix);
    free(prefix);
}

static long long zero_nonfinite(spm_image *img)
{
    long long bad = 0;
    size_t n = (size_t)img->width * img->height * 3;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(img->rgb[i])) {
            img->rgb[i] = 0.0f;
            bad++;
        }
    return bad;
}

static void to_xyz(const float *rgb, double xyz[3])
{
    double v[3] = {rgb[0], rgb[1], rgb[2]};
    spm_linear_srgb_to_xyz(v, xyz);
}

/* Statistics of v[0..n); sorts v. */
static void summarise(double *v, size_t n, spm_de_stats *s)
{
    memset(s, 0, sizeof *s);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        sum += v[i];
        int b = v[i] < SPM_COMPARE_BUCKETS - 1 ? (int)v[i] : SPM_COMPARE_BUCKETS - 1;
        s->buckets[b]++;
    }
    spm_sort_doubles(v, n);
    s->mean = n ? sum / (double)n : 0.0;
    s->median = spm_percentile_sorted(v, n, 50);
    s->p95 = spm_percentile_sorted(v, n, 95);
    s->p99 = spm_percentile_sorted(v, n, 99);
    s->max = n ? v[n - 1] : 0.0;
}

static double white_from(const spm_image *a)
{
    size_t n = (size_t)a->width * a->height;
    double *y = spm_xmalloc(n * sizeof *y);
    for (size_t i = 0; i < n; i++) {
        double xyz[3];
        to_xyz(a->rgb + 3 * i, xyz);
        y[i] = xyz[1];
    }
    spm_sort_doubles(y, n);
    double yn = spm_percentile_sorted(y, n, SPM_COMPARE_WHITE_PERCENTILE);
    free(y);
    return yn;
}

int spm_compare_images(spm_image *a, spm_image *b, const spm_compare_opts *opts,
                       spm_compare_result *res, spm_error *err)
{
    memset(res, 0, sizeof *res);
    if (a->width != b->width || a->height != b->height) {
        spm_errorf(err, "image sizes differ: %dx%d and %dx%d", a->width, a->height, b->width,
                   b->height);
        return 1;
    }
    if (opts->blur > 1 && opts->blur % 2 == 0) {
        spm_errorf(err, "blur window %d is even (use an odd size, or 0 for none)", opts->blur);
        return 1;
    }
    res->nonfinite = zero_nonfinite(a) + zero_nonfinite(b);
    spm_box_blur(a, opts->blur);
    spm_box_blur(b, opts->blur);
    double yn = opts->white_y > 0 ? opts->white_y : white_from(a);
    if (!(yn > 0) || !isfinite(yn)) {
        spm_errorf(err, "the reference image's 99.9th-percentile luminance is %g: no white to "
                        "compare against (give --white-y)", yn);
        return 1;
    }
    double white[3];
    spm_white_d65(white);
    for (int c = 0; c < 3; c++)
        white[c] *= yn;

    size_t n = (size_t)a->width * a->height;
    double *d00 = spm_xmalloc(n * sizeof *d00), *dab = spm_xmalloc(n * sizeof *dab);
    for (size_t i = 0; i < n; i++) {
        double xa[3], xb[3], la[3], lb[3];
        to_xyz(a->rgb + 3 * i, xa);
        to_xyz(b->rgb + 3 * i, xb);
        spm_xyz_to_lab(xa, white, la);
        spm_xyz_to_lab(xb, white, lb);
        d00[i] = spm_delta_e_2000(la, lb);
        dab[i] = spm_delta_e_ab(la, lb);
    }
    res->width = a->width;
    res->height = a->height;
    res->white_y = yn;
    res->de00_map = spm_xmalloc(n * sizeof *d00);
    memcpy(res->de00_map, d00, n * sizeof *d00);
    summarise(d00, n, &res->de00);
    summarise(dab, n, &res->deab);
    free(d00);
    free(dab);
    return 0;
}

void spm_compare_result_free(spm_compare_result *res)
{
    free(res->de00_map);
    res->de00_map = NULL;
}
