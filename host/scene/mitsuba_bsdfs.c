/* Mitsuba 3's BSDFs on specmip's types (docs/MITSUBA.md): diffuse -> the
 * Lambertian; conductor, roughconductor -> conductor (a `material` name
 * from specmip's spectra/, or eta and k); dielectric, roughdielectric ->
 * dielectric (eta = int_ior / ext_ior); plastic, roughplastic -> coated,
 * which is Mitsuba's plastic with nonlinear true; twosided and mask render
 * the BSDF they hold. Roughness is alpha (GGX's width); a Beckmann
 * distribution is rendered as GGX of the same alpha, with a warning. What
 * has no counterpart is warned about by name and becomes Mitsuba's default
 * BSDF (diffuse, reflectance 0.5). */
#include "mitsuba.h"
#include "materials.h"
#include <math.h>
#include <string.h>

static void proto_init(spm_scene_material *m, unsigned type)
{
    memset(m, 0, sizeof *m);
    m->refl = m->emit = m->col2 = m->col3 = m->diag = -1;
    m->type = (int)type;
    m->etype = SPM_EMIT_AREA;
}

static int constant(mi_spectra *ms, double v, spm_kind kind, const char *where, spm_error *err)
{
    spm_spectrum s;
    char name[SPM_NAME_MAX];
    spm_spectrum_constant(v, kind, &s);
    snprintf(name, sizeof name, "constant %g", v);
    return spm_sb_colour(ms->sp.b, name, &s, where, err);
}

void mi_bsdf_default(mi_spectra *ms, spm_scene_material *out)
{
    proto_init(out, SPM_MAT_LAMBERT);
    snprintf(out->name, sizeof out->name, "mitsuba default");
    out->refl = constant(ms, 0.5, SPM_KIND_REFLECTANCE, "<default bsdf>", ms->sp.err);
}

/* "<bsdf type=\"T\">" for messages. */
static void what_of(const mi_node *b, const char *suffix, char *w, size_t size)
{
    const char *t = mi_attr(b, "type");
    snprintf(w, size, "<%s type=\"%.40s\">%s%s", b->tag, t ? t : "", suffix ? ": " : "",
             suffix ? suffix : "");
}

/* alpha (default 0.1), alpha_u/alpha_v, distribution: GGX's width. */
static int roughness(mi_node *b, double *alpha, spm_error *err)
{
    int bad = 0;
    double a = mi_float(b, "alpha", 0.1, &bad, err);
    double u = mi_float(b, "alpha_u", a, &bad, err);
    double v = mi_float(b, "alpha_v", a, &bad, err);
    const char *dist = mi_string(b, "distribution", "beckmann", &bad, err);
    mi_bool(b, "sample_visible", 1, &bad, err); /* a sampling choice: the same image */
    if (bad)
        return 1;
    if (!(u >= 0 && v >= 0)) {
        spm_errorf(err, "%s: a negative alpha", b->where);
        return 1;
    }
    char w[200];
    if (u != v) {
        what_of(b, "anisotropic alpha_u, alpha_v", w, sizeof w);
        if (pbrt_warn(b->where, w, "specmip's GGX is isotropic: sqrt(u v) is used", err))
            return 1;
    }
    if (strcmp(dist, "ggx")) {
        char d[80];
        snprintf(d, sizeof d, "distribution \"%.40s\"", dist);
        what_of(b, d, w, sizeof w);
        if (pbrt_warn(b->where, w, "rendered as GGX of the same alpha", err))
            return 1;
    }
    *alpha = fmin(sqrt(u * v), 1.0);
    return 0;
}

/* specular_reflectance / specular_transmittance: 1 is the physics; other values are warned. */
static int specular_scale(mi_spectra *ms, mi_node *b, const char *name, spm_error *err)
{
    int bad = 0;
    mi_node *k = mi_prop(b, name, "spectrum|rgb|float", &bad, err);
    if (bad || !k)
        return bad;
    spm_spectrum s;
    if (mi_values(ms, b, name, MI_UNBOUNDED, &s, err) == 2)
        return 1;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        if (fabs(s.nm1[i] - 1.0) > 1e-6) {
            char w[200];
            snprintf(w, sizeof w, "'%s'", name);
            char full[260];
            what_of(b, w, full, sizeof full);
            return pbrt_warn(k->where, full, "specmip's interfaces scale by 1 (Fresnel alone)",
                             err);
        }
    return 0;
}

