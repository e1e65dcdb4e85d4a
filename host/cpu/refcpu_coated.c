/* The CPU reference's coated material (refcpu_coated.h). */
#include "refcpu_coated.h"
#include <math.h>
#include "geometry_vec3.h"

float spm_ref_coat_fresnel(float eta, float cin)
{
    /* sin^2 t = (1 - c^2) / eta^2 (>= 1: total internal reflection),
     * rs = (c - eta ct) / (c + eta ct), rp = (eta c - ct) / (eta c + ct),
     * F = (rs^2 + rp^2) / 2 */
    float c = fminf(fmaxf(cin, 0.0f), 1.0f);
    float s2 = (1.0f - c * c) / (eta * eta);
    if (s2 >= 1.0f)
        return 1.0f;
    float ct = sqrtf(1.0f - s2);
    float rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 0.5f * (rs * rs + rp * rp);
}

void spm_ref_coat_make(const spm_ref_cond *f, const spm_material *m, float u_lobe, float u1,
                       float u2, spm_ref_coat *c)
{
    c->f = *f;
    c->eta = m->p[SPM_COAT_P_ETA];
    float fo = spm_ref_coat_fresnel(c->eta, c->f.wo[2]);
    /* ps = Fo s / (Fo s + (1 - Fo)(1 - s)), 1 when both terms are 0 */
    float a = fo * m->p[SPM_COAT_P_SPEC], b = (1.0f - fo) * (1.0f - m->p[SPM_COAT_P_SPEC]);
    c->ps = a + b > 0.0f ? a / (a + b) : 1.0f;
    c->spec = u_lobe < c->ps;
    c->pdf = 0.0f;
    c->up = 1;
    c->dir[0] = c->dir[1] = c->dir[2] = 0.0f;
    if (!c->spec) { /* diffuse: (1 - Fo) kd / (1 - ps), 1 - F(cos_i) once drawn */
        c->w = (1.0f - fo) * m->p[SPM_COAT_P_KD] / (1.0f - c->ps);
        return;
    }
    float cm, g;
    c->up = spm_ref_cond_lobe(&c->f, u1, u2, c->dir, &cm, &g, &c->pdf);
    if (!c->up) { /* below the surface: weight 0 */
        c->w = 0.0f;
        c->pdf = 0.0f;
        return;
    }
    /* smooth: Fo / ps (cm = wo.n, g = 1); rough: F(wo.m) G2 / G1(wo) / ps */
    c->w = c->f.alpha == 0.0f ? fo / c->ps : spm_ref_coat_fresnel(c->eta, cm) * g / c->ps;
}

float spm_ref_coat_light(const spm_ref_coat *c, const float l[3], float cos_i, float pick_pdf,
                         float d2c, float area, float cos_e)
{
    if (c->spec) {
        float ch;
        float f = spm_ref_cond_light(&c->f, l, pick_pdf, d2c, area, cos_e, &ch);
        return spm_ref_coat_fresnel(c->eta, ch) * f / c->ps;
    }
    float ci = fabsf(cos_i);
    return ci / SPM_PI_F * (1.0f - spm_ref_coat_fresnel(c->eta, ci)) * c->w;
}
