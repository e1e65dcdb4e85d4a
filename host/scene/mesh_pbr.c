/* A mesh file's material, beyond its diffuse colour, mapped to a scene
 * material: the table of docs/SCENE_FORMAT.md ("Materials of mesh files"),
 * one row per source property (conductor, dielectric, coated or diffuse);
 * what has no target (textures aside: mesh_texture.c) is warned about,
 * naming the file and the material. */
#include "mesh.h"
#include "dispersion.h"
#include "materials.h"
#include "rgb2spec.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The largest reflectance mapped: at r = 1 the index n of a conductor whose
 * normal-incidence reflectance is r, (1 + sqrt r) / (1 - sqrt r), is
 * infinite; 0.999 keeps n below 4000. */
#define F0_MAX 0.999

/* Gulbrandsen 2014, "Artist Friendly Metallic Fresnel" (JCGT 3(4)), per
 * wavelength, from the reflectivity r and the edge tint g:
 *   n = g (1 - r) / (1 + r) + (1 - g) (1 + sqrt r) / (1 - sqrt r),
 *   k = sqrt((r (n + 1)^2 - (n - 1)^2) / (1 - r)),
 * so that ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) = r at normal incidence. A
 * file's metal gives one colour, so g = r (its edge as tinted as its face). */
void spm_mesh_gulbrandsen(const spm_spectrum *f0, spm_spectrum *eta, spm_spectrum *k)
{
    eta->kind = k->kind = SPM_KIND_REFLECTANCE; /* extended by end values, as loaded constants */
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double r = f0->nm1[i] < 0 ? 0 : f0->nm1[i] > F0_MAX ? F0_MAX : f0->nm1[i], g = r;
        double sr = sqrt(r);
        double n = g * (1 - r) / (1 + r) + (1 - g) * (1 + sr) / (1 - sr);
        double k2 = (r * (n + 1) * (n + 1) - (n - 1) * (n - 1)) / (1 - r);
        eta->nm1[i] = n;
        k->nm1[i] = k2 > 0 ? sqrt(k2) : 0;
    }
}

static int nonblack(const float c[3], float eps)
{
    return c[0] > eps || c[1] > eps || c[2] > eps;
}

/* The conductor of F0 `rgb` (linear sRGB, lifted as a reflectance) and width
 * alpha, emitting e. */
static int metal(spm_scene_builder *b, const spm_mesh_material *m, const float rgb[3],
                 double alpha, int e, const char *where, spm_error *err)
{
    double c[3];
    for (int i = 0; i < 3; i++)
        c[i] = rgb[i] < 0 ? 0 : rgb[i] > 1 ? 1 : rgb[i];
    spm_spectrum f0, eta, k;
    double de;
    spm_error inner;
    if (spm_rgb_to_reflectance(c, &f0, &de, &inner)) {
        spm_errorf(err, "%s: %s", where, inner.msg);
        return -1;
    }
    spm_mesh_gulbrandsen(&f0, &eta, &k);
    char name[SPM_NAME_MAX];
    snprintf(name, sizeof name, "eta(%.6g,%.6g,%.6g)", c[0], c[1], c[2]);
    int ce = spm_sb_colour(b, name, &eta, where, err);
    snprintf(name, sizeof name, "k(%.6g,%.6g,%.6g)", c[0], c[1], c[2]);
    int ck = ce < 0 ? -1 : spm_sb_colour(b, name, &k, where, err);
    if (ck < 0)
        return -1;
    spm_scene_material proto;
    memset(&proto, 0, sizeof proto);
    snprintf(proto.name, sizeof proto.name, "%.63s", m->name[0] ? m->name : "mesh");
    proto.type = SPM_MAT_CONDUCTOR;
    proto.etype = SPM_EMIT_AREA;
    proto.refl = ce;
    proto.col2 = ck;
    proto.col3 = proto.diag = -1;
    proto.emit = e;
    proto.p[SPM_COND_P_ALPHA] = alpha < SPM_COND_MIN_ALPHA ? 0.0 : alpha > 1 ? 1 : alpha;
    return spm_sb_material_typed(b, &proto, where, err);
}

