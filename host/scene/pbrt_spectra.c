/* Spectra as pbrt-v4 reads them (its SpectrumType): an rgb reflectance is a
 * bounded smooth spectrum (Jakob-Hanika, rgb2spec.c); an rgb eta or k is
 * unbounded: the fit of rgb / 2m times 2m, m the largest component; an rgb
 * illuminant is that shape times the colour space's white (D65), at the
 * rgb's luminance. A light's spectrum (blackbody, named, inline, a file) is
 * normalised by pbrt-v4 to luminance 1 and then scaled; specmip's emissions
 * are luminances (spm_sb_emission), so the two agree by construction. */
#include "pbrt.h"
#include "csv.h"
#include "dispersion.h"
#include "rgb2spec.h"
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_SAMPLES 100000

/* pbrt-v4's named spectra and where specmip's data has them: metals' eta and
 * k (spectra/metal_*), the CIE illuminants; glasses by the catalogue. */
static const struct {
    const char *pbrt, *file;
} named[] = {
    {"metal-Ag-eta", "metal_Ag_eta.csv"}, {"metal-Ag-k", "metal_Ag_k.csv"},
    {"metal-Al-eta", "metal_Al_eta.csv"}, {"metal-Al-k", "metal_Al_k.csv"},
    {"metal-Au-eta", "metal_Au_eta.csv"}, {"metal-Au-k", "metal_Au_k.csv"},
    {"metal-Cu-eta", "metal_Cu_eta.csv"}, {"metal-Cu-k", "metal_Cu_k.csv"},
    {"stdillum-A", "illuminant_A.csv"},   {"stdillum-D50", "illuminant_D50.csv"},
    {"stdillum-D65", "illuminant_D65.csv"}, {"stdillum-F1", "illuminant_F1.csv"},
    {"stdillum-F2", "illuminant_F2.csv"}, {"stdillum-F3", "illuminant_F3.csv"},
    {"stdillum-F4", "illuminant_F4.csv"}, {"stdillum-F5", "illuminant_F5.csv"},
    {"stdillum-F6", "illuminant_F6.csv"}, {"stdillum-F7", "illuminant_F7.csv"},
    {"stdillum-F8", "illuminant_F8.csv"}, {"stdillum-F9", "illuminant_F9.csv"},
    {"stdillum-F10", "illuminant_F10.csv"}, {"stdillum-F11", "illuminant_F11.csv"},
    {"stdillum-F12", "illuminant_F12.csv"},
};
#define NNAMED ((int)(sizeof named / sizeof named[0]))

/* pbrt's glass-F11 is Schott's SF11, whose successor N-SF11 has the same
 * n_d (1.78472) within 1e-5; glass-BK7 is N-BK7. */
static const struct {
    const char *pbrt, *catalogue;
} glasses[] = {{"glass-BK7", "N-BK7"}, {"glass-F11", "N-SF11"}};

static const char known[] =
    "metal-{Ag,Al,Au,Cu}-{eta,k}, glass-BK7, glass-F11, stdillum-{A,D50,D65,F1..F12}";

const char *pbrt_glass_catalogue_name(const char *pbrt_name)
{
    for (size_t i = 0; i < sizeof glasses / sizeof glasses[0]; i++)
        if (!strcmp(glasses[i].pbrt, pbrt_name))
            return glasses[i].catalogue;
    return NULL;
}

int pbrt_named_spectrum(const char *name, spm_kind kind, spm_spectrum *out, const char **list,
                        spm_error *err)
{
    *list = known;
    const char *cat = pbrt_glass_catalogue_name(name);
    if (cat) {
        const spm_glass *g = spm_glass_find(cat);
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            out->nm1[b] = spm_disp_sellmeier(g->b, g->c, spm_disp_bin_nm(b));
        out->kind = kind;
        return 0;
    }
    for (int i = 0; i < NNAMED; i++)
        if (!strcmp(named[i].pbrt, name)) {
            char rel[128], path[SPM_PATH_MAX];
            snprintf(rel, sizeof rel, "spectra/%s", named[i].file);
            return spm_spectrum_load(spm_data_path(rel, path, sizeof path), NULL, kind, out, err);
        }
    return 1;
}