static int conductor(mi_spectra *ms, mi_node *b, int rough, spm_scene_material *m,
                     spm_error *err)
{
    proto_init(m, SPM_MAT_CONDUCTOR);
    int bad = 0;
    const char *mat = mi_string(b, "material", NULL, &bad, err);
    mi_node *eta = mi_prop(b, "eta", "spectrum|rgb|float", &bad, err);
    if (bad)
        return 1;
    if (!mat && !eta)
        mat = "none"; /* Mitsuba's default: a perfect mirror, eta 0 and k 1 */
    if (mat && !strcmp(mat, "none")) {
        m->refl = constant(ms, 0.0, SPM_KIND_REFLECTANCE, b->where, err);
        m->col2 = constant(ms, 1.0, SPM_KIND_REFLECTANCE, b->where, err);
    } else if (mat) {
        char name[64];
        const char *list;
        spm_spectrum e, k;
        spm_error inner;
        snprintf(name, sizeof name, "metal-%.20s-eta", mat);
        int rc = pbrt_named_spectrum(name, SPM_KIND_REFLECTANCE, &e, &list, &inner);
        snprintf(name, sizeof name, "metal-%.20s-k", mat);
        rc = rc || pbrt_named_spectrum(name, SPM_KIND_REFLECTANCE, &k, &list, &inner);
        char w[160];
        snprintf(w, sizeof w, "conductor material \"%.40s\"", mat);
        if (rc && pbrt_warn(b->where, w, "specmip has data for Ag, Al, Au, Cu (spectra/"
                                         "metal_*.csv): Mitsuba's \"none\" (a mirror) instead",
                            err))
            return 1;
        if (rc) {
            spm_spectrum_constant(0.0, SPM_KIND_REFLECTANCE, &e);
            spm_spectrum_constant(1.0, SPM_KIND_REFLECTANCE, &k);
        }
        m->refl = spm_sb_colour(ms->sp.b, rc ? "eta 0" : "eta", &e, b->where, err);
        m->col2 = m->refl < 0 ? -1 : spm_sb_colour(ms->sp.b, rc ? "k 1" : "k", &k, b->where, err);
    } else {
        m->refl = mi_colour(ms, b, "eta", MI_UNBOUNDED, -2, err);
        m->col2 = m->refl < -1 ? -2 : mi_colour(ms, b, "k", MI_UNBOUNDED, -1, err);
        if (m->col2 == -1)
            m->col2 = constant(ms, 0.0, SPM_KIND_REFLECTANCE, b->where, err);
    }
    if (m->refl < 0 || m->col2 < 0 || specular_scale(ms, b, "specular_reflectance", err))
        return 1;
    return rough ? roughness(b, &m->p[SPM_COND_P_ALPHA], err) : 0;
}

static int dielectric(mi_spectra *ms, mi_node *b, int rough, spm_scene_material *m,
                      spm_error *err)
{
    proto_init(m, SPM_MAT_DIELECTRIC);
    double in, ext;
    if (mi_ior(b, "int_ior", 1.5046, &in, err) || mi_ior(b, "ext_ior", 1.000277, &ext, err))
        return 1;
    m->p[SPM_DIEL_P_IOR] = in / ext;
    if (!(in / ext >= 1.0)) {
        spm_errorf(err, "%s: int_ior / ext_ior = %g: specmip's dielectric takes 1..4 (write "
                        "the surface the other way round)", b->where, in / ext);
        return 1;
    }
    return specular_scale(ms, b, "specular_reflectance", err) ||
           specular_scale(ms, b, "specular_transmittance", err) ||
           (rough && roughness(b, &m->p[SPM_DIEL_P_ALPHA], err));
}

static int plastic(mi_spectra *ms, mi_node *b, int rough, spm_scene_material *m,
                   spm_error *err)
{
    proto_init(m, SPM_MAT_COATED);
    double in, ext;
    int bad = 0;
    m->refl = mi_colour(ms, b, "diffuse_reflectance", MI_REFLECTANCE,
                        constant(ms, 0.5, SPM_KIND_REFLECTANCE, b->where, err), err);
    if (m->refl < -1 || mi_ior(b, "int_ior", 1.49, &in, err) ||
        mi_ior(b, "ext_ior", 1.000277, &ext, err))
        return 1;
    m->p[SPM_COAT_P_ETA] = fmax(in / ext, 1.0);
    int nonlinear = mi_bool(b, "nonlinear", 0, &bad, err);
    if (bad || specular_scale(ms, b, "specular_reflectance", err))
        return 1;
    char w[200];
    what_of(b, "nonlinear false", w, sizeof w);
    if (!nonlinear && pbrt_warn(b->where, w, "specmip's coated is Mitsuba's plastic with "
                                             "nonlinear true (a darker, more saturated base)",
                                err))
        return 1;
    return rough ? roughness(b, &m->p[SPM_COAT_P_ALPHA], err) : 0;
}