/* Indices outside the types' range [1, 4] (materials.c) are clamped. */
static double clamp_ior(double ior)
{
    return ior < 1.0 ? 1.0 : ior > 4.0 ? 4.0 : ior;
}

/* An MTL's Ni where it is more than 1, else 1.5: Assimp gives every OBJ
 * material Ni 1 when the file has none, and exporters write 1 for "unset";
 * an index of 1 would make the coating or the glass vanish. */
static double mtl_ior(const spm_mesh_material *m)
{
    return m->has & SPM_MESH_HAS_IOR && m->ior > 1.0f ? clamp_ior(m->ior) : 1.5;
}

static double clamp_alpha(double alpha)
{
    return alpha < SPM_COND_MIN_ALPHA ? 0.0 : alpha > 1 ? 1 : alpha;
}

/* The darkest attenuation colour value taken: sigma = -ln(c) / d is infinite
 * at c = 0; at 1e-4 the glass passes 1e-4 of the light per distance d, black
 * to the eye after d, and sigma stays finite. */
#define ATTEN_C_MIN 1e-4

/* A coated material: the lifted base colour r under a coating of index ior
 * and width alpha, emitting e. */
static int coated(spm_scene_builder *b, const spm_mesh_material *m, int r, double ior,
                  double alpha, int e, const spm_scene_material *mix, const char *where,
                  spm_error *err)
{
    spm_scene_material proto;
    memset(&proto, 0, sizeof proto);
    if (mix) {
        proto.mix_metal = mix->mix_metal;
        proto.mix_metallic = mix->mix_metallic;
        proto.mix_rough = mix->mix_rough;
    }
    snprintf(proto.name, sizeof proto.name, "%.63s", m->name[0] ? m->name : "mesh");
    proto.type = SPM_MAT_COATED;
    proto.etype = SPM_EMIT_AREA;
    proto.refl = r;
    proto.col2 = proto.col3 = proto.diag = -1;
    proto.emit = e;
    proto.p[SPM_COAT_P_ETA] = clamp_ior(ior);
    proto.p[SPM_COAT_P_ALPHA] = clamp_alpha(alpha);
    return spm_sb_material_typed(b, &proto, where, err);
}

/* glTF's KHR_materials_dispersion on a dielectric of index nd (the file's
 * ior, taken as n at the d-line): the Abbe number V_d = 20 / disp and the
 * extension's two-term Cauchy law with its constants,
 *   n(lambda) = max(nd + (nd - 1) / V_d (523655 / lambda^2 - 1.5168), 1),
 * lambda in nm (A + B / lambda^2 through n_d at 587.6 nm, n_F - n_C =
 * (nd - 1) / V_d between 486.1 and 656.3 nm), held per 1 nm bin and kept
 * within the types' 1 to 4. */
static void gltf_dispersion(spm_scene_builder *b, double nd, double disp,
                            spm_scene_material *proto)
{
    double n[SPM_TRUTH_BINS], k = (nd - 1.0) * disp / 20.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double l = spm_disp_bin_nm(i);
        n[i] = clamp_ior(nd + k * (523655.0 / (l * l) - 1.5168));
    }
    proto->p[SPM_DIEL_P_IOR] =
        clamp_ior(nd + k * (523655.0 / (SPM_DISP_REF_NM * SPM_DISP_REF_NM) - 1.5168));
    spm_sb_index_table(b, n, proto);
}

/* A dielectric of index ior and width alpha, emitting e, absorbing with
 * sigma(lambda) = -ln(c(lambda)) / dist, c the lifted linear-sRGB colour
 * atten (clamped to [ATTEN_C_MIN, 1]), when atten is non-NULL; dispersive
 * by a glTF material's KHR_materials_dispersion. */
