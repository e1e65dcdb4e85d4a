/* The CPU reference's dielectric (refcpu_dielectric.h). */
#include "refcpu_dielectric.h"
#include <math.h>
#include <stdint.h>
#include "geometry_vec3.h"

float spm_ref_diel_fresnel(float ci, float e, float *ct_out)
{
    /* sin_t^2 = (1 - ci^2) / e^2; ct = sqrt(1 - sin_t^2);
     * rs = (ci - e ct) / (ci + e ct), rp = (e ci - ct) / (e ci + ct) */
    float s2 = (1.0f - ci * ci) / (e * e);
    if (s2 >= 1.0f) {
        *ct_out = 0.0f;
        return 1.0f;
    }
    float ct = sqrtf(1.0f - s2);
    float rs = (ci - e * ct) / (ci + e * ct);
    float rp = (e * ci - ct) / (e * ci + ct);
    *ct_out = ct;
    return 0.5f * (rs * rs + rp * rp);
}

float spm_ref_diel_eta(const spm_tri *tri, const float d[3], float ior)
{
    float back[3] = {-d[0], -d[1], -d[2]};
    return v3_dot(back, tri->n) > 0.0f ? ior : 1.0f / ior;
}

float spm_ref_diel_light(const spm_ref_cond *c, float e, const float l[3], float pick_pdf,
                         float d2c, float area, float cos_e)
{
    float wi[3] = {v3_dot(l, c->t), v3_dot(l, c->b), v3_dot(l, c->n)}, s[3], h[3];
    for (int i = 0; i < 3; i++)
        s[i] = c->wo[i] + wi[i];
    v3_normalise(h, s);
    float d = spm_ref_ggx_d(c->alpha, h[2]);
    float lo = spm_ref_ggx_lambda(c->alpha, c->wo[2]), li = spm_ref_ggx_lambda(c->alpha, wi[2]);
    float ct;
    float f = spm_ref_diel_fresnel(v3_dot(c->wo, h), e, &ct);
    float pb = f * d / ((1.0f + lo) * 4.0f * c->wo[2]);
    float fr = f * d / ((1.0f + lo + li) * 4.0f * c->wo[2]);
    float pl = pick_pdf * d2c / (area * cos_e);
    return fr * spm_ref_cond_power(pl, pb);
}

int spm_ref_diel_lobe(const spm_ref_cond *c, float e, float u1, float u2, float uc, float out[3],
                      float *w_t, float *w_g, float *pdf)
{
    float m[3] = {0.0f, 0.0f, 1.0f}, wi[3];
    float cm = c->wo[2];
    *w_t = 1.0f;
    *w_g = 1.0f;
    *pdf = 0.0f;
    if (c->alpha > 0.0f) {
        spm_ref_ggx_vndf(c->wo, c->alpha, u1, u2, m);
        cm = v3_dot(c->wo, m);
    }
    if (!(cm > 0.0f))
        return 0;
    float ct;
    float f = spm_ref_diel_fresnel(cm, e, &ct);
    int rf = uc < f;
    if (rf) /* wi = 2 (wo.m) m - wo */
        for (int i = 0; i < 3; i++)
            wi[i] = m[i] * (2.0f * cm) - c->wo[i];
    else /* wi = -wo / e + m (ci / e - ct) */
        for (int i = 0; i < 3; i++)
            wi[i] = -c->wo[i] / e + m[i] * (cm / e - ct);
    if (rf ? !(wi[2] > 0.0f) : !(wi[2] < 0.0f))
        return 0;
    if (!rf)
        *w_t = 1.0f / (e * e);
    if (c->alpha > 0.0f) {
        float lo = spm_ref_ggx_lambda(c->alpha, c->wo[2]);
        float li = spm_ref_ggx_lambda(c->alpha, fabsf(wi[2]));
        *w_g = (1.0f + lo) / (1.0f + lo + li);
        if (rf)
            *pdf = f * spm_ref_ggx_d(c->alpha, m[2]) / ((1.0f + lo) * 4.0f * c->wo[2]);
    }
    for (int i = 0; i < 3; i++)
        out[i] = c->t[i] * wi[0] + c->b[i] * wi[1] + c->n[i] * wi[2];
    return rf ? 1 : 2;
}

float spm_ref_diel_absorb(float sigma, float d)
{
    return d > 0.0f ? expf(-sigma * d) : 1.0f;
}

spm_u32 spm_ref_disp_bin(spm_u32 h)
{
    return (spm_u32)(((uint64_t)h * SPM_TRUTH_BINS) >> 32);
}
