/* The CPU reference's distant light kind (kernels/light_distant.clh):
 * parallel light along e->p[DIR], irradiance e->p[SCALE] times its colour
 * on a surface facing it; the scene's bounding sphere in e->p[POS], e->p[A].
 * A delta. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu.h"
#include "refcpu_lights.h"

/* against its direction, unoccluded to infinity: g = 1 / pmf, scale = E
 * (irradiance E cos_i) */
int spm_ref_light_sample_DISTANT(const spm_geometry *g, const spm_material *mats,
                                 const spm_emitter *e, const spm_ref_key *k, spm_u32 dim,
                                 const float x[3], spm_u32 hit, const spm_ref_hit *h,
                                 spm_ref_lsample *ls)
{
    (void)mats, (void)k, (void)dim;
    for (int i = 0; i < 3; i++)
        ls->wi[i] = -e->p[SPM_LIGHT_P_DIR + i];
    if (!spm_ref_light_faces(ls->wi, h) || !spm_ref_light_unblocked(g, x, ls->wi, hit, INFINITY))
        return 0;
    return spm_ref_light_delta(ls, e, ls->inv_pmf, e->p[SPM_LIGHT_P_SCALE]);
}

/* along its direction (density 1) from a point uniform on the disc of
 * radius r one radius before the sphere's centre c: o = c - r w + r sqrt(u1)
 * (cos, sin)(2 pi u2), density 1 / (pi r^2) */
void spm_ref_light_sample_emission_DISTANT(const spm_geometry *g, const spm_emitter *e,
                                           const float u[4], float o[3], float d[3],
                                           float *pdf_pos, float *pdf_dir)
{
    (void)g;
    float r = e->p[SPM_LIGHT_P_A], rho = r * sqrtf(u[0]), phi = 2.0f * SPM_PI_F * u[1];
    float l[3] = {rho * cosf(phi), rho * sinf(phi), -r}, off[3];
    spm_ref_light_to_world(&e->p[SPM_LIGHT_P_DIR], l, off);
    for (int i = 0; i < 3; i++) {
        o[i] = e->p[SPM_LIGHT_P_POS + i] + off[i];
        d[i] = e->p[SPM_LIGHT_P_DIR + i];
    }
    *pdf_pos = 1.0f / (SPM_PI_F * r * r);
    *pdf_dir = 1.0f;
}

/* the densities of its own rays (the direction's a delta's 1) */
void spm_ref_light_pdf_emission_DISTANT(const spm_geometry *g, const spm_emitter *e,
                                        const float o[3], const float d[3], float *pdf_pos,
                                        float *pdf_dir)
{
    (void)g, (void)o, (void)d;
    float r = e->p[SPM_LIGHT_P_A];
    *pdf_pos = 1.0f / (SPM_PI_F * r * r);
    *pdf_dir = 1.0f;
}
