/* CPU reference, the diffuse fluorescent types (SPM_MAT_FLUOR,
 * SPM_MAT_DONALDSON; kernels/fluor.clh has the kernels' own). The shade
 * stage's REEMIT factor: a colour from the table's fluor_first on is the
 * diagonal R of a re-radiation matrix M (modes.h: the colour's diagonal and
 * its fluorescence block), which mixes lanes, so a path with such a vertex
 * is walked from the light end (refcpu_shade.c, docs/METHODS.md
 * "Fluorescence"): A = M (E[e] c + A), M x = R x lane by lane plus the
 * block's columns weighted by x. Plain scalar float loops, uncontracted sums
 * in lane order (the kernel fuses them). */
#include "refcpu.h"
#include "refcpu_bsdf.h"
#include "refcpu_factors.h"
#include <string.h>

int spm_ref_kind_of(int kind, spm_u32 r, const spm_ref_lanes *ln)
{
    return kind == SPM_FK_PLAIN && ln->fluor && r >= (spm_u32)ln->fluor->fluor_first
               ? SPM_FK_REEMIT
               : kind;
}

/* camera first (never reached: such a path is walked from the light end)
 * the diagonal alone */
void spm_ref_factor_REEMIT(int eye, const spm_vertex *v, const spm_vertex_ext *x,
                           const spm_ref_lanes *ln, float *W, float *acc)
{
    const spm_shade_table *tab = ln->fluor;
    if (eye || !tab) {
        spm_ref_factor_PLAIN(eye, v, x, ln, W, acc);
        return;
    }
    float X[SPM_REF_MAX_LANES], R[SPM_REF_MAX_LANES];
    const size_t st = (size_t)tab->stride;
    spm_u32 r = v->ids & 0xFFFFu, e = v->ids >> 16;
    const float *blk = tab->rows + (size_t)tab->ncolours * st +
                       (size_t)(r - (spm_u32)tab->fluor_first) * st * st;
    if (e != SPM_NONE)
        spm_ref_emit_arrive(ln, e, v->c, acc);
    spm_ref_fetch(ln, r, R);
    memcpy(X, acc, (size_t)ln->n * sizeof *X);
    for (int l = 0; l < ln->n; l++)
        acc[l] = X[l] * R[l];
    for (int i = 0; i < ln->n; i++)
        for (int o = 0; o < ln->n; o++)
            acc[o] += blk[(size_t)i * st + (size_t)o] * X[i];
}

/* The trace stage: the diffuse fluorescent types take the Lambertian's lobe
 * (refcpu_lambert.c); their diagonal colour marks the vertex for the walk
 * above. */
#define SPM_REF_AS_LAMBERT(NAME)                                                                 \
    void spm_ref_begin_##NAME(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k, \
                              int j, spm_ref_walk *w, spm_ref_bsdf *b)                           \
    {                                                                                            \
        spm_ref_begin_LAMBERT(m, h, k, j, w, b);                                                 \
    }                                                                                            \
    spm_ref_eval spm_ref_eval_##NAME(const spm_material *m, const spm_ref_bsdf *b,               \
                                     const spm_ref_hit *h, const float wi[3], int mode)          \
    {                                                                                            \
        return spm_ref_eval_LAMBERT(m, b, h, wi, mode);                                          \
    }                                                                                            \
    float spm_ref_pdf_##NAME(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],    \
                             const float wi[3], int mode)                                        \
    {                                                                                            \
        return spm_ref_pdf_LAMBERT(m, b, wo, wi, mode);                                          \
    }                                                                                            \
    int spm_ref_sample_##NAME(const spm_material *m, const spm_ref_bsdf *b,                      \
                              const spm_ref_hit *h, const spm_ref_key *k, int j, int mode,       \
                              spm_ref_bsample *s)                                                \
    {                                                                                            \
        return spm_ref_sample_LAMBERT(m, b, h, k, j, mode, s);                                   \
    }                                                                                            \
    spm_u32 spm_ref_lobe_##NAME(const spm_material *m, const spm_ref_bsdf *b, float *mean,       \
                                float *inv_mean)                                                 \
    {                                                                                            \
        return spm_ref_lobe_LAMBERT(m, b, mean, inv_mean);                                       \
    }                                                                                            \
    spm_u32 spm_ref_record_##NAME(const spm_material *m, const spm_ref_bsdf *b,                  \
                                  const spm_ref_walk *w, spm_vertex_ext *x)                      \
    {                                                                                            \
        return spm_ref_record_LAMBERT(m, b, w, x);                                               \
    }
SPM_REF_AS_LAMBERT(FLUOR)
SPM_REF_AS_LAMBERT(DONALDSON)
