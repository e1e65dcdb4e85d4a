/* Spectral OpenEXR files (spectral_exr.h). */
#include "spectral_exr.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "colour.h"
#include "film_spectral.h"
#include "spectrum.h"

#define SPECTRAL_SUFFIX ".spectral.exr"

/* lm/W: the maximum luminous efficacy of the CIE photopic observer (K_m). */
#define KM 683.0

int spm_spectral_path(const char *path)
{
    size_t n = strlen(path), k = strlen(SPECTRAL_SUFFIX);
    return n > k && !strcasecmp(path + n - k, SPECTRAL_SUFFIX);
}

void spm_spectral_channel_name(int b, int nbins, char *buf, size_t size)
{
    /* centres are whole or half nanometres: tenths print them exactly */
    int tenths = SPM_LAMBDA_MIN * 10 + (SPM_LAMBDA_MAX - SPM_LAMBDA_MIN) * 10 * (2 * b + 1) /
                                           (2 * nbins);
    if (tenths % 10)
        snprintf(buf, size, "S0.%d,%dnm", tenths / 10, tenths % 10);
    else
        snprintf(buf, size, "S0.%dnm", tenths / 10);
}

int spm_spectral_exr_write(const char *path, const spm_film *film, const spm_image_attr *attrs,
                           int nattrs, spm_error *err)
{
    if (!film->nspec || !film->spec) {
        spm_errorf(err, "%s: this render has no spectrum to write", path);
        return 1;
    }
    size_t npix = (size_t)film->width * film->height;
    int nb = film->nspec, nch = 3 + nb;
    float *xyz = spm_xmalloc(npix * 3 * sizeof *xyz);
    float *spec = spm_xmalloc(npix * (size_t)nb * sizeof *spec);
    spm_film_resolve(film, xyz);
    spm_film_resolve_spectrum(film, spec);
    float *px = spm_xmalloc(npix * (size_t)nch * sizeof *px);
    double scale = 1.0 / (KM * spm_cmf_y_integral());
    for (size_t i = 0; i < npix; i++) {
        double v[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, rgb[3];
        spm_xyz_to_linear_srgb(v, rgb);
        float *o = &px[i * (size_t)nch];
        for (int c = 0; c < 3; c++)
            o[c] = (float)rgb[c];
        for (int b = 0; b < nb; b++)
            o[3 + b] = (float)(spec[i * (size_t)nb + (size_t)b] * scale);
    }
    free(xyz);
    free(spec);
    char **names = spm_xcalloc((size_t)nch, sizeof *names);
    names[0] = spm_xstrdup("R"), names[1] = spm_xstrdup("G"), names[2] = spm_xstrdup("B");
    for (int b = 0; b < nb; b++) {
        char buf[32];
        spm_spectral_channel_name(b, nb, buf, sizeof buf);
        names[3 + b] = spm_xstrdup(buf);
    }
    /* the layout's header, the preview's primaries, then the render's metadata */
    spm_image_attr *a = spm_xcalloc((size_t)nattrs + 4, sizeof *a);
    int n = 0;
    a[n++] = (spm_image_attr){"spectralLayoutVersion", SPM_ATTR_STRING, 0, 0.0f, "1.0"};
    a[n++] = (spm_image_attr){"emissiveUnits", SPM_ATTR_STRING, 0, 0.0f, "W.m^-2.sr^-1"};
    a[n++] = (spm_image_attr){"specmip:radiance", SPM_ATTR_STRING, 0, 0.0f,
                              "absolute: scene luminance taken as cd/m^2, Y = 683 * integral of "
                              "S0 * y-bar(CIE 1931 2 deg) over 380-780 nm; R, G, B linear sRGB "
                              "(D65) with Y in cd/m^2"};
    for (int k = 0; k < nattrs; k++)
        a[n++] = attrs[k];
    int rc = spm_image_write_channels(path, film->width, film->height, nch,
                                      (const char *const *)names, px, a, n, err);
    for (int c = 0; c < nch; c++)
        free(names[c]);
    free(names);
    free(a);
    free(px);
    return rc;
}
