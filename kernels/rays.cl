/* The ray replay of `specmip bench --rays`: each work-item one recorded ray
 * (spm_shared.h spm_ray) through the renderer's own traversal (traverse.clh,
 * as trace.cl calls it), nothing else: no random numbers, no path records.
 * Parameters: spm_kernel_args.h SPM_RAYS_ARGS. Built with -DSPM_RAYS_PACKET,
 * the work-group traces its rays as one packet (traverse_packet.clh); with
 * -DSPM_RAYS_QUANT, nodes holds the quantised tree (traverse_quant.clh). */
#pragma OPENCL FP_CONTRACT OFF
#include "spm_shared.h"
#include "spm_kernel_args.h"
#ifdef SPM_RAYS_STATS
/* statistics build only: the timed build leaves the traversal untouched */
#define SPM_TRAVERSE_COUNT(counters, index) atomic_inc(&(counters)[index])
#endif
#include "traverse.clh"

#ifdef SPM_RAYS_PACKET
#include "traverse_packet.clh"
/* The packet variant (traverse_packet.clh): a work-group of at most
 * SPM_PACKET_MAX rays of one kind; the lanes beyond nrays ride along. */
__kernel void spm_rays(SPM_RAYS_ARGS(SPM_KERNEL_PARAM, SPM_COMMA))
{
    __local float4 lt[2 * SPM_PACKET_MAX];
    uint gid = get_global_id(0);
    int active = gid < nrays;
    __global const spm_ray *r = &rays[first + (active ? gid : 0)];
    float3 o = (float3)(r->o[0], r->o[1], r->o[2]);
    float3 d = (float3)(r->d[0], r->d[1], r->d[2]);
    float t;
    int h = rays[first].emitter == SPM_RAY_CLOSEST
                ? packet_traverse(nodes, tris, o, d, r->skip, active, &t, counters, lt)
                : packet_shadow_hit(nodes, tris, o, d, r->skip, r->emitter, active, counters, lt);
    if (active)
        hits[first + gid] = h;
}
#else
#ifdef SPM_RAYS_QUANT
#include "traverse_quant.clh"
#define SPM_RAYS_TREE ((__global const spm_bvhq_node *)nodes)
#define SPM_RAYS_CLOSEST qtraverse
#define SPM_RAYS_SHADOW qshadow_hit
#else
#define SPM_RAYS_TREE nodes
#define SPM_RAYS_CLOSEST intersect
#define SPM_RAYS_SHADOW shadow_hit
#endif
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
                            ? SPM_RAYS_CLOSEST(SPM_RAYS_TREE, tris, o, d, r->skip, &t, counters)
                            : SPM_RAYS_SHADOW(SPM_RAYS_TREE, tris, o, d, r->skip, r->emitter,
                                              counters);
}
#endif
