/* Spectra as Mitsuba 3's spectral variants read them: a <spectrum> of one
 * value is a constant; "λ:v, λ:v, ..." pairs are piecewise linear and zero
 * outside their first and last wavelength (Mitsuba's irregular spectrum);
 * a file holds "λ v" lines. An <rgb> reflectance is the bounded smooth fit
 * (Mitsuba's srgb), an rgb radiance that shape times D65 at the rgb's
 * luminance (its srgb_d65), an rgb eta or k unbounded: the lifts are
 * pbrt-v4's code (pbrt_spectra.c), which match. A <blackbody> is Planck's
 * radiance in W m^-2 sr^-1 nm^-1, unnormalised, as Mitsuba's. Mitsuba's
 * film divides by the integral of y-bar, so a radiance of constant value 1
 * has luminance 1: specmip's emission scale (spm_sb_emission) is the same
 * number, and a spectrum's values carry over as they are. */
#include "mitsuba.h"
#include "colour.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PAIRS 4096

/* Mitsuba's named indices of refraction (its ior.h). */
static const struct {
    const char *name;
    double n;
} iors[] = {
    {"vacuum", 1.0},          {"helium", 1.000036},   {"hydrogen", 1.000132},
    {"air", 1.000277},        {"carbon dioxide", 1.00045}, {"water", 1.3330},
    {"acetone", 1.36},        {"ethanol", 1.361},     {"carbon tetrachloride", 1.461},
    {"glycerol", 1.4729},     {"benzene", 1.501},     {"silicone oil", 1.52045},
    {"bromine", 1.661},       {"water ice", 1.31},    {"fused quartz", 1.458},
    {"pyrex", 1.470},         {"acrylic glass", 1.49}, {"polypropylene", 1.49},
    {"bk7", 1.5046},          {"sodium chloride", 1.544}, {"amber", 1.55},
    {"pet", 1.5750},          {"diamond", 2.419},
};

int mi_ior(mi_node *pl, const char *name, double def, double *out, spm_error *err)
{
    int bad = 0;
    mi_node *k = mi_prop(pl, name, "float|string", &bad, err);
    *out = def;
    if (bad || !k)
        return bad;
    const char *v = mi_attr(k, "value");
    if (!strcmp(k->tag, "float")) {
        if (!v || mi_numbers(v, out, 1) != 1 || !(*out >= 1.0 && *out <= 4.0)) {
            spm_errorf(err, "%s: '%s' \"%s\": an index of refraction in 1..4", k->where, name,
                       v ? v : "");
            return 1;
        }
        return 0;
    }
    for (size_t i = 0; v && i < sizeof iors / sizeof iors[0]; i++)
        if (!strcmp(iors[i].name, v)) {
            *out = iors[i].n;
            return 0;
        }
    spm_errorf(err, "%s: '%s' \"%s\" is not one of Mitsuba's named media (air, water, bk7, "
                    "acrylic glass, polypropylene, diamond, ...)", k->where, name, v ? v : "");
    return 1;
}

/* Planck's law per nm at each 1 nm bin's centre: 2 h c^2 / λ^5 / (e^{hc/λkT} - 1). */
static void planck(double kelvin, spm_spectrum *out)
{
    const double h = 6.62607015e-34, c = 2.99792458e8, kb = 1.380649e-23;
    for (int b = 0; b < SPM_TRUTH_BINS; b++) {
        double l = (SPM_LAMBDA_MIN + b + 0.5) * 1e-9;
        out->nm1[b] = 1e-9 * 2 * h * c * c / (pow(l, 5) * expm1(h * c / (l * kb * kelvin)));
    }
    out->kind = SPM_KIND_EMISSION;
}

