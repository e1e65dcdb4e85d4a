/* CPU reference, fluorescent paths (refcpu.h): the record walked from the
 * light end, A = E_bg c_bg; for j = n-1 .. 0: A = M_j (E_j c_j + A);
 * L = E_first c_first + A, with M_j x = R_j x lane by lane plus, at a
 * fluorescent vertex, the block's columns weighted by x. A conductor vertex
 * (spm_vertex_ext) applies the camera-first walk's rule (spm_ref_cond_vertex)
 * to A: A = F(cos_light) E_j c_j + F(cos_lobe) (E_hit hit_c + A); a
 * dielectric's A = E_j c_j + exp(-sigma d) (E_hit hit_c + A). Plain scalar float
 * loops, uncontracted sums in lane order (the kernel fuses them). */
#include "refcpu.h"
#include "refcpu_conductor.h"
#include "refcpu_dielectric.h"
#include "refcpu_bsdf.h"
#include <string.h>

#define MAX_LANES (SPM_TRUTH_BINS + SPM_MAX_SPIKES)

int spm_ref_fluor_path(const spm_path *path, const spm_shade_table *tab)
{
    for (spm_u32 j = 0; j < path->h.nvert; j++) {
        spm_u32 r = path->v[j].ids & 0xFFFFu;
        if (r == SPM_NONE)
            return 0;
        if (r >= (spm_u32)tab->fluor_first)
            return 1;
    }
    return 0;
}

void spm_ref_fluor_shade(const spm_path *path, const spm_shade_table *tab, int n, float *L)
{
    const spm_path_head *h = &path->h;
    const size_t st = (size_t)tab->stride;
    const float *rows = tab->rows, *blocks = rows + (size_t)tab->ncolours * st;
    float A[MAX_LANES], X[MAX_LANES];
    spm_u32 nv = h->nvert;
    for (spm_u32 j = 0; j < h->nvert; j++)
        if ((path->v[j].ids & 0xFFFFu) == SPM_NONE) {
            nv = j;
            break;
        }
    int lit = nv == h->nvert && h->bg != SPM_NONE;
    for (int l = 0; l < n; l++)
        A[l] = lit ? rows[h->bg * st + (size_t)l] * h->bg_c : 0.0f;
    for (spm_u32 jj = nv; jj > 0; jj--) {
        const spm_vertex *v = &path->v[jj - 1];
        spm_u32 r = v->ids & 0xFFFFu, e = v->ids >> 16;
        const spm_vertex_ext *x = &path->x[jj - 1];
        if (SPM_EXT_DIEL(*x)) { /* A = E_j c_j + exp(-sigma d) (E_hit hit_c + A) */
            spm_u32 hit = SPM_EXT_HIT(*x);
            for (int l = 0; l < n; l++) {
                float in = A[l] + (hit != SPM_NONE ? rows[hit * st + (size_t)l] * x->hit_c : 0.0f);
                A[l] = spm_ref_diel_absorb(rows[r * st + (size_t)l], x->cos_lobe) * in;
                if (e != SPM_NONE)
                    A[l] += rows[e * st + (size_t)l] * v->c;
            }
            continue;
        }
        if (SPM_EXT_K(*x) != SPM_NONE) { /* the conductor's rule, on A */
            spm_u32 hit = SPM_EXT_HIT(*x);
            spm_ref_cond_vertex(v, x, &rows[r * st], &rows[SPM_EXT_K(*x) * st],
                                e != SPM_NONE ? &rows[e * st] : NULL,
                                hit != SPM_NONE ? &rows[hit * st] : NULL, n, 0, A, A);
            continue;
        }
        if (e != SPM_NONE)
            for (int l = 0; l < n; l++)
                A[l] += rows[e * st + (size_t)l] * v->c;
        memcpy(X, A, (size_t)n * sizeof *X);
        for (int l = 0; l < n; l++)
            A[l] = X[l] * rows[r * st + (size_t)l];
        if (r >= (spm_u32)tab->fluor_first) {
            const float *blk = blocks + (size_t)(r - (spm_u32)tab->fluor_first) * st * st;
            for (int i = 0; i < n; i++)
                for (int o = 0; o < n; o++)
                    A[o] += blk[(size_t)i * st + (size_t)o] * X[i];
        }
    }
    for (int l = 0; l < n; l++) {
        float e = h->first_emit != SPM_NONE ? h->first_emit_c * rows[h->first_emit * st + (size_t)l]
                                            : 0.0f;
        L[l] = e + A[l];
    }
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
