/* Tone mapping on Y (see tonemap.h for the operators and the choices made). */
#include "tonemap.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "percentile.h"

void spm_tonemap_default(spm_tonemap *tm)
{
    tm->op = SPM_TONE_LINEAR;
    tm->exposure = 0.0;
    tm->a = SPM_TONEMAP_THESIS_A;
    tm->adapt = 0;
}

int spm_tonemap_select(spm_tonemap *tm, const char *name, spm_error *err)
{
    if (!strcmp(name, "linear") || !strcmp(name, "auto"))
        tm->op = SPM_TONE_LINEAR;
    else if (!strcmp(name, "thesis"))
        tm->op = SPM_TONE_THESIS;
    else {
        spm_errorf(err, "unknown tone mapping '%s' (expected linear, auto or thesis)", name);
        return 1;
    }
    return 0;
}

int spm_tonemap_set_exposure(spm_tonemap *tm, const char *text, spm_error *err)
{
    if (!strcmp(text, "auto")) {
        tm->exposure = 0.0;
        return 0;
    }
    char *end;
    double e = strtod(text, &end);
    if (end == text || *end || !isfinite(e) || e <= 0) {
        spm_errorf(err, "exposure '%s' is not 'auto' or a positive number", text);
        return 1;
    }
    tm->exposure = e;
    return 0;
}

double spm_tonemap_exposure(const spm_tonemap *tm, const float *xyz, size_t npix)
{
    if (tm->exposure > 0)
        return tm->exposure;
    if (tm->op == SPM_TONE_THESIS)
        return 1.0;
    double *y = spm_xmalloc((npix ? npix : 1) * sizeof *y);
    size_t n = 0;
    for (size_t i = 0; i < npix; i++)
        if (isfinite(xyz[3 * i + 1]))
            y[n++] = xyz[3 * i + 1];
    spm_sort_doubles(y, n);
    double white = spm_percentile_sorted(y, n, SPM_TONEMAP_AUTO_PERCENTILE);
    free(y);
    /* A black (or all-negative) image keeps exposure 1 rather than dividing by 0. */
    return white > 0 && isfinite(white) ? 1.0 / white : 1.0;
}

void spm_tonemap_white_balance(const spm_tonemap *tm, float *xyz, size_t npix)
{
    if (!tm || !tm->adapt)
        return;
    for (size_t i = 0; i < npix; i++) {
        double v[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        for (int r = 0; r < 3; r++)
            xyz[3 * i + r] = (float)(tm->cat[r][0] * v[0] + tm->cat[r][1] * v[1] +
                                     tm->cat[r][2] * v[2]);
    }
}

void spm_tonemap_apply(const spm_tonemap *tm, const float *xyz, size_t npix, unsigned char *rgb8)
{
    double e = spm_tonemap_exposure(tm, xyz, npix);
    for (size_t i = 0; i < npix; i++) {
        double v[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, rgb[3];
        double s = e;
        if (tm->op == SPM_TONE_THESIS) {
            double l = e * v[1];
            s = l > -tm->a ? e / (tm->a + l) : 0.0;  /* guard the pole at L = -a */
        }
        for (int c = 0; c < 3; c++)
            v[c] = isfinite(v[c]) ? v[c] * s : 0.0;
        spm_xyz_to_linear_srgb(v, rgb);
        double m = 0.0;
        for (int c = 0; c < 3; c++) {
            rgb[c] = rgb[c] > 0 ? rgb[c] : 0.0;
            m = rgb[c] > m ? rgb[c] : m;
        }
        for (int c = 0; c < 3; c++)
            rgb8[3 * i + c] = (unsigned char)lround(255.0 * spm_srgb_encode(m > 1 ? rgb[c] / m : rgb[c]));
    }
}