/* A spectrum file (pbrt-v4: "lambda value" pairs, '#' comments), by the path rule. */
static int spectrum_file(pbrt_spectra *sp, const pbrt_param *pa, spm_kind kind, spm_spectrum *out)
{
    spm_file path;
    if (spm_path_check(sp->dir, pa->str[0], pa->where, &path, sp->err))
        return 1;
    FILE *f = spm_path_fopen(&path, "r");
    if (!f) {
        spm_errorf(sp->err, "%s: spectrum file '%s': cannot open: %s", pa->where, pa->str[0],
                   strerror(errno));
        return 1;
    }
    double *v = spm_xmalloc(2 * MAX_FILE_SAMPLES * sizeof *v);
    size_t n = 0;
    int c, rc = 0;
    while (!rc && (c = fgetc(f)) != EOF) {
        if (c == '#') {
            while ((c = fgetc(f)) != EOF && c != '\n')
                ;
        } else if (!strchr(" \t\r\n,", c)) {
            ungetc(c, f);
            rc = n == 2 * MAX_FILE_SAMPLES || fscanf(f, "%lf", &v[n++]) != 1;
        }
    }
    fclose(f);
    if (rc || n % 2 || n < 2) {
        spm_errorf(sp->err, "%s: spectrum file '%s': %s", pa->where, pa->str[0],
                   rc ? "not a list of numbers (wavelength value pairs)"
                      : "an odd count of numbers or none (wavelength value pairs)");
        free(v);
        return 1;
    }
    double *wl = spm_xmalloc(n / 2 * sizeof *wl), *val = spm_xmalloc(n / 2 * sizeof *val);
    for (size_t i = 0; i < n / 2; i++) {
        wl[i] = v[2 * i];
        val[i] = v[2 * i + 1];
    }
    char what[700];
    snprintf(what, sizeof what, "%s: spectrum file '%s'", pa->where, pa->str[0]);
    rc = spm_spectrum_from_samples(wl, val, n / 2, kind, what, out, sp->err);
    free(v);
    free(wl);
    free(val);
    return rc;
}

/* An rgb lifted as `lift` (no scale). */
static int rgb_values(pbrt_spectra *sp, const pbrt_param *pa, pbrt_lift lift, spm_spectrum *out)
{
    const double *rgb = pa->num;
    double m = fmax(rgb[0], fmax(rgb[1], rgb[2]));
    spm_error inner;
    int rc = 0;
    if (!(rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0)) {
        spm_errorf(sp->err, "%s: '%s': a negative rgb component", pa->where, pa->name);
        return 1;
    }
    if (lift == PBRT_ALBEDO && m > 1.0) {
        spm_errorf(sp->err, "%s: '%s': rgb reflectance %g above 1", pa->where, pa->name, m);
        return 1;
    }
    if (m == 0.0) {
        spm_spectrum_constant(0.0, lift == PBRT_ILLUMINANT ? SPM_KIND_EMISSION : SPM_KIND_REFLECTANCE, out);
        return 0;
    }
    if (lift == PBRT_ILLUMINANT) {
        rc = spm_rgb_to_emission(rgb, out, NULL, &inner);
    } else if (lift == PBRT_ALBEDO) {
        rc = spm_rgb_to_reflectance(rgb, out, NULL, &inner);
    } else {
        double half[3] = {rgb[0] / (2 * m), rgb[1] / (2 * m), rgb[2] / (2 * m)};
        rc = spm_rgb_to_reflectance(half, out, NULL, &inner);
        spm_spectrum_scale(out, 2 * m);
    }
    if (rc)
        spm_errorf(sp->err, "%s: %s", pa->where, inner.msg);
    return rc;
}

