/* The CPU reference's dielectric (refcpu_dielectric.h). */
#include "refcpu_dielectric.h"
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include "geometry_vec3.h"
#include "refcpu_bsdf.h"
#include "refcpu_factors.h"

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

/* F(wo.h) D G2 / (4 wo_z) toward unit l (world) and *pdf, the chance of
 * reflecting there: F G1(wo) D / (4 wo_z) */
static float diel_f(const spm_ref_cond *c, float e, const float l[3], float *pdf)
{
    float wi[3] = {v3_dot(l, c->t), v3_dot(l, c->b), v3_dot(l, c->n)}, s[3], h[3];
    for (int i = 0; i < 3; i++)
        s[i] = c->wo[i] + wi[i];
    v3_normalise(h, s);
    float d = spm_ref_ggx_d(c->alpha, h[2]);
    float lo = spm_ref_ggx_lambda(c->alpha, c->wo[2]), li = spm_ref_ggx_lambda(c->alpha, wi[2]);
    float ct;
    float f = spm_ref_diel_fresnel(v3_dot(c->wo, h), e, &ct);
    *pdf = f * d / ((1.0f + lo) * 4.0f * c->wo[2]);
    return f * d / ((1.0f + lo + li) * 4.0f * c->wo[2]);
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

/* ---- the contract (refcpu_bsdf.h; kernels/dielectric.clh's) --------------- */
void spm_ref_begin_DIELECTRIC(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k,
                              int j, spm_ref_walk *w, spm_ref_bsdf *b)
{
    (void)j;
    b->commit = 0;
    float ior = m->p[SPM_DIEL_P_IOR];
    spm_u32 row = w->disperse ? (spm_u32)m->p[SPM_DIEL_P_DISP] : 0u;
    if (row) {
        b->commit = 2; /* its index is the committed bin's */
        if (w->lam == SPM_NONE) {
            w->lam = spm_ref_disp_bin(spm_rng_stratified_u32(k->seed, k->pixel, k->sample,
                                                             SPM_DIM_TYPE(0u, SPM_DIM_DIEL_LAMBDA)));
            b->commit = 1;
        }
        ior = w->disp[(size_t)(row - 1u) * SPM_TRUTH_BINS + w->lam];
    }
    spm_ref_bsdf_frame(h, m->p[SPM_DIEL_P_ALPHA], &b->c);
    float back[3] = {-h->d[0], -h->d[1], -h->d[2]};
    b->eta = v3_dot(back, h->ng) > 0.0f ? ior : 1.0f / ior;
    b->nee = b->c.alpha != 0.0f;
}

/* A join's refraction toward unit l (world, below the surface: wi_z < 0),
 * Walter et al. 2007 with pbrt-v4's adjoint: f |cos_i| =
 *   (1 - F(wo.h)) D(h) G2 (wo.h) |wi.h| / (wo_z (wi.h + wo.h / e)^2) / e^2
 * in radiance mode, without the 1 / e^2 in importance mode (the adjoint
 * BSDF, Veach 1997 5.2: light is not compressed into the denser medium, its
 * importance is), h = unit(wo + e wi) turned to wo's side; *pdf the
 * density of sampling l (spm_ref_pdf_DIELECTRIC's refraction). */
static float diel_ft(const spm_ref_bsdf *b, const float l[3], int mode, float *pdf)
{
    const spm_ref_cond *c = &b->c;
    float wi[3] = {v3_dot(l, c->t), v3_dot(l, c->b), v3_dot(l, c->n)}, s[3], h[3], ct;
    float a = c->alpha, e = b->eta;
    *pdf = 0.0f;
    for (int i = 0; i < 3; i++)
        s[i] = c->wo[i] + wi[i] * e;
    v3_normalise(h, s);
    if (h[2] < 0.0f)
        h[0] = -h[0], h[1] = -h[1], h[2] = -h[2];
    float co = v3_dot(c->wo, h), ci = v3_dot(wi, h), den = co + e * ci;
    if (!(c->wo[2] > 0.0f) || !(wi[2] < 0.0f) || !(co > 0.0f) || !(ci < 0.0f) || den == 0.0f)
        return 0.0f;
    float t = 1.0f - spm_ref_diel_fresnel(co, e, &ct), d = spm_ref_ggx_d(a, h[2]);
    float lo = spm_ref_ggx_lambda(a, c->wo[2]), li = spm_ref_ggx_lambda(a, -wi[2]);
    float jac = e * e * -ci / (den * den); /* |dh / dwi|, times 4 (wo.h) in reflection's terms */
    *pdf = t * d / (1.0f + lo) * co / c->wo[2] * jac;
    float f = t * d / (1.0f + lo + li) * co / c->wo[2] * jac;
    return mode & SPM_REF_IMPORTANCE ? f : f / (e * e);
}

spm_ref_eval spm_ref_eval_DIELECTRIC(const spm_material *m, const spm_ref_bsdf *b,
                                     const spm_ref_hit *h, const float wi[3], int mode)
{
    (void)m;
    float pb;
    if ((mode & SPM_REF_JOIN) && !(v3_dot(wi, b->c.n) > 0.0f)) { /* a join's refraction */
        spm_ref_eval e = spm_ref_eval_value(diel_ft(b, wi, mode, &pb), 1.0f);
        if (h->smooth && !(v3_dot(wi, h->gn) < 0.0f)) /* not through the surface */
            e.f = 0.0f;
        e.pdf = pb;
        return e;
    }
    spm_ref_eval e = spm_ref_eval_value(diel_f(&b->c, b->eta, wi, &pb), 1.0f);
    if (h->smooth && !(v3_dot(wi, b->c.n) > 0.0f)) /* below the shading horizon */
        e.f = 0.0f;
    e.pdf = pb;
    return e;
}

/* reflection F G1 D / (4 wo_z); refraction (Walter et al. 2007)
 * (1 - F) G1 D (wo.h) / wo_z e^2 |wi.h| / (wo.h + e wi.h)^2, h = unit(wo + e wi);
 * from wo on the other side (a reverse density through the refraction,
 * --integrator bdpt's MIS): the same with both mirrored in the surface and
 * the index inverted, as a vertex seen from there would have it */
float spm_ref_pdf_DIELECTRIC(const spm_material *m, const spm_ref_bsdf *b, const float wo_in[3],
                             const float wi_in[3], int mode)
{
    (void)m, (void)mode;
    float a = b->c.alpha, e = b->eta, ct, s[3], h[3];
    float wo[3] = {wo_in[0], wo_in[1], wo_in[2]}, wi[3] = {wi_in[0], wi_in[1], wi_in[2]};
    if (wo[2] < 0.0f)
        wo[2] = -wo[2], wi[2] = -wi[2], e = 1.0f / e;
    if (!(wo[2] > 0.0f) || a == 0.0f)
        return 0.0f;
    float g1 = 1.0f / (1.0f + spm_ref_ggx_lambda(a, wo[2]));
    int refl = wi[2] > 0.0f;
    for (int i = 0; i < 3; i++)
        s[i] = wo[i] + wi[i] * (refl ? 1.0f : e);
    v3_normalise(h, s);
    if (h[2] < 0.0f)
        h[0] = -h[0], h[1] = -h[1], h[2] = -h[2];
    float co = v3_dot(wo, h), ci = v3_dot(wi, h);
    if (refl)
        return spm_ref_diel_fresnel(co, e, &ct) * g1 * spm_ref_ggx_d(a, h[2]) / (4.0f * wo[2]);
    float den = co + e * ci;
    if (!(co > 0.0f) || !(ci < 0.0f) || den == 0.0f)
        return 0.0f;
    return (1.0f - spm_ref_diel_fresnel(co, e, &ct)) * g1 * spm_ref_ggx_d(a, h[2]) * co / wo[2] *
           e * e * fabsf(ci) / (den * den);
}

int spm_ref_sample_DIELECTRIC(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                              const spm_ref_key *k, int j, int mode, spm_ref_bsample *s)
{
    (void)m;
    float wt;
    int ok = spm_ref_diel_lobe(&b->c, b->eta, spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_DIEL_M_A)),
                               spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_DIEL_M_B)),
                               spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_DIEL_CHOICE)), s->wi, &wt,
                               &s->w, &s->pdf);
    if (!ok)
        return 0;
    s->wt = mode == SPM_REF_RADIANCE ? wt : 1.0f;
    s->refract = ok == 2;
    s->inside = v3_dot(s->wi, h->ng) < 0.0f; /* into the back face's side: inside */
    s->cos_lobe = 0.0f;
    return 1;
}

