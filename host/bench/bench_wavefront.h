/* `specmip bench --rays SCENE --rays-wavefront N`: a path tracer's rays as a
 * wavefront, one launch of the renderer's traversal (kernels/rays.cl) per
 * bounce and kind, each bounce's rays traced twice: in path order and sorted
 * by direction octant and origin (a 30-bit key, radix-sorted on the host).
 * Depth 1 is the camera's rays; at every closest hit a path continues with a
 * cosine-weighted bounce and casts one shadow ray towards a point on an
 * emitter triangle; a path ends when it misses or meets an emitter. Both
 * orders, the sort's own time and (with --embree) Embree's, per depth; every
 * sorted ray's answer is compared with the same ray's in path order, and the
 * path order's with the CPU reference's. */
#ifndef SPM_BENCH_WAVEFRONT_H
#define SPM_BENCH_WAVEFRONT_H
#include "bench_rays.h"
#include "render_setup.h"

/* The whole study on the opened scene s; prints a table (or JSON). Returns
 * the exit code, err filled on failure. */
int spm_bench_wavefront(const spm_rays_opts *o, const spm_render_setup *s, spm_error *err);

/* The coherent order of rays[0, n): perm[i] is the ray that goes i-th, by
 * key = octant of d (3 bits) << 27 | Morton code of the origin's cell in a
 * 512^3 grid over the origins' bounds, ties in the given order (a stable
 * least-significant-digit radix sort, three passes of 10 bits); the CPU
 * seconds the keys and the sort took in *key_s and *sort_s. */
void spm_wavefront_order(const spm_ray *rays, size_t n, spm_u32 *perm, double *key_s,
                         double *sort_s);
#endif