static int glass(spm_scene_builder *b, const spm_mesh_material *m, double ior, double alpha,
                 const float *atten, double dist, int e, const char *where, spm_error *err)
{
    spm_scene_material proto;
    memset(&proto, 0, sizeof proto);
    snprintf(proto.name, sizeof proto.name, "%.63s", m->name[0] ? m->name : "mesh");
    proto.type = SPM_MAT_DIELECTRIC;
    proto.etype = SPM_EMIT_AREA;
    proto.refl = proto.col2 = proto.col3 = proto.diag = -1;
    proto.emit = e;
    proto.p[SPM_DIEL_P_IOR] = clamp_ior(ior);
    proto.p[SPM_DIEL_P_ALPHA] = clamp_alpha(alpha);
    if (m->has & SPM_MESH_HAS_DISPERSION && m->dispersion > 0)
        gltf_dispersion(b, clamp_ior(ior), m->dispersion, &proto);
    if (atten) {
        double c[3];
        for (int i = 0; i < 3; i++)
            c[i] = atten[i] < ATTEN_C_MIN ? ATTEN_C_MIN : atten[i] > 1 ? 1 : atten[i];
        spm_spectrum cs, sigma;
        spm_error inner;
        if (spm_rgb_to_reflectance(c, &cs, NULL, &inner)) {
            spm_errorf(err, "%s: %s", where, inner.msg);
            return -1;
        }
        /* an optical colour as loaded constants are: extended by end values */
        sigma.kind = SPM_KIND_REFLECTANCE;
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            sigma.nm1[i] = -log(cs.nm1[i] < ATTEN_C_MIN ? ATTEN_C_MIN
                                : cs.nm1[i] > 1 ? 1 : cs.nm1[i]) / dist;
        char name[SPM_NAME_MAX];
        snprintf(name, sizeof name, "absorb(%.5g,%.5g,%.5g)/%.5g", c[0], c[1], c[2], dist);
        proto.col2 = spm_sb_colour(b, name, &sigma, where, err);
        if (proto.col2 < 0)
            return -1;
    }
    return spm_sb_material_typed(b, &proto, where, err);
}

/* glTF's metallic-roughness model where the metallic value varies or lies
 * between 0 and 1: the coated base (alpha = roughness^2) with a mix record
 * naming its metal, the conductor of F0 = the base colour (spm_shared.h
 * SPM_MIX_*, kernels/metalrough.clh); its maps are bound after
 * (spm_mesh_mix_bind). */
static int metallic_roughness(spm_scene_builder *b, const spm_mesh_material *m, int r,
                              double ior, double metallic, double rough, int e,
                              const char *where, spm_error *err)
{
    int metal_i = metal(b, m, m->diffuse, rough * rough, e, where, err);
    if (metal_i < 0)
        return -1;
    snprintf(b->s->materials[metal_i].name, sizeof b->s->materials[metal_i].name, "%.56s:metal",
             m->name[0] ? m->name : "mesh");
    spm_scene_material mix;
    memset(&mix, 0, sizeof mix);
    mix.mix_metal = 1 + metal_i;
    mix.mix_metallic = (float)(metallic > 1 ? 1 : metallic);
    mix.mix_rough = (float)rough;
    return coated(b, m, r, ior, rough * rough, e, &mix, where, err);
}