/* "λ:v, λ:v" or a single value, into pa (pbrt's parameter form). */
static int spectrum_value(const mi_node *k, const char *v, pbrt_param *pa, spm_error *err)
{
    if (!strchr(v, ':')) {
        pa->type = PP_FLOAT;
        if (mi_numbers(v, pa->num, 1) == 1 && pa->num[0] >= 0) {
            pa->nnum = 1;
            return 0;
        }
    } else {
        pa->nnum = 0;
        for (const char *s = v; *s && pa->nnum < 2 * MAX_PAIRS;) {
            char *end;
            pa->num[pa->nnum] = strtod(s, &end);
            if (end == s)
                break;
            s = end;
            while (*s == ' ')
                s++;
            if ((pa->nnum % 2 == 0) != (*s == ':'))
                break;
            s += *s == ':' || *s == ',';
            while (*s == ' ' || *s == ',' || *s == '\n' || *s == '\t' || *s == '\r')
                s++;
            pa->nnum++;
            if (!*s && pa->nnum % 2 == 0)
                return 0;
        }
    }
    spm_errorf(err, "%s: <spectrum> '%s' value \"%.80s\": one non-negative number or "
                    "\"wavelength:value, ...\" pairs", k->where, pa->name, v);
    return 1;
}

/* The property as pbrt's parameter: 0, or 2 on error; param_free frees it. */
static int as_param(mi_spectra *ms, mi_node *k, pbrt_param *pa, spm_error *err)
{
    const char *v = mi_attr(k, "value");
    snprintf(pa->name, sizeof pa->name, "%s", mi_attr(k, "name"));
    snprintf(pa->where, sizeof pa->where, "%s", k->where);
    snprintf(pa->type_name, sizeof pa->type_name, "%s", k->tag);
    pa->num = spm_xmalloc(2 * MAX_PAIRS * sizeof *pa->num);
    if (!strcmp(k->tag, "rgb")) {
        int n = v ? mi_numbers(v, pa->num, 3) : -1;
        if (n == 1)
            pa->num[1] = pa->num[2] = pa->num[0];
        pa->type = PP_RGB;
        pa->nnum = 3;
        if (n == 1 || n == 3)
            return 0;
        spm_errorf(err, "%s: <rgb> '%s': value \"%s\" is not one or three numbers", k->where,
                   pa->name, v ? v : "");
        return 2;
    }
    if (!strcmp(k->tag, "float")) {
        pa->type = PP_FLOAT;
        pa->nnum = 1;
        if (v && mi_numbers(v, pa->num, 1) == 1 && pa->num[0] >= 0)
            return 0;
        spm_errorf(err, "%s: '%s': \"%s\" is not a non-negative number", k->where, pa->name,
                   v ? v : "");
        return 2;
    }
    pa->type = PP_SPECTRUM;
    const char *file = mi_attr(k, "filename");
    if (file) { /* checked here, read by pbrt's reader by its absolute path */
        spm_file f;
        if (mi_file(ms->doc, k, file, &f, err))
            return 2;
        pa->str = spm_xmalloc(sizeof *pa->str);
        pa->str[0] = spm_xstrdup(f.path);
        pa->nstr = 1;
        return 0;
    }
    if (!v) {
        spm_errorf(err, "%s: <spectrum> '%s' needs 'value' or 'filename'", k->where, pa->name);
        return 2;
    }
    return spectrum_value(k, v, pa, err) ? 2 : 0;
}

static void param_free(pbrt_param *pa)
{
    free(pa->num);
    if (pa->nstr)
        free(pa->str[0]);
    free(pa->str);
}

static int blackbody(mi_node *k, mi_lift lift, spm_spectrum *out, spm_error *err)
{
    const char *t = mi_attr(k, "temperature");
    double kelvin = 0;
    char *end = NULL;
    if (t)
        kelvin = strtod(t, &end);
    if (!t || end == t || (*end && strcmp(end, "K")) || !(kelvin > 0 && kelvin < 1e6)) {
        spm_errorf(err, "%s: <blackbody> temperature \"%s\": kelvin, such as \"5000K\"",
                   k->where, t ? t : "");
        return 2;
    }
    if (lift != MI_RADIANCE) {
        spm_errorf(err, "%s: a <blackbody> is an emitter's radiance only", k->where);
        return 2;
    }
    planck(kelvin, out);
    return 0;
}

