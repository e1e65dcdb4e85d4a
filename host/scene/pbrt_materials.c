/* pbrt-v4's materials on specmip's types (docs/PBRT.md): diffuse -> the
 * Lambertian, conductor -> conductor (eta and k, or pbrt's 'reflectance'
 * as eta 1, k = 2 sqrt(r) / sqrt(1 - r)), dielectric -> dielectric (a
 * varying eta disperses), coateddiffuse -> coated. Roughness is GGX's alpha,
 * sqrt(roughness) when 'remaproughness' is true (pbrt-v4's RoughnessToAlpha).
 * Other types become pbrt's default material, with a warning. */
#include "pbrt.h"
#include "materials.h"
#include "dispersion.h"
#include <math.h>
#include <string.h>

static const char *const pbrt_types[] = {
    "coateddiffuse", "coatedconductor", "conductor",  "dielectric",  "diffuse", "diffusetransmission",
    "hair",          "interface",       "measured",   "mix",         "subsurface", "thindielectric",
};

static void proto_init(spm_scene_material *m, unsigned type)
{
    memset(m, 0, sizeof *m);
    m->refl = m->emit = m->col2 = m->col3 = m->diag = -1;
    m->type = (int)type;
    m->etype = SPM_EMIT_AREA;
}

/* A constant reflectance-kind colour (pbrt's defaults). */
static int constant_colour(pbrt_spectra *sp, double v, const char *where)
{
    spm_spectrum s;
    char name[SPM_NAME_MAX];
    spm_spectrum_constant(v, SPM_KIND_REFLECTANCE, &s);
    snprintf(name, sizeof name, "constant %g", v);
    return spm_sb_colour(sp->b, name, &s, where, sp->err);
}

void pbrt_material_default(pbrt_spectra *sp, spm_scene_material *out)
{
    proto_init(out, SPM_MAT_LAMBERT);
    snprintf(out->name, sizeof out->name, "pbrt default");
    out->refl = constant_colour(sp, 0.5, "<default material>");
}

/* A spectrum parameter: its colour (-1 black), `def` when absent or given
 * by a texture (warned about); -2 on error. */
static int colour_param(pbrt_spectra *sp, pbrt_params *ps, const char *mt, const char *name,
                        pbrt_lift lift, int def)
{
    int bad = 0;
    pbrt_param *pa = pbrt_param_find(ps, name,
                                     1u << PP_RGB | 1u << PP_SPECTRUM | 1u << PP_BLACKBODY |
                                         1u << PP_TEXTURE | 1u << PP_FLOAT,
                                     &bad, sp->err);
    if (bad)
        return -2;
    if (!pa)
        return def;
    if (pa->type == PP_FLOAT && pa->nnum == 1) { /* a constant spectrum */
        if (lift == PBRT_ALBEDO && !(pa->num[0] >= 0 && pa->num[0] <= 1)) {
            spm_errorf(sp->err, "%s: '%s' %g is not a reflectance (0..1)", pa->where, name,
                       pa->num[0]);
            return -2;
        }
        int c = constant_colour(sp, pa->num[0], pa->where);
        return c < 0 ? -2 : c;
    }
    if (pa->type == PP_TEXTURE || pa->type == PP_FLOAT) {
        char what[160];
        snprintf(what, sizeof what, "Material \"%s\": a %s as '%s'", mt,
                 pa->type == PP_TEXTURE ? "texture" : "float", name);
        return pbrt_warn(pa->where, what, "textures are not rendered yet; the default is used",
                         sp->err) ? -2 : def;
    }
    return pbrt_spectrum_colour(sp, pa, lift, 1.0);
}

/* GGX alpha from roughness, uroughness, vroughness and remaproughness. */
static int roughness(pbrt_spectra *sp, pbrt_params *ps, const char *mt, const char *where,
                     double *alpha)
{
    int bad = 0;
    double r = pbrt_param_float(ps, "roughness", 0.0, &bad, sp->err);
    double u = pbrt_param_float(ps, "uroughness", r, &bad, sp->err);
    double v = pbrt_param_float(ps, "vroughness", r, &bad, sp->err);
    int remap = pbrt_param_bool(ps, "remaproughness", 1, &bad, sp->err);
    if (bad)
        return 1;
    if (!(u >= 0 && v >= 0)) {
        spm_errorf(sp->err, "%s: Material \"%s\": a negative roughness", where, mt);
        return 1;
    }
    char what[128];
    if (u != v) {
        snprintf(what, sizeof what, "Material \"%s\": anisotropic roughness", mt);
        if (pbrt_warn(where, what, "specmip's GGX is isotropic: sqrt(u v) is used", sp->err))
            return 1;
    }
    double a = sqrt(u * v);
    *alpha = remap ? sqrt(a) : a;
    if (*alpha > 1.0) {
        snprintf(what, sizeof what, "Material \"%s\": a GGX alpha above 1", mt);
        if (pbrt_warn(where, what, "clamped to 1", sp->err))
            return 1;
        *alpha = 1.0;
    }
    return 0;
}

