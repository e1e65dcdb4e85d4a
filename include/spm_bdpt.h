/* What the bidirectional integrator's host and kernels share (--integrator
 * bdpt; docs/ARCHITECTURE.md "Connected paths"): the depth cap, the light
 * subpath's seed, and the kernels' parameter lists (kernels/bdpt.cl, the
 * host's launches in host/opencl/cl_bdpt.c). */
#ifndef SPM_BDPT_H
#define SPM_BDPT_H
#include "spm_shared.h"

/* Surface vertices a subpath holds at most (its endpoint apart): two
 * subpaths connected fill a path record (SPM_MAX_DEPTH) at most. */
#define SPM_BDPT_SUBPATH (SPM_MAX_DEPTH / 2)
/* the light subpath's seed: the camera subpath's with this mixed in, so the
 * two draw independent numbers */
#define SPM_BDPT_LIGHT_SEED 0x9E3779B9u

/* spm_bdpt_trace takes SPM_TRACE_ARGS (npaths: the record room and the
 * records' stride; heads, verts, levels: the connected paths' records;
 * first_pixel unused), then: samples first_path .. first_path + nsamples - 1
 * of the pass (keyed as camera paths); rpx each record's pixel; rstat[0]
 * counts the records (those from npaths on are counted, not written); rsam
 * each record's sample (its index in the pass: its per-path lanes' key). */
#define SPM_BDPT_TRACE_ARGS(X, S)                                       \
    X(uint, spm_u32, first_path) S                                      \
    X(uint, spm_u32, nsamples) S                                        \
    X(__global uint *, cl_mem, rpx) S                                   \
    X(__global int *, cl_mem, rstat) S                                  \
    X(__global uint *, cl_mem, rsam)

/* In a mode whose lanes are drawn per path (hero), the shade kernels of the
 * bidirectional program take after SPM_SHADE_PATH_ARGS the records' samples
 * (kernels/shade.cl HERO_LT_PARAM): a connected path's hero set is its
 * sample's, the same for every strategy of both subpaths. */
#define SPM_BDPT_SHADE_ARGS(X, S)                                       \
    X(__global const uint *, cl_mem, rsam)

/* spm_bdpt_exponent: the largest binary exponent of the n records' values
 * (SPM_PATH_CH floats each) into rstat[1], the fixed-point unit's. */
#define SPM_BDPT_EXP_ARGS(X, S)                                         \
    X(__global const float *, cl_mem, xyz) S                            \
    X(uint, spm_u32, n) S                                               \
    X(__global int *, cl_mem, rstat)
#endif
