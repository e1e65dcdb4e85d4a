/* The CPU reference's conductor (SPM_MAT_CONDUCTOR): the GGX lobe, its light
 * sample and MIS weights for the trace stage, the spectral Fresnel for the
 * shade stage, in plain scalar float C (kernels/conductor.clh has the
 * kernels' own, in the same operation order). */
#ifndef SPM_REFCPU_CONDUCTOR_H
#define SPM_REFCPU_CONDUCTOR_H
#include "spm_shared.h"

/* A conductor vertex's frame: the normal turned to the viewer's side n, the
 * triangle's tangent t, b = n x t; back = -d, and wo, back in the frame
 * (wo[2] > 0); the width. */
typedef struct {
    float n[3], t[3], b[3], back[3], wo[3];
    float alpha;
} spm_ref_cond;

void spm_ref_cond_make(const spm_tri *tri, const float d[3], float alpha, spm_ref_cond *c);
/* The light sample towards unit l (same side as wo): D G2 / (4 wo_z) times
 * the power heuristic against the lobe's density; pick_pdf the emitter's
 * pick probability, d2c the clamped squared distance, area and cos_e the
 * emitter's; *cos_h = wo.h, the Fresnel angle. */
float spm_ref_cond_light(const spm_ref_cond *c, const float l[3], float pick_pdf, float d2c,
                         float area, float cos_e, float *cos_h);
/* The lobe toward unit l (world): D G2 / (4 wo_z), *pdf the visible normals'
 * G1(wo) D / (4 wo_z), *cos_h = wo.h. */
float spm_ref_cond_f(const spm_ref_cond *c, const float l[3], float *pdf, float *cos_h);
/* The lobe's direction into out from the two random numbers (unused when
 * smooth): returns 0 when it points below the surface (the path ends), else 1
 * with *cos_m = wo.m (smooth: wo.n), *w the colour-independent weight
 * f cos / pdf without F (1, or G2 / G1(wo)) and *pdf its density (0: a delta). */
int spm_ref_cond_lobe(const spm_ref_cond *c, float u1, float u2, float out[3], float *cos_m,
                      float *w, float *pdf);
/* The power heuristic's weight of density a against b: a^2 / (a^2 + b^2). */
float spm_ref_cond_power(float a, float b);
/* The conductor's exact unpolarised Fresnel reflectance (materials.c's formula). */
float spm_ref_cond_fresnel(float eta, float k, float c);
/* GGX of width a in a vertex frame: Smith's Lambda at cosine z, D at m_z, a
 * visible normal m for wo from two random numbers (the formulas above) */
float spm_ref_ggx_lambda(float a, float z);
float spm_ref_ggx_d(float a, float mz);
void spm_ref_ggx_vndf(const float wo[3], float a, float u1, float u2, float m[3]);
#endif