int mi_values(mi_spectra *ms, mi_node *pl, const char *name, mi_lift lift, spm_spectrum *out,
              spm_error *err)
{
    int bad = 0;
    mi_node *k = mi_prop(pl, name, "spectrum|rgb|float|blackbody", &bad, err);
    if (bad)
        return 2;
    if (!k)
        return 1;
    if (!strcmp(k->tag, "blackbody"))
        return blackbody(k, lift, out, err);
    pbrt_param pa = {0};
    int rc = as_param(ms, k, &pa, err);
    if (!rc && pa.type == PP_FLOAT) {
        spm_spectrum_constant(pa.num[0], SPM_KIND_REFLECTANCE, out);
    } else if (!rc) {
        /* an illuminant's kind makes the samples zero outside their range */
        pbrt_lift pl_lift = lift == MI_REFLECTANCE ? PBRT_ALBEDO
                            : lift == MI_UNBOUNDED ? PBRT_UNBOUNDED : PBRT_ILLUMINANT;
        ms->sp.err = err;
        rc = pbrt_spectrum_values(&ms->sp, &pa, pa.type == PP_RGB ? pl_lift : PBRT_ILLUMINANT,
                                  out) ? 2 : 0;
    }
    out->kind = lift == MI_RADIANCE ? SPM_KIND_EMISSION : SPM_KIND_REFLECTANCE;
    param_free(&pa);
    return rc;
}

/* A texture (a <texture> or a <ref> to one) as the property: warned, 1. */
static int textured(mi_node *pl, const char *name, int *bad, spm_error *err)
{
    mi_node *k = mi_prop(pl, name, "texture|ref", bad, err);
    if (!k || *bad) {
        *bad = 0;
        return 0;
    }
    char w[160];
    snprintf(w, sizeof w, "<%s type=\"%.30s\">: a texture as '%.40s'", pl->tag,
             mi_attr(pl, "type") ? mi_attr(pl, "type") : "", name);
    for (int i = 0; i < k->nkids; i++)
        k->kids[i]->used = 1;
    *bad = pbrt_warn(k->where, w, "textures are not rendered yet; the default is used", err);
    return 1;
}

int mi_colour(mi_spectra *ms, mi_node *pl, const char *name, mi_lift lift, int def,
              spm_error *err)
{
    int bad = 0;
    if (textured(pl, name, &bad, err))
        return bad ? -2 : def;
    mi_node *k = mi_prop(pl, name, "spectrum|rgb|float|blackbody", &bad, err);
    if (bad)
        return -2;
    if (!k)
        return def;
    char cname[SPM_NAME_MAX];
    snprintf(cname, sizeof cname, "%.40s@%.20s", name, strrchr(k->where, ':') ? k->where : "");
    if (!strcmp(k->tag, "rgb") && lift != MI_UNBOUNDED) { /* one fit per value, shared */
        pbrt_param pa = {0};
        int rc = as_param(ms, k, &pa, err);
        ms->sp.err = err;
        int c = rc ? -2 : pbrt_spectrum_colour(&ms->sp, &pa,
                                               lift == MI_RADIANCE ? PBRT_ILLUMINANT
                                                                   : PBRT_ALBEDO, 1.0);
        param_free(&pa);
        return c;
    }
    spm_spectrum s, out;
    if (mi_values(ms, pl, name, lift, &s, err))
        return -2;
    int rc = 0;
    if (lift == MI_RADIANCE) {
        double xyz[3];
        spm_xyz_emission(&s, xyz);
        if (xyz[1] == 0)
            return -1;
        rc = spm_sb_emission(&s, xyz[1], k->where, &out, err);
    } else if (lift == MI_REFLECTANCE) {
        rc = spm_sb_reflectance(&s, 1.0, k->where, &out, err);
    } else {
        rc = spm_sb_optical(&s, 1.0, &out);
    }
    if (rc)
        return -2;
    int c = spm_sb_colour(ms->sp.b, cname, &out, k->where, err);
    return c < 0 ? -2 : c;
}