/* A dielectric's eta: a float or a spectrum (named glass, rgb, inline):
 * n_d into p[slot]; a varying one also into the scene's index table. */
static int eta_param(pbrt_spectra *sp, pbrt_params *ps, const char *mt, int slot, int table,
                     spm_scene_material *m)
{
    int bad = 0;
    pbrt_param *pa = pbrt_param_find(ps, "eta", 1u << PP_FLOAT | 1u << PP_SPECTRUM | 1u << PP_RGB,
                                     &bad, sp->err);
    if (bad)
        return 1;
    m->p[slot] = 1.5;
    if (!pa)
        return 0;
    spm_spectrum s;
    if (pa->type == PP_FLOAT) {
        if (pa->nnum != 1)
            return spm_errorf(sp->err, "%s: 'eta' takes one value", pa->where), 1;
        spm_spectrum_constant(pa->num[0], SPM_KIND_REFLECTANCE, &s);
    } else if (pbrt_spectrum_values(sp, pa, PBRT_UNBOUNDED, &s)) {
        return 1;
    }
    int constant = 1;
    for (int b = 0; b < SPM_TRUTH_BINS; b++) {
        constant &= s.nm1[b] == s.nm1[0];
        if (!(s.nm1[b] >= 1.0 && s.nm1[b] <= 4.0)) {
            spm_errorf(sp->err, "%s: Material \"%s\": eta %g at %g nm is outside specmip's 1..4 "
                                "(an eta below 1, a bubble, is written as the outer medium's "
                                "surface turned: ReverseOrientation)", pa->where, mt, s.nm1[b],
                       spm_disp_bin_nm(b));
            return 1;
        }
    }
    m->p[slot] = s.nm1[(int)SPM_DISP_REF_NM - SPM_LAMBDA_MIN];
    if (constant)
        return 0;
    if (!table) {
        char what[128];
        snprintf(what, sizeof what, "Material \"%s\": a spectral 'eta'", mt);
        return pbrt_warn(pa->where, what, "the coating takes one index: its value at 587.6 nm",
                         sp->err);
    }
    spm_sb_index_table(sp->b, s.nm1, m);
    return 0;
}

static int conductor(pbrt_spectra *sp, pbrt_params *ps, const char *where, spm_scene_material *m)
{
    proto_init(m, SPM_MAT_CONDUCTOR);
    int bad = 0;
    pbrt_param *r = pbrt_param_find(ps, "reflectance", 1u << PP_RGB | 1u << PP_SPECTRUM, &bad,
                                    sp->err);
    if (bad)
        return 1;
    if (r) { /* pbrt-v4: eta 1 and k = 2 sqrt(r) / sqrt(1 - r), r clamped below 1 */
        spm_spectrum f, eta, k;
        if (pbrt_spectrum_values(sp, r, PBRT_ALBEDO, &f))
            return 1;
        spm_spectrum_constant(1.0, SPM_KIND_REFLECTANCE, &eta);
        k = f;
        for (int b = 0; b < SPM_TRUTH_BINS; b++) {
            double rv = fmin(f.nm1[b], 0.9999);
            k.nm1[b] = 2.0 * sqrt(rv) / sqrt(1.0 - rv);
        }
        m->refl = spm_sb_colour(sp->b, "eta 1", &eta, where, sp->err);
        m->col2 = m->refl < 0 ? -2 : spm_sb_colour(sp->b, "k of a reflectance", &k, where, sp->err);
    } else {
        pbrt_param def_eta = {.type = PP_SPECTRUM, .name = "eta", .nstr = 1,
                              .str = (char *[]){"metal-Cu-eta"}};
        pbrt_param def_k = {.type = PP_SPECTRUM, .name = "k", .nstr = 1,
                            .str = (char *[]){"metal-Cu-k"}};
        snprintf(def_eta.where, sizeof def_eta.where, "%s", where);
        snprintf(def_k.where, sizeof def_k.where, "%s", where);
        int de = pbrt_param_find(ps, "eta", ~0u, &bad, sp->err) ? 0 : 1;
        int dk = pbrt_param_find(ps, "k", ~0u, &bad, sp->err) ? 0 : 1;
        m->refl = de ? pbrt_spectrum_colour(sp, &def_eta, PBRT_UNBOUNDED, 1.0)
                     : colour_param(sp, ps, "conductor", "eta", PBRT_UNBOUNDED, -2);
        m->col2 = m->refl < -1 ? -2
                  : dk ? pbrt_spectrum_colour(sp, &def_k, PBRT_UNBOUNDED, 1.0)
                       : colour_param(sp, ps, "conductor", "k", PBRT_UNBOUNDED, -2);
    }
    if (m->refl < -1 || m->col2 < -1)
        return 1;
    return roughness(sp, ps, "conductor", where, &m->p[SPM_COND_P_ALPHA]);
}

