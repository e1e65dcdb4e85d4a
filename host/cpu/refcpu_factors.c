/* CPU reference, the shade stage's vertex_apply (refcpu_factors.h). */
#include "refcpu_factors.h"

void spm_ref_fetch(const spm_ref_lanes *v, spm_u32 c, float *out)
{
    const float *row = v->base + (size_t)c * v->stride;
    for (int l = 0; l < v->n; l++)
        out[l] = row[v->idx ? v->idx[l] : l];
}

void spm_ref_emit_eye(const spm_ref_lanes *v, spm_u32 col, float cw, const float *W, float *acc)
{
    float X[SPM_REF_MAX_LANES];
    spm_ref_fetch(v, col, X);
    for (int l = 0; l < v->n; l++)
        acc[l] += W[l] * X[l] * cw;
}

void spm_ref_emit_arrive(const spm_ref_lanes *v, spm_u32 col, float cw, float *acc)
{
    float X[SPM_REF_MAX_LANES];
    spm_ref_fetch(v, col, X);
    for (int l = 0; l < v->n; l++)
        acc[l] += X[l] * cw;
}

#define SPM_REF_FACTOR_CASE_(NAME, STORED, ...) \
    case SPM_FK_##NAME:                         \
        spm_ref_factor_##NAME(__VA_ARGS__);     \
        break;
void spm_ref_vertex_apply(int eye, int kind, const spm_vertex *v, const spm_vertex_ext *x,
                          const spm_ref_lanes *ln, float *W, float *acc)
{
    spm_u32 hit = SPM_VX_HIT(*x);
    if (!eye && hit != SPM_NONE)
        spm_ref_emit_arrive(ln, hit, x->hit_c, acc);
    switch (kind) {
        SPM_FACTOR_KINDS(SPM_REF_FACTOR_CASE_, eye, v, x, ln, W, acc)
    default:
        break;
    }
    if (eye && hit != SPM_NONE)
        spm_ref_emit_eye(ln, hit, x->hit_c, W, acc);
}
