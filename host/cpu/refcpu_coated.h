/* The CPU reference's coated material (SPM_MAT_COATED): the lobe choice, the
 * specular lobe's direction and the light sample's factor for the trace
 * stage, in plain scalar float C (kernels/coated.clh has the kernels' own, in
 * the same operation order, and the formulas). The shade stage needs nothing
 * of its own: a coated vertex shades as a plain vertex plus its hit. */
#ifndef SPM_REFCPU_COATED_H
#define SPM_REFCPU_COATED_H
#include "spm_shared.h"
#include "refcpu_conductor.h"

/* A coated vertex: the conductor's frame (wo[2] = cos_o > 0) and the
 * coating's width, its index, the specular lobe's probability ps, whether it
 * was chosen, the chosen lobe's scalar weight w (diffuse: without its
 * 1 - F(cos_i)), and for the specular lobe its direction, its density (0: the
 * smooth lobe, a delta) and up = 0 when it points below the surface. */
typedef struct {
    spm_ref_cond f;
    float eta, ps, w, pdf;
    int spec, up;
    float dir[3];
} spm_ref_coat;

/* The vertex of frame f (spm_ref_cond_make's, the geometric one, or
 * spm_ref_cond_frame's, a shading frame; its alpha the coating's), its lobe
 * chosen with u_lobe and the rough lobe's normal drawn from u1, u2
 * (SPM_DIM_COAT_*). */
void spm_ref_coat_make(const spm_ref_cond *f, const spm_material *m, float u_lobe, float u1,
                       float u2, spm_ref_coat *c);
/* The coating's Fresnel reflectance in float (host/scene/coated.h's formula). */
float spm_ref_coat_fresnel(float eta, float c);
#endif
