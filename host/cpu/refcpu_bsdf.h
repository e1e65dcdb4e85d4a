/* The CPU reference's material contract (kernels/bsdf.clh has the kernels'
 * own and says what each call means): a type T provides, in its own file
 * host/cpu/refcpu_<t>.c, spm_ref_begin_T, _eval_T, _pdf_T, _sample_T,
 * _lobe_T and _record_T; the dispatch (refcpu_bsdf.c) is one switch per call
 * generated from include/spm_types.h, and the path loop (refcpu_trace.c)
 * names no type. Plain scalar float C, each type in the operation order of
 * its kernel file. */
#ifndef SPM_REFCPU_BSDF_H
#define SPM_REFCPU_BSDF_H
#include "spm_shared.h"
#include "spm_rng.h"
#include "refcpu_conductor.h"

#define SPM_REF_RADIANCE 0
#define SPM_REF_IMPORTANCE 1
/* or'd into eval's mode by the light integrators' joins (a vertex joined to
 * the camera or to another subpath's vertex): the whole BSDF, with what a
 * camera path's light sample leaves to its sampled rays (a rough
 * dielectric's refraction) */
#define SPM_REF_JOIN 2

/* a path's random-number key */
typedef struct {
    spm_u32 seed, pixel, sample;
} spm_ref_key;

static inline float spm_ref_rnd(const spm_ref_key *k, spm_u32 dim)
{
    return spm_rng(k->seed, k->pixel, k->sample, dim);
}

/* A hit's shading frame: n (the viewer's side) and t, the ray's direction d,
 * gn the geometric normal on the viewer's side, ng the triangle's own;
 * smooth: n is interpolated (refcpu_shading.h). */
typedef struct {
    float n[3], t[3], d[3], gn[3], ng[3];
    int smooth;
} spm_ref_hit;

/* What a path carries for its types: the 1 nm bin it committed to (SPM_NONE:
 * none yet), the dispersive glasses' index tables, whether to use them. */
typedef struct {
    const float *disp;
    int disperse;
    spm_u32 lam;
} spm_ref_walk;

/* A vertex's BSDF instance: c the frame in the conductor's form (its alpha
 * the type's width), nee whether it takes a light sample; commit: 1 the
 * vertex committed its path to a bin, 2 it took the bin committed before, 0
 * its index is no bin's; the rest the type's own. */
typedef struct {
    spm_ref_cond c;
    float eta, ps, w, pdf;
    float dir[3];
    int lobe, nee, commit;
} spm_ref_bsdf;

/* A light sample's f |cos_i| = k (f w_mis) / div / post (kernels/bsdf.clh
 * spm_eval: the factors in each type's rounding order), pdf its density of
 * sampling wi (< 0: its sampled rays count no emission), cos_light the
 * spectral factor's argument. */
typedef struct {
    float f, k, div, post, pdf, cos_light;
} spm_ref_eval;

static inline spm_ref_eval spm_ref_eval_value(float f, float post)
{
    return (spm_ref_eval){f, 1.0f, 1.0f, post, -1.0f, 0.0f};
}

/* A sampled direction (kernels/bsdf.clh spm_bsample). */
typedef struct {
    float wi[3];
    float w, wt, pdf, cos_lobe;
    int refract, inside;
} spm_ref_bsample;

#define SPM_REF_BSDF_PROTOS(NAME)                                                                \
    void spm_ref_begin_##NAME(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k, \
                              int j, spm_ref_walk *w, spm_ref_bsdf *b);                          \
    spm_ref_eval spm_ref_eval_##NAME(const spm_material *m, const spm_ref_bsdf *b,               \
                                     const spm_ref_hit *h, const float wi[3], int mode);         \
    float spm_ref_pdf_##NAME(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],    \
                             const float wi[3], int mode);                                       \
    int spm_ref_sample_##NAME(const spm_material *m, const spm_ref_bsdf *b,                      \
                              const spm_ref_hit *h, const spm_ref_key *k, int j, int mode,       \
                              spm_ref_bsample *s);                                               \
    spm_u32 spm_ref_lobe_##NAME(const spm_material *m, const spm_ref_bsdf *b, float *mean,       \
                                float *inv_mean);                                                \
    spm_u32 spm_ref_record_##NAME(const spm_material *m, const spm_ref_bsdf *b,                  \
                                  const spm_ref_walk *w, spm_vertex_ext *x);
#define SPM_MATERIAL_TYPE(NAME, ...) SPM_REF_BSDF_PROTOS(NAME)
#define SPM_EMITTER_TYPE(NAME, ...)
#include "spm_types.h"
#undef SPM_MATERIAL_TYPE
#undef SPM_EMITTER_TYPE

/* the dispatch on m's type (a type unknown: no light sample, black, dark) */
void spm_ref_begin(const spm_material *m, const spm_ref_hit *h, const spm_ref_key *k, int j,
                   spm_ref_walk *w, spm_ref_bsdf *b);
spm_ref_eval spm_ref_eval_bsdf(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                               const float wi[3], int mode);
float spm_ref_pdf(const spm_material *m, const spm_ref_bsdf *b, const float wo[3],
                  const float wi[3], int mode);
int spm_ref_sample(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                   const spm_ref_key *k, int j, int mode, spm_ref_bsample *s);
spm_u32 spm_ref_lobe(const spm_material *m, const spm_ref_bsdf *b, float *mean, float *inv_mean);
spm_u32 spm_ref_record(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_walk *w,
                       spm_vertex_ext *x);

/* the usual lobe: the material's colour, survival its mean */
spm_u32 spm_ref_lobe_plain(const spm_material *m, float *mean, float *inv_mean);
/* the cosine-weighted bounce about h's frame (MiniLight's), *z its cos_i */
void spm_ref_bounce(const spm_ref_hit *h, const spm_ref_key *k, int j, float out[3], float *z);
/* h's frame with width alpha into c (spm_ref_cond_frame) */
void spm_ref_bsdf_frame(const spm_ref_hit *h, float alpha, spm_ref_cond *c);
#endif
