/* The CPU reference's spot light kind (kernels/light_spot.clh): intensity
 * e->p[SCALE] f(theta) times its colour, f falling between the beam angle
 * e->p[B] and the cone angle e->p[A] in the shape e->p[D] (SPM_SPOT_*); a
 * delta. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu.h"
#include "refcpu_lights.h"

/* f(theta) of a direction at cosine cos_l to the axis: 1 to b, 0 beyond c,
 * between them (c - theta) / (c - b) (linear), or of t = (cos_l - cos c) /
 * (cos b - cos c) the smoothstep t^2 (3 - 2 t) or the square t^2 */
float spm_ref_spot_falloff(const spm_emitter *e, float cos_l)
{
    float cc = e->p[SPM_LIGHT_P_C], c = e->p[SPM_LIGHT_P_A], b = e->p[SPM_LIGHT_P_B];
    if (!(cos_l >= cc))
        return 0.0f;
    if (e->p[SPM_LIGHT_P_D] == SPM_SPOT_LINEAR) {
        float theta = acosf(fminf(cos_l, 1.0f));
        return theta <= b ? 1.0f : (c - theta) / (c - b);
    }
    float cb = cosf(b), t = cos_l >= cb ? 1.0f : (cos_l - cc) / (cb - cc);
    return e->p[SPM_LIGHT_P_D] == SPM_SPOT_SMOOTHSTEP ? t * t * (3.0f - 2.0f * t) : t * t;
}

/* toward the light at distance d, unoccluded up to d: g = (1 / pmf) / d^2,
 * scale = I f (irradiance I f cos_i / d^2) */
int spm_ref_light_sample_SPOT(const spm_geometry *g, const spm_material *mats,
                              const spm_emitter *e, const spm_ref_key *k, spm_u32 dim,
                              const float x[3], spm_u32 hit, const spm_ref_hit *h,
                              spm_ref_lsample *ls)
{
    (void)mats, (void)k, (void)dim;
    float d2;
    if (!spm_ref_light_toward(e, x, h, ls, &d2))
        return 0;
    float f = spm_ref_spot_falloff(e, -v3_dot(ls->wi, &e->p[SPM_LIGHT_P_DIR]));
    if (!(f > 0.0f))
        return 0;
    if (!spm_ref_light_unblocked(g, x, ls->wi, hit, sqrtf(d2)))
        return 0;
    return spm_ref_light_delta(ls, e, ls->inv_pmf / d2, e->p[SPM_LIGHT_P_SCALE] * f);
}

/* from the apex (density 1), uniform in the cone: cos = 1 - u3 (1 - cos c),
 * phi = 2 pi u4, density 1 / (2 pi (1 - cos c)) */
void spm_ref_light_sample_emission_SPOT(const spm_geometry *g, const spm_emitter *e,
                                        const float u[4], float o[3], float d[3], float *pdf_pos,
                                        float *pdf_dir)
{
    (void)g;
    float cc = e->p[SPM_LIGHT_P_C], z = 1.0f - u[2] * (1.0f - cc);
    float r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * SPM_PI_F * u[3];
    float l[3] = {r * cosf(phi), r * sinf(phi), z};
    for (int i = 0; i < 3; i++)
        o[i] = e->p[SPM_LIGHT_P_POS + i];
    spm_ref_light_to_world(&e->p[SPM_LIGHT_P_DIR], l, d);
    *pdf_pos = 1.0f;
    *pdf_dir = 1.0f / (2.0f * SPM_PI_F * (1.0f - cc));
}

void spm_ref_light_pdf_emission_SPOT(const spm_geometry *g, const spm_emitter *e, const float o[3],
                                     const float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)g, (void)o;
    float cc = e->p[SPM_LIGHT_P_C];
    *pdf_pos = 1.0f;
    *pdf_dir = v3_dot(d, &e->p[SPM_LIGHT_P_DIR]) >= cc ? 1.0f / (2.0f * SPM_PI_F * (1.0f - cc))
                                                       : 0.0f;
}
