/* CPU reference, the shade stage's spectral factors (spm_shared.h
 * spm_vertex_ext, SPM_FACTOR_KINDS): one vertex_apply, its switch generated
 * from the list, and each kind's rule in the reference file of the type that
 * records it (refcpu_lambert.c PLAIN, refcpu_conductor.c FRESNEL,
 * refcpu_dielectric.c ABSORB, refcpu_fluor.c REEMIT). The kernels' own:
 * kernels/factors.clh. Plain scalar float loops over the lanes, uncontracted. */
#ifndef SPM_REFCPU_FACTORS_H
#define SPM_REFCPU_FACTORS_H
#include "refcpu.h"

#define SPM_REF_MAX_LANES (SPM_TRUTH_BINS + SPM_MAX_SPIKES) /* mlc at level 0 */

/* The lanes a path is shaded at: colour c's lane l is
 * base[c * stride + (idx ? idx[l] : l)]; XYZ channel ch of the lanes is the
 * sum over l of lane l * w[ch][l]; fluor the table when it has fluorescence
 * blocks (modes.h). */
typedef struct {
    const float *base;
    size_t stride;
    int n;
    const int *idx;
    const float *w[3];
    const spm_shade_table *fluor;
} spm_ref_lanes;

/* colour c's lanes into out */
void spm_ref_fetch(const spm_ref_lanes *v, spm_u32 c, float *out);
/* acc += W E[col] cw: an emission reaching the eye through the path weight W */
void spm_ref_emit_eye(const spm_ref_lanes *v, spm_u32 col, float cw, const float *W, float *acc);
/* acc += E[col] cw: an emission joining the light that arrives */
void spm_ref_emit_arrive(const spm_ref_lanes *v, spm_u32 col, float cw, float *acc);

/* Kind NAME's rule at vertex v (record x): eye 1, camera first, on the path
 * weight W and radiance acc; eye 0, from the light end, on acc = A, the
 * light arriving along the vertex's sampled ray (W unused). */
#define SPM_REF_FACTOR_DECL_(NAME, STORED, ...)                                              \
    void spm_ref_factor_##NAME(int eye, const spm_vertex *v, const spm_vertex_ext *x,        \
                               const spm_ref_lanes *ln, float *W, float *acc);
SPM_FACTOR_KINDS(SPM_REF_FACTOR_DECL_, 0)
#undef SPM_REF_FACTOR_DECL_

/* The kind of a vertex of colour r whose record says kind: a fluorescent
 * colour of a table with blocks re-radiates (refcpu_fluor.c). */
int spm_ref_kind_of(int kind, spm_u32 r, const spm_ref_lanes *ln);

/* vertex_apply: eye 1 the kind's factor then acc += W E[hit] hit_c; eye 0
 * acc += E[hit] hit_c then the kind's factor. */
void spm_ref_vertex_apply(int eye, int kind, const spm_vertex *v, const spm_vertex_ext *x,
                          const spm_ref_lanes *ln, float *W, float *acc);
#endif
