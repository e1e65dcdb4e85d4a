/* The CPU reference's dielectric (SPM_MAT_DIELECTRIC): glass of one index,
 * smooth or GGX-rough, in plain scalar float C (kernels/dielectric.clh has the
 * kernels' own, in the same operation order). Its frame is the conductor's
 * (spm_ref_cond: the normal turned to the viewer's side); e is the relative
 * index eta_t / eta_i of the side wo comes from to the other: the material's
 * index when wo is on the front face's side (outside), its inverse else. */
#ifndef SPM_REFCPU_DIELECTRIC_H
#define SPM_REFCPU_DIELECTRIC_H
#include "refcpu_conductor.h"

/* The unpolarised Fresnel reflectance at incidence cosine ci in [0, 1] for
 * relative index e (1 under total internal reflection); *ct the cosine of
 * the refracted direction (0 then). */
float spm_ref_diel_fresnel(float ci, float e, float *ct);
/* The relative index at a vertex of index ior reached along d on triangle
 * tri: ior through the front face, 1 / ior through the back. */
float spm_ref_diel_eta(const spm_tri *tri, const float d[3], float ior);
/* The lobe: the normal (the surface's, or a visible one from u1, u2), then
 * reflection if uc < F(wo.m), else refraction, into out (world). Returns 0
 * when the direction lands on the wrong side of the frame's normal (the path
 * ends), else 1 (reflected) or 2 (refracted) with
 * *w_t the refraction's radiance factor 1 / e^2 (1 when reflecting), *w_g the
 * rough lobe's G2 / G1(wo) (1 smooth), *pdf the density of a reflection for
 * MIS (F times the visible normals'; 0 for the smooth lobe and a refraction). */
int spm_ref_diel_lobe(const spm_ref_cond *c, float e, float u1, float u2, float uc, float out[3],
                      float *w_t, float *w_g, float *pdf);
/* The transmittance exp(-sigma d) of a length d inside (1 for d <= 0). */
/* The 1 nm bin a path commits to at its first dispersive vertex from the 32
 * bits h of its key: floor(h 400 / 2^32) (pdf 1 / 400, uniform). */
spm_u32 spm_ref_disp_bin(spm_u32 h);
float spm_ref_diel_absorb(float sigma, float d);
#endif
