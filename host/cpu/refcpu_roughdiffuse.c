/* The CPU reference's rough diffuse type (SPM_MAT_ROUGHDIFFUSE, EON;
 * kernels/roughdiffuse.clh has the kernels' own and the formulas), in the
 * kernel's operation order. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu_bsdf.h"

#define EON_C1 0.287793409f
#define EON_C2 0.0724882125f

static float clamp01(float x)
{
    return fminf(fmaxf(x, 0.0f), 1.0f);
}

/* FON's directional albedo E(mu) */
static float eon_albedo(float mu, float r)
{
    float a = 1.0f / (1.0f + EON_C1 * r);
    float c = fminf(fmaxf(mu, 1e-7f), 1.0f);
    float s = sqrtf(fmaxf(1.0f - c * c, 0.0f));
    float g = s * (acosf(c) - s * c) + 2.0f / 3.0f * (s / c * (1.0f - s * s * s) - s);
    return a + r * a * g / SPM_PI_F;
}

/* the fitted LTC matrix's a, b, c, d */
static void eon_ltc(float mu, float r, float m[4])
{
    m[0] = 1.0f + r * (0.303392f + (-0.518982f + 0.111709f * mu) * mu +
                       (-0.276266f + 0.335918f * mu) * r);
    m[1] = r * (-1.16407f + 1.15859f * mu + (0.150815f - 0.150105f * mu) * r) /
           (mu * mu * mu - 1.43545f);
    m[2] = 1.0f + (0.20013f + (-0.506373f + 0.261777f * mu) * mu) * r;
    m[3] = (0.540852f + (-1.01625f + 0.475392f * mu) * mu) * r /
           (-1.0743f + mu * (0.0725628f + mu));
}

static void eon_azimuth(const float wo[3], float x[2])
{
    float l2 = wo[0] * wo[0] + wo[1] * wo[1];
    if (!(l2 > 0.0f)) {
        x[0] = 1.0f, x[1] = 0.0f;
        return;
    }
    float inv = 1.0f / sqrtf(l2);
    x[0] = wo[0] * inv, x[1] = wo[1] * inv;
}

static float eon_uniform_prob(float mu, float r)
{
    return powf(r, 0.1f) * (0.162925f + mu * (-0.372058f + (0.538233f - 0.290822f * mu) * mu));
}

static float eon_cltc_pdf(const float wo[3], const float wi[3], float r)
{
    float m[4], x[2];
    eon_ltc(clamp01(wo[2]), r, m);
    eon_azimuth(wo, x);
    float wx = x[0] * wi[0] + x[1] * wi[1], wy = -x[1] * wi[0] + x[0] * wi[1];
    float det = m[2] * (m[0] - m[1] * m[3]);
    float hx = m[2] * (wx - m[1] * wi[2]), hy = (m[0] - m[1] * m[3]) * wy;
    float hz = -m[2] * (m[3] * wx - m[0] * wi[2]);
    float l2 = hx * hx + hy * hy + hz * hz;
    float k = 0.5f * (1.0f + 1.0f / sqrtf(m[3] * m[3] + 1.0f));
    float q = det / l2;
    return q * q * fmaxf(hz, 0.0f) / (SPM_PI_F * k);
}

static float eon_pdf(const float wo[3], const float wi[3], float r)
{
    float pu = eon_uniform_prob(clamp01(wo[2]), r);
    return pu / (2.0f * SPM_PI_F) + (1.0f - pu) * eon_cltc_pdf(wo, wi, r);
}

static void eon_cltc_sample(const float wo[3], float r, float u, float v, float out[3])
{
    float m[4], a[2];
    eon_ltc(clamp01(wo[2]), r, m);
    float rad = sqrtf(v), phi = 2.0f * SPM_PI_F * u;
    float x = rad * cosf(phi), y = rad * sinf(phi);
    float k = 0.5f * (1.0f + 1.0f / sqrtf(m[3] * m[3] + 1.0f));
    float e = sqrtf(fmaxf(1.0f - y * y, 0.0f));
    x = -(e + (x - e) * k);
    float hz = sqrtf(fmaxf(1.0f - (x * x + y * y), 0.0f));
    float wx = m[0] * x + m[1] * hz, wy = m[2] * y, wz = m[3] * x + hz;
    eon_azimuth(wo, a);
    float w[3] = {a[0] * wx - a[1] * wy, a[1] * wx + a[0] * wy, wz};
    v3_normalise(out, w);
}

/* the picked term's f pi without its colour */
static float eon_term(const spm_ref_bsdf *b, const float wo[3], const float wi[3])
{
    float r = b->c.alpha;
    if (b->lobe)
        return fmaxf(1.0f - b->eta, 0.0f) * fmaxf(1.0f - eon_albedo(wi[2], r), 0.0f) /
               (1.0f - b->pdf);
    float s = v3_dot(wi, wo) - wi[2] * wo[2];
    float sot = s > 0.0f ? s / fmaxf(wi[2], wo[2]) : s;
    return (1.0f + r * sot) / (1.0f + EON_C1 * r);
}

static void to_local(const spm_ref_cond *c, const float w[3], float l[3])
{
    l[0] = v3_dot(w, c->t);
    l[1] = v3_dot(w, c->b);
    l[2] = v3_dot(w, c->n);
}