int pbrt_spectrum_values(pbrt_spectra *sp, const pbrt_param *pa, pbrt_lift lift,
                         spm_spectrum *out)
{
    spm_kind kind = lift == PBRT_ILLUMINANT ? SPM_KIND_EMISSION : SPM_KIND_REFLECTANCE;
    if (pa->type == PP_RGB)
        return rgb_values(sp, pa, lift, out);
    if (pa->type == PP_BLACKBODY) {
        if (!(pa->num[0] > 0 && pa->num[0] < 1e6)) {
            spm_errorf(sp->err, "%s: blackbody temperature %g K", pa->where, pa->num[0]);
            return 1;
        }
        spm_spectrum_blackbody(pa->num[0], out);
        out->kind = kind;
        if (lift != PBRT_ILLUMINANT) /* pbrt-v4's blackbody peaks at 1 */
            spm_spectrum_scale(out, 1.0 / spm_spectrum_max(out));
        return 0;
    }
    if (pa->nstr) {
        const char *list;
        spm_error inner;
        int rc = pbrt_named_spectrum(pa->str[0], kind, out, &list, &inner);
        if (rc == 0)
            return 0;
        if (strncmp(pa->str[0], "metal-", 6) && strncmp(pa->str[0], "glass-", 6) &&
            strncmp(pa->str[0], "stdillum-", 9))
            return spectrum_file(sp, pa, kind, out);
        spm_errorf(sp->err, "%s: named spectrum '%s' is not one specmip has (%s)", pa->where,
                   pa->str[0], list);
        return 1;
    }
    size_t n = pa->nnum / 2;
    double *wl = spm_xmalloc(n * sizeof *wl), *val = spm_xmalloc(n * sizeof *val);
    for (size_t i = 0; i < n; i++) {
        wl[i] = pa->num[2 * i];
        val[i] = pa->num[2 * i + 1];
    }
    char what[700];
    snprintf(what, sizeof what, "%s: '%s'", pa->where, pa->name);
    int rc = spm_spectrum_from_samples(wl, val, n, kind, what, out, sp->err);
    free(wl);
    free(val);
    return rc;
}

int pbrt_spectrum_colour(pbrt_spectra *sp, const pbrt_param *pa, pbrt_lift lift, double scale)
{
    char name[SPM_NAME_MAX];
    if (pa->type == PP_RGB && lift != PBRT_UNBOUNDED) {
        double rgb[3] = {pa->num[0] * scale, pa->num[1] * scale, pa->num[2] * scale};
        spm_spectrum tmp;
        if (rgb_values(sp, pa, lift, &tmp)) /* the range checks, on the file's values */
            return -2;
        int c = spm_sb_rgb_colour(sp->b, &sp->rgb_fits, rgb,
                                  lift == PBRT_ILLUMINANT ? SPM_KIND_EMISSION
                                                          : SPM_KIND_REFLECTANCE,
                                  pa->where, sp->err);
        return c;
    }
    spm_spectrum s, out;
    if (pbrt_spectrum_values(sp, pa, lift, &s))
        return -2;
    int rc;
    if (lift == PBRT_ILLUMINANT)
        rc = spm_sb_emission(&s, scale, pa->where, &out, sp->err);
    else if (lift == PBRT_ALBEDO)
        rc = spm_sb_reflectance(&s, scale, pa->where, &out, sp->err);
    else
        rc = spm_sb_optical(&s, scale, &out);
    if (rc)
        return -2;
    if (pa->nstr)
        snprintf(name, sizeof name, "%.40s*%.6g", pa->str[0], scale);
    else
        snprintf(name, sizeof name, "%.30s %.20s*%.6g", pa->type_name, pa->name, scale);
    int c = spm_sb_colour(sp->b, name, &out, pa->where, sp->err);
    return c < 0 ? -2 : c;
}
