/* A mesh file's material, beyond its diffuse colour, mapped to a scene
 * material: the table of docs/SCENE_FORMAT.md ("Materials of mesh files"),
 * one row per source property, implemented for the targets that exist
 * (diffuse, conductor); the rows whose target types are planned (dielectric,
 * coated) warn, naming the file and the material. */
#include "mesh.h"
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

int spm_mesh_map_material(spm_scene_builder *b, const spm_mesh_material *m, int r, int e,
                          const char *where, spm_error *err)
{
    char name[SPM_NAME_MAX], todo[400] = "";
    size_t n = 0;
#define TODO(...) \
    (n += (size_t)snprintf(todo + n, n < sizeof todo ? sizeof todo - n : 0, __VA_ARGS__))
    snprintf(name, sizeof name, "%.63s", m->name[0] ? m->name : "mesh");
    int out = -2;
    static int said_layer[3]; /* per format */
    if (m->format == SPM_MESH_FMT_GLTF) {
        /* metallic >= 0.5: a conductor of F0 = base colour, alpha = roughness^2
         * (glTF's defaults: metallic 1, roughness 1) */
        double metallic = m->has & SPM_MESH_HAS_METALLIC ? m->metallic : 1.0;
        double rough = m->has & SPM_MESH_HAS_ROUGHNESS ? m->roughness : 1.0;
        rough = rough < 0 ? 0 : rough > 1 ? 1 : rough;
        if (metallic > 0 && metallic < 1)
            TODO("%smetallic %g (taken as %s: the threshold is 0.5)", n ? "; " : "", metallic,
                 metallic >= 0.5 ? "1" : "0");
        if (metallic >= 0.5)
            out = metal(b, m, m->diffuse, rough * rough, e, where, err);
        else if (!said_layer[m->format]++) /* nearly every glTF material: once per run */
            TODO("%sthe specular layer of a non-metal (F0 0.04, alpha %g: planned as 'coated'; "
                 "said once per run)", n ? "; " : "", rough * rough);
        if (m->has & SPM_MESH_HAS_TRANSMISSION && m->transmission > 0)
            TODO("%stransmission %g (KHR_materials_transmission: planned as 'dielectric')",
                 n ? "; " : "", m->transmission);
        if (m->has & SPM_MESH_HAS_IOR)
            TODO("%sior %g (KHR_materials_ior: planned for 'dielectric' and 'coated')",
                 n ? "; " : "", m->ior);
        if (m->has & SPM_MESH_HAS_VOLUME)
            TODO("%sa volume (KHR_materials_volume: planned as 'dielectric' 'absorb')",
                 n ? "; " : "");
    } else if (m->format == SPM_MESH_FMT_OBJ) {
        int ks = m->has & SPM_MESH_HAS_SPECULAR && nonblack(m->specular, 0.0f);
        /* Ns a Phong exponent: alpha = sqrt(2 / (Ns + 2)) (Walter et al. 2007) */
        double ns = m->has & SPM_MESH_HAS_SHININESS && m->shininess > 0 ? m->shininess : 0;
        double alpha = sqrt(2.0 / (ns + 2.0));
        if (ks && !nonblack(m->diffuse, 1e-3f))
            out = metal(b, m, m->specular, alpha, e, where, err);
        else if (ks && !said_layer[m->format]++) /* most MTL files have one: once per run */
            TODO("Ks %g %g %g, Ns %g (a specular layer over Kd: planned as 'coated'; said once "
                 "per run)", m->specular[0], m->specular[1], m->specular[2], ns);
        if (m->has & SPM_MESH_HAS_IOR && m->ior != 1 && ks)
            TODO("%sNi %g (planned for 'dielectric' and 'coated')", n ? "; " : "", m->ior);
    }
    if (n)
        spm_warnf("%s: not rendered yet: %s", where, todo);
#undef TODO
    if (out == -1)
        return -1;
    if (out >= 0)
        return out;
    return spm_sb_material(b, name, r, e, where, err);
}