int spm_mesh_map_material(spm_scene_builder *b, const spm_mesh_material *m, int r, int e,
                          double scale, const char *where, spm_error *err)
{
    char name[SPM_NAME_MAX], todo[600] = "";
    size_t n = 0;
#define TODO(...) \
    (n += (size_t)snprintf(todo + n, n < sizeof todo ? sizeof todo - n : 0, __VA_ARGS__))
#define SEP (n ? "; " : "")
    snprintf(name, sizeof name, "%.63s", m->name[0] ? m->name : "mesh");
    int out = -2;
    if (m->format == SPM_MESH_FMT_GLTF) {
        /* glTF's defaults: metallic 1, roughness 1, ior 1.5, no transmission */
        double metallic = m->has & SPM_MESH_HAS_METALLIC ? m->metallic : 1.0;
        double rough = m->has & SPM_MESH_HAS_ROUGHNESS ? m->roughness : 1.0;
        rough = rough < 0 ? 0 : rough > 1 ? 1 : rough;
        double alpha = rough * rough;
        double ior = m->has & SPM_MESH_HAS_IOR ? m->ior : 1.5;
        double t = m->has & SPM_MESH_HAS_TRANSMISSION ? m->transmission : 0.0;
        if (m->has & SPM_MESH_HAS_IOR && (ior < 1.0 || ior > 4.0))
            TODO("%sior %g (taken as %g: the types' range is 1 to 4)", SEP, ior, clamp_ior(ior));
        /* a metallic map, or a metallic value between 0 and 1: the mix */
        int mixed = t < 0.5 && (m->mr_map || (metallic > 0 && metallic < 1));
        if (mixed) {
            out = metallic_roughness(b, m, r, ior, metallic, rough, e, where, err);
        } else if (metallic >= 0.5) {
            /* a conductor of F0 = base colour, alpha = roughness^2; transmission
             * and ior are the dielectric part's, which a metal has not */
            if (t > 0)
                TODO("%stransmission %g (not on a metal)", SEP, t);
            out = metal(b, m, m->diffuse, alpha, e, where, err);
        } else if (t >= 0.5) {
            if (t < 1)
                TODO("%stransmission %g (taken as 1: the threshold is 0.5)", SEP, t);
            /* a volume: thicknessFactor > 0 (0: thin-walled); its attenuation
             * distance is in glTF world units (node transforms applied, as
             * the triangles here), so the statement's scale makes it scene
             * units; 0 or none: Assimp's and glTF's "infinite", no absorption */
            int volume = m->has & SPM_MESH_HAS_VOLUME && m->thickness > 0;
            double dist = m->atten_dist * scale;
            int absorbs = volume && m->atten_dist > 0 && isfinite(dist) && dist > 0 &&
                          (m->atten_colour[0] < 1 || m->atten_colour[1] < 1 ||
                           m->atten_colour[2] < 1);
            if (!volume)
                TODO("%sthin-walled (no KHR_materials_volume thickness: taken as solid glass)",
                     SEP);
            out = glass(b, m, ior, alpha, absorbs ? m->atten_colour : NULL, dist, e, where, err);
        } else {
            if (t > 0)
                TODO("%stransmission %g (taken as 0: the threshold is 0.5)", SEP, t);
            /* glTF's dielectric BRDF: a specular layer of index ior over the
             * base colour */
            out = coated(b, m, r, ior, alpha, e, NULL, where, err);
        }
        if (mixed && m->texture != SPM_MESH_TEX_NONE)
            TODO("%sthe base colour texture on the metal (its mean colour there)", SEP);
        if (!mixed && metallic > 0 && metallic < 1)
            TODO("%smetallic %g on a transmissive material (taken as %s: the threshold is 0.5)",
                 SEP, metallic, metallic >= 0.5 ? "1" : "0");
        if (m->mr_map && !mixed)
            TODO("%smetallic-roughness map '%s' (not on a transmissive material)", SEP,
                 m->mr_name);
        if (m->has & SPM_MESH_HAS_VOLUME && metallic < 0.5 && t < 0.5 && m->thickness > 0)
            TODO("%sa volume without transmission (not rendered)", SEP);
    } else if (m->format == SPM_MESH_FMT_OBJ) {
        int ks = m->has & SPM_MESH_HAS_SPECULAR && nonblack(m->specular, 0.0f);
        /* Ns a Phong exponent: alpha = sqrt(2 / (Ns + 2)) (Walter et al. 2007) */
        double ns = m->has & SPM_MESH_HAS_SHININESS && m->shininess > 0 ? m->shininess : 0;
        double alpha = sqrt(2.0 / (ns + 2.0));
        if (m->has & SPM_MESH_HAS_REFRACT) /* illum 6 or 7: refraction on */
            out = glass(b, m, mtl_ior(m), alpha, NULL, 1.0, e, where, err);
        else if (ks && !nonblack(m->diffuse, 1e-3f))
            out = metal(b, m, m->specular, alpha, e, where, err);
        else if (ks)
            out = coated(b, m, r, mtl_ior(m), alpha, e, NULL, where, err);
    }
    if (n)
        spm_warnf("%s: not rendered as the file says: %s", where, todo);
#undef SEP
#undef TODO
    if (out == -1)
        return -1;
    if (out >= 0)
        return out;
    return spm_sb_material(b, name, r, e, where, err);
}
