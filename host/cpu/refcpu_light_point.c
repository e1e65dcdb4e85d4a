/* The CPU reference's point light kind (kernels/light_point.clh): intensity
 * e->p[SCALE] times its colour in every direction; a delta. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu.h"
#include "refcpu_lights.h"

/* toward the light at distance d, unoccluded up to d: g = (1 / pmf) / d^2,
 * scale = I (irradiance I cos_i / d^2) */
int spm_ref_light_sample_POINT(const spm_geometry *g, const spm_material *mats,
                               const spm_emitter *e, const spm_ref_key *k, spm_u32 dim,
                               const float x[3], spm_u32 hit, const spm_ref_hit *h,
                               spm_ref_lsample *ls)
{
    (void)mats, (void)k, (void)dim;
    float d2;
    if (!spm_ref_light_toward(e, x, h, ls, &d2))
        return 0;
    if (!spm_ref_light_unblocked(g, x, ls->wi, hit, sqrtf(d2)))
        return 0;
    return spm_ref_light_delta(ls, e, ls->inv_pmf / d2, e->p[SPM_LIGHT_P_SCALE]);
}

/* from the point (density 1), a uniform direction (density 1 / (4 pi)) */
void spm_ref_light_sample_emission_POINT(const spm_geometry *g, const spm_emitter *e,
                                         const float u[4], float o[3], float d[3], float *pdf_pos,
                                         float *pdf_dir)
{
    (void)g;
    float z = 1.0f - 2.0f * u[2], r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * SPM_PI_F * u[3];
    for (int i = 0; i < 3; i++)
        o[i] = e->p[SPM_LIGHT_P_POS + i];
    d[0] = r * cosf(phi);
    d[1] = r * sinf(phi);
    d[2] = z;
    *pdf_pos = 1.0f;
    *pdf_dir = 1.0f / (4.0f * SPM_PI_F);
}

void spm_ref_light_pdf_emission_POINT(const spm_geometry *g, const spm_emitter *e, const float o[3],
                                      const float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)g, (void)e, (void)o, (void)d;
    *pdf_pos = 1.0f;
    *pdf_dir = 1.0f / (4.0f * SPM_PI_F);
}
