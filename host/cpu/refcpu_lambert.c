/* The CPU reference's Lambertian type (SPM_MAT_LAMBERT; kernels/lambert.clh
 * has the kernels' own and the formulas): the light sample only, no MIS. */
#include <math.h>
#include "geometry_vec3.h"
#include "refcpu_bsdf.h"
#include "refcpu_factors.h"

void spm_ref_begin_LAMBERT(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k,
                           int j, spm_ref_walk *w, spm_ref_bsdf *b)
{
    (void)m, (void)h, (void)k, (void)j, (void)w;
    b->nee = 1;
}

spm_ref_eval spm_ref_eval_LAMBERT(const spm_material *m, const spm_ref_bsdf *b,
                                  const spm_ref_hit *h, const float wi[3], int mode)
{
    (void)m, (void)b, (void)mode;
    return spm_ref_eval_value(fmaxf(v3_dot(wi, h->n), 0.0f), SPM_PI_F);
}

float spm_ref_pdf_LAMBERT(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],
                          const float wi[3], int mode)
{
    (void)m, (void)b, (void)mode;
    return wo[2] * wi[2] > 0.0f ? fabsf(wi[2]) / SPM_PI_F : 0.0f;
}

int spm_ref_sample_LAMBERT(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                           const spm_ref_key *k, int j, int mode, spm_ref_bsample *s)
{
    (void)m, (void)b, (void)mode;
    float z;
    spm_ref_bounce(h, k, j, s->wi, &z);
    s->w = 1.0f;
    s->wt = 1.0f;
    s->pdf = -1.0f;
    s->cos_lobe = 0.0f;
    s->refract = 0;
    s->inside = 0;
    return 1;
}

spm_u32 spm_ref_lobe_LAMBERT(const spm_material *m, const spm_ref_bsdf *b, float *mean,
                             float *inv_mean)
{
    (void)b;
    return spm_ref_lobe_plain(m, mean, inv_mean);
}

spm_u32 spm_ref_record_LAMBERT(const spm_material *m, const spm_ref_bsdf *b,
                               const spm_ref_walk *w, spm_vertex_ext *x)
{
    (void)m, (void)b, (void)w, (void)x;
    return SPM_NONE;
}

/* The PLAIN factor (refcpu_factors.h): the vertex's colour R; camera first
 * W *= R, acc += W E[e] c; from the light end A = R (E[e] c + A). */
void spm_ref_factor_PLAIN(int eye, const spm_vertex *v, const spm_vertex_ext *x,
                          const spm_ref_lanes *ln, float *W, float *acc)
{
    (void)x;
    float R[SPM_REF_MAX_LANES];
    spm_u32 r = v->ids & 0xFFFFu, e = v->ids >> 16;
    spm_ref_fetch(ln, r, R);
    if (eye) {
        for (int l = 0; l < ln->n; l++)
            W[l] *= R[l];
        if (e != SPM_NONE)
            spm_ref_emit_eye(ln, e, v->c, W, acc);
        return;
    }
    if (e != SPM_NONE)
        spm_ref_emit_arrive(ln, e, v->c, acc);
    for (int l = 0; l < ln->n; l++)
        acc[l] *= R[l];
}