static int coated(pbrt_spectra *sp, pbrt_params *ps, const char *where, spm_scene_material *m)
{
    static int said;
    if (!said++)
        spm_warnf("%s: Material \"coateddiffuse\" is rendered as specmip's coated: a dielectric "
                  "interface over a Lambertian base, without pbrt-v4's layer thickness, medium "
                  "albedo and random walk between the two (docs/PBRT.md)", where);
    proto_init(m, SPM_MAT_COATED);
    m->refl = colour_param(sp, ps, "coateddiffuse", "reflectance", PBRT_ALBEDO,
                           constant_colour(sp, 0.5, where));
    if (m->refl < -1 || eta_param(sp, ps, "coateddiffuse", SPM_COAT_P_ETA, 0, m))
        return 1;
    int bad = 0;
    pbrt_param *al = pbrt_param_find(ps, "albedo", ~0u, &bad, sp->err);
    if (al && !(al->type == PP_RGB && al->num[0] == 0 && al->num[1] == 0 && al->num[2] == 0) &&
        !(al->type == PP_FLOAT && al->num[0] == 0) &&
        pbrt_warn(al->where, "Material \"coateddiffuse\": a scattering 'albedo' in the layer",
                  "specmip's coating holds no medium", sp->err))
        return 1;
    static const char *const layer[] = {"thickness", "g", "maxdepth", "nsamples"};
    for (int i = 0; i < 4; i++) /* the random walk's own settings: nothing to map them to */
        pbrt_param_find(ps, layer[i], ~0u, &bad, sp->err);
    return roughness(sp, ps, "coateddiffuse", where, &m->p[SPM_COAT_P_ALPHA]);
}

int pbrt_material_make(pbrt_spectra *sp, const char *type, pbrt_params *ps, const char *where,
                       spm_scene_material *out, spm_error *err)
{
    sp->err = err;
    char what[128];
    snprintf(what, sizeof what, "Material \"%.60s\"", type);
    int rc;
    if (!strcmp(type, "diffuse")) {
        proto_init(out, SPM_MAT_LAMBERT);
        out->refl = colour_param(sp, ps, type, "reflectance", PBRT_ALBEDO,
                                 constant_colour(sp, 0.5, where));
        rc = out->refl < -1;
    } else if (!strcmp(type, "conductor")) {
        rc = conductor(sp, ps, where, out);
    } else if (!strcmp(type, "dielectric")) {
        proto_init(out, SPM_MAT_DIELECTRIC);
        rc = eta_param(sp, ps, type, SPM_DIEL_P_IOR, 1, out) ||
             roughness(sp, ps, type, where, &out->p[SPM_DIEL_P_ALPHA]);
    } else if (!strcmp(type, "coateddiffuse")) {
        rc = coated(sp, ps, where, out);
    } else {
        size_t i = 0;
        while (i < sizeof pbrt_types / sizeof pbrt_types[0] && strcmp(pbrt_types[i], type))
            i++;
        if (i == sizeof pbrt_types / sizeof pbrt_types[0]) {
            spm_errorf(err, "%s: unknown material type \"%s\" (pbrt-v4 has coateddiffuse, "
                            "coatedconductor, conductor, dielectric, diffuse, "
                            "diffusetransmission, hair, interface, measured, mix, subsurface, "
                            "thindielectric)", where, type);
            return 1;
        }
        pbrt_material_default(sp, out);
        if (pbrt_warn(where, what, "a type specmip does not render yet: pbrt's default "
                                   "(diffuse, reflectance 0.5) instead", err))
            return 1;
        for (int k = 0; k < ps->n; k++) /* said with the type, not one by one */
            ps->p[k].used = 1;
        return 0;
    }
    if (rc)
        return 1;
    int bad = 0;
    pbrt_param_find(ps, "type", ~0u, &bad, err); /* MakeNamedMaterial's */
    return pbrt_params_unused(ps, what, err);
}
