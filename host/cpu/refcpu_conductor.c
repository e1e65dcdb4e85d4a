/* The CPU reference's conductor (refcpu_conductor.h). */
#include "refcpu_conductor.h"
#include <float.h>
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu_bsdf.h"
#include "refcpu_factors.h"

void spm_ref_cond_make(const spm_tri *tri, const float d[3], float alpha, spm_ref_cond *c)
{
    float back[3] = {-d[0], -d[1], -d[2]};
    for (int i = 0; i < 3; i++)
        c->n[i] = tri->n[i], c->t[i] = tri->t[i], c->back[i] = back[i];
    if (v3_dot(c->n, back) < 0.0f)
        c->n[0] = -c->n[0], c->n[1] = -c->n[1], c->n[2] = -c->n[2];
    v3_cross(c->b, c->n, c->t);
    c->wo[0] = v3_dot(back, c->t);
    c->wo[1] = v3_dot(back, c->b);
    c->wo[2] = v3_dot(back, c->n);
    c->alpha = alpha;
}

/* Smith's Lambda(w) = (-1 + sqrt(1 + a^2 tan^2)) / 2, tan^2 = (1 - z^2) / z^2 */
static float lambda(float a, float z)
{
    float z2 = z * z;
    float t2 = fmaxf(1.0f - z2, 0.0f) / z2;
    return 0.5f * (-1.0f + sqrtf(1.0f + a * a * t2));
}

/* GGX D(m) = a^2 / (pi (m_z^2 (a^2 - 1) + 1)^2) */
static float ggx_d(float a, float mz)
{
    float a2 = a * a;
    float t = mz * mz * (a2 - 1.0f) + 1.0f;
    return a2 / (SPM_PI_F * t * t);
}

