/* CPU reference: a textured vertex's colour (kernels/texture.clh has the
 * kernels' own and the formulas; spm_shared.h SPM_TEXD_* the layout). */
#ifndef SPM_REFCPU_TEXTURE_H
#define SPM_REFCPU_TEXTURE_H
#include "geometry.h"
#include "refcpu_bsdf.h"

/* The colour vertex j records on triangle `hit` (material mat; refl without
 * a texture) at x, seen along d by a ray cone of width `cone` there: the
 * texture's pick when refl is the material's base colour `base` (a coated
 * vertex's specular lobe records white: not textured), and *survive its
 * survival ratio (spm_shared.h SPM_TEXD_SURVIVE; untouched otherwise). */
spm_u32 spm_ref_texture_colour(const spm_geometry *g, spm_u32 mat, spm_u32 hit, const float x[3],
                               const float d[3], float cone, const spm_ref_key *k, int j,
                               spm_u32 refl, spm_u32 base, float *survive);

/* The colour a light integrator's vertex j records there (its subpath's key
 * k): spm_ref_texture_colour with the footprint of the camera's direct view
 * of x, the same whichever subpath made the vertex; *mean and *inv_mean, its
 * Russian roulette's, scaled by the pick's survival ratio. */
spm_u32 spm_ref_texture_seen(const spm_geometry *g, spm_u32 mat, spm_u32 hit, const float x[3],
                             const spm_ref_key *k, int j, spm_u32 refl, spm_u32 base, float *mean,
                             float *inv_mean);

/* The grid node picked at (u, v) on level l of the texture whose header is
 * h (texel along x by r1, along y by r2, the cell's corner by r3): its index
 * in a palette (kernels/texture.clh tex_node_at). */
spm_u32 spm_ref_texture_node(const spm_geometry *g, const spm_u32 *h, spm_u32 l, float u, float v,
                             float r1, float r2, float r3);

/* The ray cone's spread past a vertex on triangle tri where the cone of width
 * w, arriving along d, left as s says (shading normal n, relative index eta):
 * kernels/texture.clh tex_cone_bounce's formulas. */
float spm_ref_cone_bounce(const spm_geometry *g, const spm_tri *tri, float spread, float w,
                          const float n[3], float eta, const float d[3],
                          const spm_ref_bsample *s);
#endif
