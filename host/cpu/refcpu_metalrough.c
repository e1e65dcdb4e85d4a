/* CPU reference, glTF's metallic-roughness mix (refcpu_metalrough.h): one
 * draw on its own dimension picks the metal with probability the metallic
 * value (host/geometry/geometry_alpha.c spm_mix_values reads the record and
 * its maps as kernels/metalrough.clh does). */
#include "refcpu_metalrough.h"
#include "spm_rng.h"

spm_u32 spm_ref_mix_pick(const spm_geometry *g, const spm_material *mats, spm_u32 hit,
                         const float x[3], const spm_ref_key *k, int j, spm_material *m)
{
    spm_u32 mi = g->tris[hit].material;
    float metallic, alpha;
    *m = mats[mi];
    int metal = spm_mix_values(g, hit, x, &metallic, &alpha);
    if (metal < 0)
        return mi;
    if (spm_ref_rnd(k, SPM_DIM_MIX(j)) < metallic) {
        mi = (spm_u32)metal;
        *m = mats[mi];
    }
    m->p[SPM_COND_P_ALPHA] = alpha;
    return mi;
}