spm_u32 spm_ref_lobe_DIELECTRIC(const spm_material *m, const spm_ref_bsdf *b, float *mean,
                                float *inv_mean)
{
    (void)b;
    return spm_ref_lobe_plain(m, mean, inv_mean); /* its absorption colour; R + T = 1 */
}

spm_u32 spm_ref_record_DIELECTRIC(const spm_material *m, const spm_ref_bsdf *b,
                                  const spm_ref_walk *w, spm_vertex_ext *x)
{
    (void)m;
    /* the length inside comes with the next hit; the committed bin and 1 /
     * its pdf (spm_shared.h SPM_VX_LAMBDA) */
    x->ids = SPM_VX_IDS(SPM_FK_ABSORB, b->commit == 1 ? w->lam : SPM_NONE);
    if (b->commit == 1)
        x->light = (float)SPM_TRUTH_BINS;
    return SPM_NONE;
}

/* The ABSORB factor (refcpu_factors.h): r the absorption sigma, the
 * record's lobe the length d inside (0: none). Camera first acc += W E[e] c;
 * W *= exp(-sigma d); from the light end A = exp(-sigma d) A + E[e] c. */
void spm_ref_factor_ABSORB(int eye, const spm_vertex *v, const spm_vertex_ext *x,
                           const spm_ref_lanes *ln, float *W, float *acc)
{
    float S[SPM_REF_MAX_LANES];
    spm_u32 e = v->ids >> 16;
    if (eye && e != SPM_NONE)
        spm_ref_emit_eye(ln, e, v->c, W, acc);
    if (x->lobe > 0.0f) {
        spm_ref_fetch(ln, v->ids & 0xFFFFu, S);
        for (int l = 0; l < ln->n; l++) {
            if (eye)
                W[l] *= spm_ref_diel_absorb(S[l], x->lobe);
            else
                acc[l] = spm_ref_diel_absorb(S[l], x->lobe) * acc[l];
        }
    }
    if (!eye && e != SPM_NONE)
        spm_ref_emit_arrive(ln, e, v->c, acc);
}