/* The BSDF a twosided or mask holds (a child <bsdf> or a <ref>). */
static mi_node *inner(mi_ids *ids, mi_node *b, int *count, spm_error *err)
{
    mi_node *first = NULL;
    *count = 0;
    for (int i = 0; i < b->nkids; i++) {
        mi_node *k = b->kids[i];
        if (strcmp(k->tag, "bsdf") && strcmp(k->tag, "ref"))
            continue;
        k->used = 1;
        mi_node *t = strcmp(k->tag, "ref") ? k : mi_ref(ids, k, err);
        if (!t)
            return NULL;
        if (!first)
            first = t;
        (*count)++;
    }
    if (!first)
        spm_errorf(err, "%s: <bsdf type=\"%s\"> holds no <bsdf>", b->where, mi_attr(b, "type"));
    return first;
}

static int wrapper(mi_spectra *ms, mi_ids *ids, mi_node *b, const char *type,
                   spm_scene_material *out, spm_error *err)
{
    int n, bad = 0;
    mi_node *in = inner(ids, b, &n, err);
    if (!in)
        return 1;
    char w[200];
    if (!strcmp(type, "mask")) {
        mi_prop(b, "opacity", "spectrum|rgb|float|texture", &bad, err);
        what_of(b, NULL, w, sizeof w);
        if (bad || pbrt_warn(b->where, w, "an opacity mask: the surface is rendered whole", err))
            return 1;
    } else if (n > 1) {
        what_of(b, "a second BSDF for the back", w, sizeof w);
        if (pbrt_warn(b->where, w, "both faces take the first", err))
            return 1;
    }
    return mi_bsdf_make(ms, ids, in, out, err);
}

static const char *const known_other[] = {
    "thindielectric", "bumpmap", "normalmap", "blendbsdf", "principled", "principledthin",
    "hair", "measured", "pplastic", "polarizer", "retarder", "circular", "null", NULL};

int mi_bsdf_make(mi_spectra *ms, mi_ids *ids, mi_node *b, spm_scene_material *out,
                 spm_error *err)
{
    const char *type = mi_attr(b, "type");
    int rc;
    b->used = 1;
    ms->sp.err = err;
    if (!type) {
        spm_errorf(err, "%s: <bsdf> needs a 'type'", b->where);
        return 1;
    }
    if (!strcmp(type, "diffuse")) {
        proto_init(out, SPM_MAT_LAMBERT);
        out->refl = mi_colour(ms, b, "reflectance", MI_REFLECTANCE,
                              constant(ms, 0.5, SPM_KIND_REFLECTANCE, b->where, err), err);
        rc = out->refl < -1;
    } else if (!strcmp(type, "conductor") || !strcmp(type, "roughconductor")) {
        rc = conductor(ms, b, type[0] == 'r', out, err);
    } else if (!strcmp(type, "dielectric") || !strcmp(type, "roughdielectric")) {
        rc = dielectric(ms, b, type[0] == 'r', out, err);
    } else if (!strcmp(type, "plastic") || !strcmp(type, "roughplastic")) {
        rc = plastic(ms, b, type[0] == 'r', out, err);
    } else if (!strcmp(type, "twosided") || !strcmp(type, "mask")) {
        return wrapper(ms, ids, b, type, out, err) || mi_unused(b, "<bsdf>", err);
    } else {
        int i = 0;
        while (known_other[i] && strcmp(known_other[i], type))
            i++;
        if (!known_other[i]) {
            spm_errorf(err, "%s: unknown BSDF type \"%s\"", b->where, type);
            return 1;
        }
        char w[200];
        what_of(b, NULL, w, sizeof w);
        mi_bsdf_default(ms, out);
        for (int k = 0; k < b->nkids; k++) /* said with the type, not one by one */
            b->kids[k]->used = 1;
        return pbrt_warn(b->where, w, "a BSDF specmip does not render: Mitsuba's default "
                                      "(diffuse, reflectance 0.5) instead", err);
    }
    if (rc)
        return 1;
    snprintf(out->name, sizeof out->name, "%.60s", mi_attr(b, "id") ? mi_attr(b, "id") : type);
    char w[200];
    what_of(b, NULL, w, sizeof w);
    return mi_unused(b, w, err);
}
