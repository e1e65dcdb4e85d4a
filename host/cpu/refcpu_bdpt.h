/* The CPU reference's bidirectional path tracer (--integrator bdpt;
 * docs/ARCHITECTURE.md "Connected paths"): a camera subpath and a light
 * subpath per sample, every prefix of one connected with every prefix of the
 * other, each connected path weighed by Veach's multiple importance sampling
 * in pbrt-v4's form (BDPTIntegrator's MISWeight) and shaded at the level its
 * own colours need. */
#ifndef SPM_REFCPU_BDPT_H
#define SPM_REFCPU_BDPT_H
#include "refcpu.h"
#include "spm_bdpt.h"

/* A vertex's densities for MIS, per unit area at the vertex: fwd of being
 * sampled by its own subpath, rev by the other direction; delta: a delta
 * lobe's vertex (its densities 0, which remap0 turns into 1). */
typedef struct {
    float fwd, rev;
    int delta;
} spm_bdpt_pdf;

/* The weight of strategy (s, t): camera vertices z[0 .. t-1] (z[0] the
 * lens), light vertices y[0 .. s-1] (y[0] on the light), their densities
 * already those of the connected path; light_delta: the light is a point. */
float spm_ref_bdpt_mis(const spm_bdpt_pdf *z, int t, const spm_bdpt_pdf *y, int s,
                       int light_delta);

/* Samples [begin, end) of a pass (keyed as camera paths, spm_ref_path_key)
 * traced, connected and shaded in mode m into splats appended to out (ch
 * floats each, film_splat.h); hist[level byte] counts the connected paths. */
void spm_ref_bdpt_range(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                        int start_level, const spm_mode_desc *m, const spm_shade_table *tabs,
                        const spm_spec_map *maps, int ch, const spm_trace_params *p, size_t begin,
                        size_t end, spm_splats *out, size_t hist[256]);

/* The light tracer's pieces both integrators from the light use
 * (refcpu_lighttrace.c): the pixel a film point falls in, and light e's
 * emission along d (its colour, *scale, *cos_o). */
spm_u32 spm_ref_lt_film_pixel(const spm_camera *cam, const float film[2]);
spm_u32 spm_ref_lt_emission(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                            const float d[3], float *scale, float *cos_o);
/* The camera ray of sample (pixel, sample), as a camera path draws it
 * (refcpu_trace.c). */
void spm_ref_pixel_ray(const spm_camera *cam, spm_u32 seed, spm_u32 pixel, spm_u32 sample,
                       float o[3], float d[3]);
#endif
