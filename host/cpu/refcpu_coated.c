/* The CPU reference's coated material (refcpu_coated.h). */
#include "refcpu_coated.h"
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu_bsdf.h"

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

/* ---- the contract (refcpu_bsdf.h; kernels/coated.clh's) ------------------- */
void spm_ref_begin_COATED(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k,
                          int j, spm_ref_walk *w, spm_ref_bsdf *b)
{
    (void)w;
    spm_ref_cond f;
    spm_ref_coat co;
    spm_ref_bsdf_frame(h, m->p[SPM_COAT_P_ALPHA], &f);
    spm_ref_coat_make(&f, m, spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_COAT_LOBE)),
                      spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_COAT_M_A)),
                      spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_COAT_M_B)), &co);
    b->c = co.f;
    b->eta = co.eta;
    b->ps = co.ps;
    b->w = co.w;
    b->pdf = co.pdf;
    b->lobe = co.spec;
    for (int i = 0; i < 3; i++)
        b->dir[i] = co.dir[i];
    b->nee = !(co.spec && co.f.alpha == 0.0f); /* none on a delta lobe */
}

spm_ref_eval spm_ref_eval_COATED(const spm_material *m, const spm_ref_bsdf *b,
                                 const spm_ref_hit *h, const float wi[3], int mode)
{
    (void)m, (void)mode;
    if (!b->lobe) {
        float ci = fmaxf(v3_dot(wi, h->n), 0.0f);
        return spm_ref_eval_value(ci / SPM_PI_F * (1.0f - spm_ref_coat_fresnel(b->eta, ci)) * b->w,
                                  1.0f);
    }
    float pb, ch;
    spm_ref_eval e = spm_ref_eval_value(spm_ref_cond_f(&b->c, wi, &pb, &ch), 1.0f);
    if (h->smooth && !(v3_dot(wi, b->c.n) > 0.0f)) /* below the shading horizon */
        e.f = 0.0f;
    e.k = spm_ref_coat_fresnel(b->eta, ch);
    e.div = b->ps;
    e.pdf = pb;
    return e;
}

float spm_ref_pdf_COATED(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],
                         const float wi[3], int mode)
{
    (void)mode;
    if (!(wo[2] > 0.0f) || !(wi[2] > 0.0f))
        return 0.0f;
    float fo = spm_ref_coat_fresnel(b->eta, wo[2]), s = m->p[SPM_COAT_P_SPEC];
    float a = fo * s, bb = (1.0f - fo) * (1.0f - s), ps = a + bb > 0.0f ? a / (a + bb) : 1.0f;
    float spec = 0.0f;
    if (b->c.alpha > 0.0f) { /* G1(wo) D(h) / (4 wo_z) */
        float sum[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]}, hv[3];
        v3_normalise(hv, sum);
        spec = spm_ref_ggx_d(b->c.alpha, hv[2]) /
               ((1.0f + spm_ref_ggx_lambda(b->c.alpha, wo[2])) * 4.0f * wo[2]);
    }
    return ps * spec + (1.0f - ps) * wi[2] / SPM_PI_F;
}

int spm_ref_sample_COATED(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                          const spm_ref_key *k, int j, int mode, spm_ref_bsample *s)
{
    (void)m, (void)mode;
    s->wt = 1.0f;
    s->refract = 0;
    s->inside = 0;
    s->cos_lobe = 0.0f;
    if (b->lobe) { /* its hit counted at the next vertex */
        for (int i = 0; i < 3; i++)
            s->wi[i] = b->dir[i];
        s->w = 1.0f;
        s->pdf = b->pdf;
        return 1;
    }
    float z; /* the diffuse lobe's transmission out: 1 - F(cos_i) */
    spm_ref_bounce(h, k, j, s->wi, &z);
    s->w = 1.0f - spm_ref_coat_fresnel(b->eta, z);
    s->pdf = -1.0f;
    return 1;
}

/* the lobe's colour; survival q = min(1, w mean), weight w / q */
spm_u32 spm_ref_lobe_COATED(const spm_material *m, const spm_ref_bsdf *b, float *mean,
                            float *inv_mean)
{
    float q = fminf(1.0f, b->w * (b->lobe ? 1.0f : m->mean));
    *mean = q;
    *inv_mean = q > 0.0f ? b->w / q : 0.0f;
    return b->lobe ? m->col2 : m->refl;
}

spm_u32 spm_ref_record_COATED(const spm_material *m, const spm_ref_bsdf *b,
                              const spm_ref_walk *w, spm_vertex_ext *x)
{
    (void)m, (void)b, (void)w, (void)x;
    return SPM_NONE;
}