/* ---- the contract (refcpu_bsdf.h) ---------------------------------------- */
void spm_ref_begin_ROUGHDIFFUSE(const spm_material *m, const spm_ref_hit *h,
                                const spm_ref_key *k, int j, spm_ref_walk *w, spm_ref_bsdf *b)
{
    (void)w;
    float r = m->p[SPM_ROUGH_P_R];
    spm_ref_bsdf_frame(h, r, &b->c);
    b->nee = 1;
    b->lobe = 0;
    b->ps = 1.0f;
    b->w = m->mean;
    if (r == 0.0f)
        return;
    float mu = b->c.wo[2];
    b->eta = eon_albedo(mu, r);
    b->pdf = (1.0f + EON_C2 * r) / (1.0f + EON_C1 * r);
    float rm = m->mean;
    float ss = rm * b->eta;
    float ms = rm * rm * b->pdf / (1.0f - rm * (1.0f - b->pdf)) * (1.0f - b->eta);
    b->w = mu > 0.0f ? ss + ms : 0.0f;
    float pm = b->w > 0.0f ? ms / b->w : 0.0f;
    b->lobe = spm_ref_rnd(k, SPM_DIM_TYPE(j, 0)) < pm;
    b->ps = b->lobe ? pm : 1.0f - pm;
}

spm_ref_eval spm_ref_eval_ROUGHDIFFUSE(const spm_material *m, const spm_ref_bsdf *b,
                                       const spm_ref_hit *h, const float wi[3], int mode)
{
    (void)m, (void)mode;
    float ci = fmaxf(v3_dot(wi, h->n), 0.0f);
    if (b->c.alpha == 0.0f)
        return spm_ref_eval_value(ci, SPM_PI_F);
    if (!(b->w > 0.0f) || !(ci > 0.0f))
        return spm_ref_eval_value(0.0f, 1.0f);
    float l[3];
    to_local(&b->c, wi, l);
    spm_ref_eval e = spm_ref_eval_value(eon_term(b, b->c.wo, l) * ci, SPM_PI_F);
    e.div = b->ps;
    return e;
}

float spm_ref_pdf_ROUGHDIFFUSE(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],
                               const float wi[3], int mode)
{
    (void)b, (void)mode;
    float r = m->p[SPM_ROUGH_P_R];
    if (r == 0.0f)
        return wo[2] * wi[2] > 0.0f ? fabsf(wi[2]) / SPM_PI_F : 0.0f;
    return wo[2] > 0.0f && wi[2] > 0.0f ? eon_pdf(wo, wi, r) : 0.0f;
}

int spm_ref_sample_ROUGHDIFFUSE(const spm_material *m, const spm_ref_bsdf *b,
                                const spm_ref_hit *h, const spm_ref_key *k, int j, int mode,
                                spm_ref_bsample *s)
{
    (void)m, (void)mode;
    s->wt = 1.0f;
    s->pdf = -1.0f;
    s->cos_lobe = 0.0f;
    s->refract = 0;
    s->inside = 0;
    float r = b->c.alpha;
    if (r == 0.0f) {
        float z;
        spm_ref_bounce(h, k, j, s->wi, &z);
        s->w = 1.0f;
        return 1;
    }
    if (!(b->w > 0.0f))
        return 0;
    float u = spm_ref_rnd(k, SPM_DIM_VERTEX(j) + SPM_DIM_DIR_A);
    float v = spm_ref_rnd(k, SPM_DIM_VERTEX(j) + SPM_DIM_DIR_B);
    const float *wo = b->c.wo;
    float il[3];
    if (spm_ref_rnd(k, SPM_DIM_TYPE(j, 1)) < eon_uniform_prob(clamp01(wo[2]), r)) {
        float st = sqrtf(fmaxf(1.0f - u * u, 0.0f)), phi = 2.0f * SPM_PI_F * v;
        il[0] = st * cosf(phi), il[1] = st * sinf(phi), il[2] = u;
    } else {
        eon_cltc_sample(wo, r, u, v, il);
    }
    if (!(il[2] > 0.0f))
        return 0;
    for (int i = 0; i < 3; i++)
        s->wi[i] = b->c.t[i] * il[0] + b->c.b[i] * il[1] + b->c.n[i] * il[2];
    s->w = eon_term(b, wo, il) * il[2] / SPM_PI_F / eon_pdf(wo, il, r) / b->ps;
    return 1;
}

spm_u32 spm_ref_lobe_ROUGHDIFFUSE(const spm_material *m, const spm_ref_bsdf *b, float *mean,
                                  float *inv_mean)
{
    if (b->c.alpha == 0.0f)
        return spm_ref_lobe_plain(m, mean, inv_mean);
    float q = fminf(1.0f, b->w);
    *mean = q;
    *inv_mean = q > 0.0f ? 1.0f / q : 0.0f;
    return b->lobe ? m->col2 : m->refl;
}

spm_u32 spm_ref_record_ROUGHDIFFUSE(const spm_material *m, const spm_ref_bsdf *b,
                                    const spm_ref_walk *w, spm_vertex_ext *x)
{
    (void)m, (void)b, (void)w, (void)x;
    return SPM_NONE;
}