float spm_ref_cond_power(float a, float b)
{
    float a2 = a * a, b2 = b * b;
    if (isinf(a2)) /* a strategy alone (refcpu_trace.c mis_pick) */
        return 1.0f;
    return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

/* D G2 / (4 wo_z) toward unit l (world) and *pdf, the visible normals'
 * G1(wo) D / (4 wo_z); *cos_h = wo.h */
float spm_ref_cond_f(const spm_ref_cond *c, const float l[3], float *pdf, float *cos_h)
{
    float wi[3] = {v3_dot(l, c->t), v3_dot(l, c->b), v3_dot(l, c->n)}, s[3], h[3];
    for (int i = 0; i < 3; i++)
        s[i] = c->wo[i] + wi[i];
    v3_normalise(h, s);
    float d = ggx_d(c->alpha, h[2]);
    float lo = lambda(c->alpha, c->wo[2]), li = lambda(c->alpha, wi[2]);
    *cos_h = v3_dot(c->wo, h);
    *pdf = d / ((1.0f + lo) * 4.0f * c->wo[2]);
    return d / ((1.0f + lo + li) * 4.0f * c->wo[2]);
}

float spm_ref_cond_light(const spm_ref_cond *c, const float l[3], float pick_pdf, float d2c,
                         float area, float cos_e, float *cos_h)
{
    float pb;
    float f = spm_ref_cond_f(c, l, &pb, cos_h);
    float pl = pick_pdf * d2c / (area * cos_e);
    return f * spm_ref_cond_power(pl, pb);
}

/* Heitz 2018's visible normal: stretch wo by a, a point on the projected
 * half disc squeezed by s = (1 + vh_z) / 2, lifted, unstretched. */
static void vndf(const float wo[3], float a, float u1, float u2, float m[3])
{
    float v[3] = {a * wo[0], a * wo[1], wo[2]}, vh[3], t1[3], t2[3];
    v3_normalise(vh, v);
    float l2 = vh[0] * vh[0] + vh[1] * vh[1];
    float il = l2 > 0.0f ? 1.0f / sqrtf(l2) : 0.0f;
    if (l2 > 0.0f)
        t1[0] = -vh[1] * il, t1[1] = vh[0] * il, t1[2] = 0.0f;
    else
        t1[0] = 1.0f, t1[1] = 0.0f, t1[2] = 0.0f;
    v3_cross(t2, vh, t1);
    float r = sqrtf(u1), phi = 2.0f * SPM_PI_F * u2;
    float p1 = r * cosf(phi), p2 = r * sinf(phi);
    float s = 0.5f * (1.0f + vh[2]);
    p2 = (1.0f - s) * sqrtf(1.0f - p1 * p1) + s * p2;
    float pz = sqrtf(fmaxf(0.0f, 1.0f - p1 * p1 - p2 * p2));
    float nh[3];
    for (int i = 0; i < 3; i++)
        nh[i] = t1[i] * p1 + t2[i] * p2 + vh[i] * pz;
    float st[3] = {a * nh[0], a * nh[1], fmaxf(0.0f, nh[2])};
    v3_normalise(m, st);
}

int spm_ref_cond_lobe(const spm_ref_cond *c, float u1, float u2, float out[3], float *cos_m,
                      float *w, float *pdf)
{
    float wi[3];
    if (c->alpha == 0.0f) { /* the mirror: wi = 2 (wo.n) n - wo */
        *cos_m = c->wo[2];
        for (int i = 0; i < 3; i++)
            out[i] = c->n[i] * (2.0f * c->wo[2]) - c->back[i];
        *w = 1.0f;
        *pdf = 0.0f;
        return 1;
    }
    float m[3];
    vndf(c->wo, c->alpha, u1, u2, m);
    float cm = v3_dot(c->wo, m);
    for (int i = 0; i < 3; i++)
        wi[i] = m[i] * (2.0f * cm) - c->wo[i];
    *cos_m = cm;
    if (!(wi[2] > 0.0f) || !(cm > 0.0f))
        return 0;
    float lo = lambda(c->alpha, c->wo[2]), li = lambda(c->alpha, wi[2]);
    *w = (1.0f + lo) / (1.0f + lo + li);
    *pdf = ggx_d(c->alpha, m[2]) / ((1.0f + lo) * 4.0f * c->wo[2]);
    for (int i = 0; i < 3; i++)
        out[i] = c->t[i] * wi[0] + c->b[i] * wi[1] + c->n[i] * wi[2];
    return 1;
}

float spm_ref_cond_fresnel(float eta, float k, float cin)
{
    /* s2 = 1 - c^2, t0 = eta^2 - k^2 - s2, a2b2 = sqrt(t0^2 + 4 eta^2 k^2),
     * a = sqrt((a2b2 + t0) / 2), Rs = (a2b2 + c^2 - 2ac) / (a2b2 + c^2 + 2ac),
     * Rp = Rs (c^2 a2b2 + s2^2 - 2ac s2) / (c^2 a2b2 + s2^2 + 2ac s2) */
    float c = fminf(fmaxf(cin, 0.0f), 1.0f);
    float c2 = c * c, s2 = 1.0f - c2;
    float t0 = eta * eta - k * k - s2;
    float a2b2 = sqrtf(t0 * t0 + 4.0f * eta * eta * k * k);
    float a = sqrtf(fmaxf(0.5f * (a2b2 + t0), 0.0f));
    float t1 = a2b2 + c2, t2 = 2.0f * c * a;
    float rs = (t1 - t2) / fmaxf(t1 + t2, FLT_MIN);
    float t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
    float rp = rs * (t3 - t4) / fmaxf(t3 + t4, FLT_MIN);
    return 0.5f * (rs + rp);
}

/* The FRESNEL factor (refcpu_factors.h): r the eta colour, the record's
 * colour word k; toward the eye the vertex sends F(light) E[e] c + F(lobe) A,
 * A the light arriving along its sampled ray. Camera first
 * acc += W F(light) E[e] c; W *= F(lobe); from the light end
 * A = F(lobe) A + F(light) E[e] c. Each walk in its own order of roundings
 * (the kernels' too). */
void spm_ref_factor_FRESNEL(int eye, const spm_vertex *v, const spm_vertex_ext *x,
                            const spm_ref_lanes *ln, float *W, float *acc)
{
    float eta[SPM_REF_MAX_LANES], k[SPM_REF_MAX_LANES], E[SPM_REF_MAX_LANES];
    spm_u32 e = v->ids >> 16;
    spm_ref_fetch(ln, v->ids & 0xFFFFu, eta);
    spm_ref_fetch(ln, SPM_VX_COL(*x), k);
    if (e != SPM_NONE)
        spm_ref_fetch(ln, e, E);
    for (int l = 0; l < ln->n; l++) {
        if (eye) {
            if (e != SPM_NONE)
                acc[l] += W[l] * spm_ref_cond_fresnel(eta[l], k[l], x->light) * E[l] * v->c;
            W[l] *= spm_ref_cond_fresnel(eta[l], k[l], x->lobe);
        } else {
            acc[l] = spm_ref_cond_fresnel(eta[l], k[l], x->lobe) * acc[l];
            if (e != SPM_NONE)
                acc[l] += spm_ref_cond_fresnel(eta[l], k[l], x->light) * E[l] * v->c;
        }
    }
}

/* GGX's pieces for the dielectric's lobe (refcpu_dielectric.c) */
float spm_ref_ggx_lambda(float a, float z)
{
    return lambda(a, z);
}

float spm_ref_ggx_d(float a, float mz)
{
    return ggx_d(a, mz);
}

void spm_ref_ggx_vndf(const float wo[3], float a, float u1, float u2, float m[3])
{
    vndf(wo, a, u1, u2, m);
}

/* ---- the contract (refcpu_bsdf.h; kernels/conductor.clh's) ---------------- */
void spm_ref_begin_CONDUCTOR(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k,
                             int j, spm_ref_walk *w, spm_ref_bsdf *b)
{
    (void)k, (void)j, (void)w;
    spm_ref_bsdf_frame(h, m->p[SPM_COND_P_ALPHA], &b->c);
    b->nee = b->c.alpha != 0.0f;
}

spm_ref_eval spm_ref_eval_CONDUCTOR(const spm_material *m, const spm_ref_bsdf *b,
                                    const spm_ref_hit *h, const float wi[3], int mode)
{
    (void)m, (void)mode;
    float pb, ch;
    spm_ref_eval e = spm_ref_eval_value(spm_ref_cond_f(&b->c, wi, &pb, &ch), 1.0f);
    (void)h;
    if (!(v3_dot(wi, b->c.n) > 0.0f)) /* below the (shading) horizon, a join through the surface */
        e.f = 0.0f;
    e.pdf = pb;
    e.cos_light = ch;
    return e;
}

float spm_ref_pdf_CONDUCTOR(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],
                            const float wi[3], int mode)
{
    (void)m, (void)mode;
    float a = b->c.alpha, s[3], h[3];
    if (!(wo[2] > 0.0f) || !(wi[2] > 0.0f) || a == 0.0f)
        return 0.0f;
    for (int i = 0; i < 3; i++)
        s[i] = wo[i] + wi[i];
    v3_normalise(h, s);
    return ggx_d(a, h[2]) / ((1.0f + lambda(a, wo[2])) * 4.0f * wo[2]);
}

int spm_ref_sample_CONDUCTOR(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                             const spm_ref_key *k, int j, int mode, spm_ref_bsample *s)
{
    (void)m, (void)h, (void)mode;
    s->wt = 1.0f;
    s->refract = 0;
    s->inside = 0;
    return spm_ref_cond_lobe(&b->c, spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_COND_M_A)),
                             spm_ref_rnd(k, SPM_DIM_TYPE(j, SPM_DIM_COND_M_B)), s->wi,
                             &s->cos_lobe, &s->w, &s->pdf);
}

spm_u32 spm_ref_lobe_CONDUCTOR(const spm_material *m, const spm_ref_bsdf *b, float *mean,
                               float *inv_mean)
{
    (void)b;
    return spm_ref_lobe_plain(m, mean, inv_mean); /* eta as the colour */
}

spm_u32 spm_ref_record_CONDUCTOR(const spm_material *m, const spm_ref_bsdf *b,
                                 const spm_ref_walk *w, spm_vertex_ext *x)
{
    (void)b, (void)w;
    x->ids = SPM_VX_IDS(SPM_FK_FRESNEL, m->col2);
    return m->col2;
}
