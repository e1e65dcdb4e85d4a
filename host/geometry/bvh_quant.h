/* The quantised wide BVH (include/spm_bvhq.h), made from the wide tree on
 * demand: today the ray benchmark's --rays-quant variant. */
#ifndef SPM_BVH_QUANT_H
#define SPM_BVH_QUANT_H
#include "geometry.h"
#include "spm_bvhq.h"

/* The float the kernel computes for code q on an axis of origin o and scale s. */
static inline float spm_bvhq_face(float o, float s, unsigned q)
{
    return o + (float)q * s;
}

/* One axis of a node's frame from its children's least lower and greatest
 * upper bound: origin = lo and the least power of two s (at least 2^-149) with
 * spm_bvhq_face(lo, s, 255) >= hi. 0, or 1 when even 2^120 is too small (an
 * extent beyond about 2^127: no finite scale of 8 bits covers it). */
int spm_bvhq_axis(float lo, float hi, float *origin, float *scale);
/* A child's bounds [lo, hi] on that axis as codes, rounded outward: the
 * greatest qlo whose face is <= lo and the least qhi whose face is >= hi
 * (lo >= origin and hi <= the face of 255, as spm_bvhq_axis makes them). */
void spm_bvhq_codes(float origin, float scale, float lo, float hi, unsigned char *qlo,
                    unsigned char *qhi);
/* The quantised tree of g->wide, slot for slot in the same order (the root,
 * the leaf planes, the other nodes), in *out (freed by the caller), *nslots
 * its 64-byte slots. 0, or 1 with err filled (a box too large). */
int spm_bvhq_build(const spm_geometry *g, spm_bvhq_node **out, size_t *nslots, spm_error *err);
#endif
