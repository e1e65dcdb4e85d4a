/* CPU reference: glTF's metallic-roughness mix at a vertex
 * (kernels/metalrough.clh has the kernel's, the same operations in order). */
#ifndef SPM_REFCPU_METALROUGH_H
#define SPM_REFCPU_METALROUGH_H
#include "geometry.h"
#include "refcpu_bsdf.h"

/* The material vertex j meets on triangle `hit` at x, into *m: its
 * triangle's, or for one with a mix record (spm_shared.h SPM_MIX_*) its metal
 * with probability the metallic value there, alpha the roughness there
 * squared in either. Its index. */
spm_u32 spm_ref_mix_pick(const spm_geometry *g, const spm_material *mats, spm_u32 hit,
                         const float x[3], const spm_ref_key *k, int j, spm_material *m);
#endif
