/* The CPU reference's sun kind (kernels/light_sun.clh): a disc of angular
 * radius alpha around e->p[DIR] (toward it), radiance e->p[SCALE];
 * e->p[B] = 1 - cos alpha, e->p[C] = sin^2 alpha; the scene's bounding
 * sphere in e->p[POS], e->p[A]. Sampled uniformly in its cone. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu.h"
#include "refcpu_lights.h"

/* uniform in the cone: 1 - cos theta = t = u1 (1 - cos alpha), sin theta =
 * sqrt(t (2 - t)) */
static void sun_cone(const spm_emitter *e, float u1, float u2, float w[3])
{
    float t = u1 * e->p[SPM_LIGHT_P_B], st = sqrtf(t * (2.0f - t)), phi = 2.0f * SPM_PI_F * u2;
    float l[3] = {st * cosf(phi), st * sinf(phi), 1.0f - t};
    spm_ref_light_to_world(&e->p[SPM_LIGHT_P_DIR], l, w);
}

/* toward it and |d x w|^2 <= sin^2 alpha */
static int sun_inside(const spm_emitter *e, const float d[3])
{
    float c[3];
    v3_cross(c, d, &e->p[SPM_LIGHT_P_DIR]);
    return v3_dot(d, &e->p[SPM_LIGHT_P_DIR]) > 0.0f && v3_dot(c, c) <= e->p[SPM_LIGHT_P_C];
}

spm_u32 spm_ref_light_escape_SUN(const spm_emitter *e, float pmf, const float d[3], float *scale,
                                 float *pdf)
{
    if (!sun_inside(e, d))
        return SPM_NONE;
    *scale = e->p[SPM_LIGHT_P_SCALE];
    *pdf = pmf / (2.0f * SPM_PI_F * e->p[SPM_LIGHT_P_B]);
    return e->colour;
}

int spm_ref_light_sample_SUN(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                             const spm_ref_key *k, spm_u32 dim, const float x[3], spm_u32 hit,
                             const spm_ref_hit *h, spm_ref_lsample *ls)
{
    (void)mats;
    sun_cone(e, spm_ref_rnd(k, dim + SPM_DIM_EPOINT_A), spm_ref_rnd(k, dim + SPM_DIM_EPOINT_B),
             ls->wi);
    if (!spm_ref_light_faces(ls->wi, h) || !spm_ref_light_unblocked(g, x, ls->wi, hit, INFINITY))
        return 0;
    float pdf_sa = 1.0f / (2.0f * SPM_PI_F * e->p[SPM_LIGHT_P_B]);
    ls->pdf = ls->pmf * pdf_sa;
    ls->g = ls->inv_pmf / pdf_sa;
    ls->scale = e->p[SPM_LIGHT_P_SCALE];
    ls->colour = e->colour;
    ls->delta = 0;
    return 1;
}

/* along -w, w uniform in the cone (u[0], u[1]), from a point uniform on the
 * disc of radius r facing it, r before the centre c toward it (u[2], u[3]);
 * densities 1 / (pi r^2), 1 / (2 pi (1 - cos alpha)) */
void spm_ref_light_sample_emission_SUN(const spm_geometry *g, const spm_emitter *e, const float u[4],
                                       float o[3], float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)g;
    float w[3], off[3];
    sun_cone(e, u[0], u[1], w);
    float r = e->p[SPM_LIGHT_P_A], rho = r * sqrtf(u[2]), phi = 2.0f * SPM_PI_F * u[3];
    float l[3] = {rho * cosf(phi), rho * sinf(phi), r};
    spm_ref_light_to_world(w, l, off);
    for (int i = 0; i < 3; i++) {
        o[i] = e->p[SPM_LIGHT_P_POS + i] + off[i];
        d[i] = -w[i];
    }
    *pdf_pos = 1.0f / (SPM_PI_F * r * r);
    *pdf_dir = 1.0f / (2.0f * SPM_PI_F * e->p[SPM_LIGHT_P_B]);
}

void spm_ref_light_pdf_emission_SUN(const spm_geometry *g, const spm_emitter *e, const float o[3],
                                    const float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)g, (void)o;
    float back[3] = {-d[0], -d[1], -d[2]}, r = e->p[SPM_LIGHT_P_A];
    *pdf_pos = 1.0f / (SPM_PI_F * r * r);
    *pdf_dir = sun_inside(e, back) ? 1.0f / (2.0f * SPM_PI_F * e->p[SPM_LIGHT_P_B]) : 0.0f;
}
