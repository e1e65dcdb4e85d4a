/* The quantised 4-wide BVH: the wide tree (spm_bvh4_node) with each node's
 * four child boxes stored as 8-bit offsets in a frame of the node's own
 * (Ylitie, Karras and Laine 2017), one 64-byte cache line a node instead of
 * 112 bytes. Built from the wide tree by host/geometry/bvh_quant.c, traversed
 * by kernels/traverse_quant.clh (the ray benchmark's --rays-quant).
 *
 * Per axis a a node has an origin o_a (the least child bound on a) and a
 * power-of-two scale s_a; child i's box on axis a is
 *     [o_a + qlo_a[i] * s_a,  o_a + qhi_a[i] * s_a]
 * computed in float as written (q * s is exact: q < 2^8 and s a power of two,
 * so the sum is the one rounding, FP_CONTRACT on or off). The builder picks
 * each q so that this float box contains the child's true box: qlo rounded
 * down and qhi up, each checked on the float value the kernel computes. A
 * ray's float slab test is monotone in the box's faces, so every box the wide
 * tree's test enters, this one enters too, no later: the same hits.
 *
 * child[] is as in spm_bvh4_node (an interior node's slot, a leaf code, or
 * SPM_WIDE_EMPTY); slot 0 is the root, the slots from 1 on hold the same
 * leaf planes (SPM_LEAF_PLANES), the other nodes follow them. */
#ifndef SPM_BVHQ_H
#define SPM_BVHQ_H
#include "spm_shared.h"

typedef struct {
    float origin[3];
    float scale[3]; /* powers of two */
    spm_u32 child[SPM_WIDE];
    unsigned char qlo_x[SPM_WIDE], qhi_x[SPM_WIDE];
    unsigned char qlo_y[SPM_WIDE], qhi_y[SPM_WIDE];
    unsigned char qlo_z[SPM_WIDE], qhi_z[SPM_WIDE];
} spm_bvhq_node; /* 64 bytes (bvh_quant.c asserts it) */
#endif
