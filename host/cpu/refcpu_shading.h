/* The CPU reference's smooth shading (kernels/shading.clh has the kernels'
 * own, in the same operation order): the shading frame of a hit on a
 * triangle with vertex normals (spm_tri.vn), and a conductor's frame made
 * from it. The rule against leaks is kernels/shading.clh's. */
#ifndef SPM_REFCPU_SHADING_H
#define SPM_REFCPU_SHADING_H
#include "spm_shared.h"
#include "refcpu_conductor.h"
#include "refcpu_bsdf.h"
#include "geometry.h"

/* The shading normal sn (the viewer's side, bent so that the viewer's mirror
 * reflection stays above the geometric surface) and a unit tangent st
 * perpendicular to it, at the hit of ray o + t d on tr, whose vertex normals
 * are vn (nine floats), gn the geometric normal on the viewer's side. */
void spm_ref_shading_frame(const spm_tri *tr, const float vn[9], const float o[3],
                           const float d[3], const float gn[3], float sn[3], float st[3]);
/* The shading frame of a hit on triangle `hit` of g whose material has a
 * normal map (spm_shared.h SPM_NMAP_*; kernels/shading.clh nmap_frame's
 * formulas): 1 with sn, st; 0 (untouched) without a map or where the map's
 * tangent-space x and y are both 0. */
int spm_ref_nmap_frame(const spm_geometry *g, spm_u32 hit, const float o[3], const float d[3],
                       const float gn[3], float sn[3], float st[3]);
/* A conductor vertex's frame from a normal on the viewer's side n and a unit
 * tangent t perpendicular to it (spm_ref_cond_make's, for a shading frame). */
void spm_ref_cond_frame(const float n[3], const float t[3], const float d[3], float alpha,
                        spm_ref_cond *c);
/* The hit's shading frame on tri of ray o + t d (refcpu_bsdf.h spm_ref_hit):
 * the one place a type finds it, for both integrators. */
void spm_ref_hit_frame(const spm_geometry *g, const spm_tri *tri, const float o[3],
                       const float d[3], spm_ref_hit *h);
/* The next vertex of a walk: the ray o + t d leaving triangle skip (told to
 * a ray sink, refcpu.h), the triangle it hits (< 0: none), its point x and
 * frame h. */
int spm_ref_next_vertex(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                        float *t, float x[3], spm_ref_hit *h);
/* The type's sampled direction (spm_ref_sample) unless it lies on the wrong
 * side of the geometric surface for a smooth hit (a reflection under it, a
 * refraction over it): 0 then, and the path ends. */
int spm_ref_sample_sided(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                         const spm_ref_key *k, int j, int mode, spm_ref_bsample *s);
/* Veach's correction of a shading normal for importance (a light subpath's
 * vertex, pbrt-v4's CorrectShadingNormal): light arrives from wo and leaves
 * along wi, and f |wi . ns| times
 *   |wo . ns| |wi . ng| / (|wo . ng| |wi . ns|)
 * is the adjoint of the radiance-mode f |wo . ns|; 1 at a flat hit, 0 where
 * the denominator is. kernels/lighttrace.cl adjoint_ns has the kernels'. */
float spm_ref_adjoint_ns(const spm_ref_hit *h, const float wo[3], const float wi[3]);
#endif
