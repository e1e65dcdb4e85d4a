/* The CPU reference's material dispatch (refcpu_bsdf.h): one switch per
 * call, its cases generated from include/spm_types.h. */
#include "refcpu_bsdf.h"
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu_shading.h"

#define SPM_EMITTER_TYPE(NAME, ...)

void spm_ref_begin(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k, int j,
                   spm_ref_walk *w, spm_ref_bsdf *b)
{
    b->nee = 0;
    switch (SPM_MAT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...) \
    case SPM_MAT_##NAME: spm_ref_begin_##NAME(m, h, k, j, w, b); return;
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
    default:
        return;
    }
}

spm_ref_eval spm_ref_eval_bsdf(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                               const float wi[3], int mode)
{
    switch (SPM_MAT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...) \
    case SPM_MAT_##NAME: return spm_ref_eval_##NAME(m, b, h, wi, mode);
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
    default:
        return spm_ref_eval_value(0.0f, 1.0f);
    }
}

float spm_ref_pdf(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],
                  const float wi[3], int mode)
{
    switch (SPM_MAT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...) \
    case SPM_MAT_##NAME: return spm_ref_pdf_##NAME(m, b, wo, wi, mode);
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
    default:
        return 0.0f;
    }
}

int spm_ref_sample(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                   const spm_ref_key *k, int j, int mode, spm_ref_bsample *s)
{
    switch (SPM_MAT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...) \
    case SPM_MAT_##NAME: return spm_ref_sample_##NAME(m, b, h, k, j, mode, s);
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
    default:
        return 0;
    }
}

spm_u32 spm_ref_lobe(const spm_material *m, const spm_ref_bsdf *b, float *mean, float *inv_mean)
{
    switch (SPM_MAT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...) \
    case SPM_MAT_##NAME: return spm_ref_lobe_##NAME(m, b, mean, inv_mean);
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
    default:
        *mean = 0.0f;
        *inv_mean = 0.0f;
        return SPM_NONE;
    }
}

spm_u32 spm_ref_record(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_walk *w,
                       spm_vertex_ext *x)
{
    switch (SPM_MAT_TAG(*m)) {
#define SPM_MATERIAL_TYPE(NAME, ...) \
    case SPM_MAT_##NAME: return spm_ref_record_##NAME(m, b, w, x);
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
    default:
        return SPM_NONE;
    }
}

spm_u32 spm_ref_lobe_plain(const spm_material *m, float *mean, float *inv_mean)
{
    *mean = m->mean;
    *inv_mean = m->inv_mean;
    return m->refl;
}

void spm_ref_bounce(const spm_ref_hit *h, const spm_ref_key *k, int j, float out[3], float *z)
{
    spm_u32 dim = SPM_DIM_VERTEX(j);
    float phi = 2.0f * SPM_PI_F * spm_ref_rnd(k, dim + SPM_DIM_DIR_A);
    float v = spm_ref_rnd(k, dim + SPM_DIM_DIR_B);
    float sr = sqrtf(v);
    float x = cosf(phi) * sr, y = sinf(phi) * sr;
    *z = sqrtf(1.0f - v);
    float c[3];
    v3_cross(c, h->n, h->t);
    for (int i = 0; i < 3; i++)
        out[i] = h->t[i] * x + c[i] * y + h->n[i] * *z;
}

void spm_ref_bsdf_frame(const spm_ref_hit *h, float alpha, spm_ref_cond *c)
{
    spm_ref_cond_frame(h->n, h->t, h->d, alpha, c);
}
