/* The ray replay of `specmip bench --rays`: each work-item one recorded ray
 * (spm_shared.h spm_ray) through the renderer's own traversal (traverse.clh,
 * as trace.cl calls it), nothing else: no random numbers, no path records.
 * Parameters: spm_kernel_args.h SPM_RAYS_ARGS. */
#pragma OPENCL FP_CONTRACT OFF
#include "spm_shared.h"
#include "spm_kernel_args.h"
#ifdef SPM_RAYS_STATS
/* statistics build only: the timed build leaves the traversal untouched */
#define SPM_TRAVERSE_COUNT(counters, index) atomic_inc(&(counters)[index])
#endif
#include "traverse.clh"

__kernel void spm_rays(SPM_RAYS_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    uint gid = get_global_id(0);
    if (gid >= nrays)
        return;
    __global const spm_ray *r = &rays[first + gid];
    float3 o = (float3)(r->o[0], r->o[1], r->o[2]);
    float3 d = (float3)(r->d[0], r->d[1], r->d[2]);
    float t;
    hits[first + gid] = r->emitter == SPM_RAY_CLOSEST
                            ? intersect(nodes, tris, o, d, r->skip, &t, counters)
                            : shadow_hit(nodes, tris, o, d, r->skip, r->emitter, counters);
}
