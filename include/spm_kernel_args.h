/* The kernels' parameter lists, written once for both sides of the host-kernel
 * contract. Each list is X(device type, host type, name) entries joined by S:
 * the kernels declare their parameters with SPM_KERNEL_PARAM and SPM_COMMA,
 * and the host lays out one struct field per argument (spm_*_args, in this
 * order) and sets the kernel's arguments from it, so the two cannot disagree
 * on the order. Host types: cl_mem for a buffer, spm_u32 for a uint, the
 * struct itself for a struct. */
#ifndef SPM_KERNEL_ARGS_H
#define SPM_KERNEL_ARGS_H

#define SPM_COMMA ,
#define SPM_KERNEL_PARAM(dev, host, name) dev name
#define SPM_KERNEL_ARG(dev, host, name) name /* a kernel passing its parameters on */

/* spm_trace (kernels/trace.cl): one batch of a pass, npaths paths, the samples
 * of pixels first_pixel ... (records indexed from 0 within the batch).
 * counters[0]: truncated paths; counters[1]: BVH stack overflows.
 * lvlk: the level feeler's table, a level per colour c and k, the times a path
 * meets c: lvlk[c * SPM_PRETEST_KMAX + k - 1] (host/spectral/tables.h).
 * light_pdf: per triangle its probability of being picked by power as the
 * light (spm_geometry.light_pdf; 0: not an emitter), for MIS at a rough
 * lobe; with p.light_tree, the light tree after them (spm_light_tree.h).
 * vnormals: the smooth triangles' vertex normals (spm_tri.vn; a placeholder
 * in a scene without them, never read).
 * disp: the dispersive glasses' index tables (spm_geometry disp; a
 * placeholder in a scene without them).
 * tex, uvs: the textures' words and the triangles' texture coordinates
 * (spm_shared.h SPM_TEXD_*; placeholders in a scene without textures).
 * envmap: the environment map's texels and distribution (spm_shared.h
 * SPM_ENV_*; a placeholder in a scene without one). */
#define SPM_TRACE_ARGS(X, S)                                            \
    X(__global const spm_tri *, cl_mem, tris) S                         \
    X(__global const spm_bvh4_node *, cl_mem, nodes) S                  \
    X(__global const spm_emitter *, cl_mem, emitters) S                 \
    X(__global const spm_material *, cl_mem, mats) S                    \
    X(__global const uchar *, cl_mem, lvlk) S                           \
    X(__global const float *, cl_mem, light_pdf) S                      \
    X(__global const float *, cl_mem, vnormals) S                       \
    X(__global const float *, cl_mem, disp) S                           \
    X(__global const uint *, cl_mem, tex) S                             \
    X(__global const float *, cl_mem, uvs) S                            \
    X(__global const float *, cl_mem, envmap) S                         \
    X(const spm_trace_params, spm_trace_params, p) S                    \
    X(uint, spm_u32, init_level) S                                      \
    X(uint, spm_u32, npaths) S                                          \
    X(__global spm_dev_head *, cl_mem, heads) S                         \
    X(__global spm_vertex *, cl_mem, verts) S                           \
    X(__global uchar *, cl_mem, levels) S                               \
    X(__global uint *, cl_mem, counters) S                              \
    X(uint, spm_u32, first_pixel)

/* Every shade kernel (kernels/shade_body.clh): entries begin .. end-1 of idx
 * are its bucket of the batch's npaths records (device layout, spm_shared.h);
 * tab and cmf are its shade table's rows and XYZ weights (host/spectral/modes.h);
 * XYZ per path into xyz. */
#define SPM_SHADE_ARGS(X, S)                                            \
    X(__global const spm_dev_head *, cl_mem, heads) S                   \
    X(__global const spm_vertex *, cl_mem, verts) S                     \
    X(uint, spm_u32, npaths) S                                          \
    X(__global const uint *, cl_mem, idx) S                             \
    X(uint, spm_u32, begin) S                                           \
    X(uint, spm_u32, end) S                                             \
    X(__global const float *, cl_mem, tab) S                            \
    X(__global const float *, cl_mem, cmf) S                            \
    X(__global float *, cl_mem, xyz)

/* ...followed, in a mode whose lanes are drawn per path (hero), by its extra
 * table (SPM_HERO_*) and each path's RNG key: path pi of the batch is pixel
 * first_pixel + pi / spp, sample first_sample + pi % spp (spp as a divisor,
 * spm_shared.h: spp.d). Such a kernel sets up its work-group's paths
 * together, so it is launched in work-groups of SPM_LOCAL_SIZE. */
#define SPM_SHADE_PATH_ARGS(X, S)                                       \
    X(__global const float *, cl_mem, extra) S                          \
    X(uint, spm_u32, seed) S                                            \
    X(const spm_divisor, spm_divisor, spp) S                            \
    X(uint, spm_u32, first_sample) S                                    \
    X(uint, spm_u32, first_pixel)

/* ...followed, when the program writes spectral records (-DSPM_SPEC_BINS=n,
 * -DSPM_PATH_CH=3+n), by the slot's lane-to-bin map (host/modes.h
 * spm_spec_map: idx = row starts then lanes, fac = factors; a per-path mode
 * leaves them unread). Each path's record is then SPM_PATH_CH floats of xyz:
 * XYZ, then the n bins. */
#define SPM_SHADE_SPEC_ARGS(X, S)                                       \
    X(__global const uint *, cl_mem, smap) S                            \
    X(__global const float *, cl_mem, sfac)

/* ...followed, in a scene with dispersive glass (-DSPM_WITH_DISPERSION), by
 * the 1 nm rows of every colour and truth's XYZ weights (modes.h
 * spm_shade_table nm1, nm1_w), which a committed path is shaded from. */
#define SPM_SHADE_DISP_ARGS(X, S)                                       \
    X(__global const float *, cl_mem, dtab) S                           \
    X(__global const float *, cl_mem, dcmf)

/* spm_accumulate (kernels/shade.cl): per pixel of the batch (npix) the sum of
 * its spp samples' records (XYZ, and the bins of spectral records), in
 * sample order, into pass_xyz (SPM_PATH_CH floats a pixel); counters[2] counts the
 * non-finite samples left out. */
#define SPM_ACCUM_ARGS(X, S)                                            \
    X(__global const float *, cl_mem, xyz) S                            \
    X(uint, spm_u32, npix) S                                            \
    X(uint, spm_u32, spp) S                                             \
    X(__global float *, cl_mem, pass_xyz) S                             \
    X(__global uint *, cl_mem, counters)

/* spm_rays (kernels/rays.cl): rays [first, first + nrays) of the buffer, each
 * one traversal (spm_ray), its answer into hits (the triangle, or -1). A
 * shadow ray's answer is -1 or the emitter when unoccluded, else an
 * occluder. Built with -DSPM_RAYS_STATS, counters[SPM_COUNTER_NODES] and
 * [SPM_COUNTER_TRIS] add up the nodes visited and triangles tested. */
#define SPM_RAYS_ARGS(X, S)                                             \
    X(__global const spm_tri *, cl_mem, tris) S                         \
    X(__global const spm_bvh4_node *, cl_mem, nodes) S                  \
    X(__global const spm_ray *, cl_mem, rays) S                         \
    X(uint, spm_u32, first) S                                           \
    X(uint, spm_u32, nrays) S                                           \
    X(__global int *, cl_mem, hits) S                                   \
    X(__global uint *, cl_mem, counters)

/* The light integrator's kernels (kernels/lighttrace.cl, a program built with
 * -DSPM_LIGHT_TRACE). spm_light_trace takes SPM_TRACE_ARGS (first_pixel
 * unused), then: its subpaths are first_path ... of the pass; lpx the pixel
 * words, SPM_MAX_DEPTH + 1 slabs of npaths (slab 0 the light's own splat). */
#define SPM_LIGHT_TRACE_ARGS(X, S)                                      \
    X(uint, spm_u32, first_path) S                                      \
    X(__global uint *, cl_mem, lpx)

/* ...each shade kernel's _lt twin takes SPM_SHADE_ARGS (xyz: the splats'
 * values), the path and spectral arguments as the shade kernel, then these:
 * the pixel words, the splats' pixels, lstat (count, largest exponent), the
 * list's room, and (per-path lanes) the chunk's first subpath's offset in
 * its pixel (kernels/shade.cl HERO_LT_PARAM). */
#define SPM_SPLAT_SHADE_ARGS(X, S)                                      \
    X(__global const uint *, cl_mem, lpx) S                             \
    X(__global uint *, cl_mem, spx) S                                   \
    X(__global int *, cl_mem, lstat) S                                  \
    X(uint, spm_u32, scap) S                                            \
    X(uint, spm_u32, pofs)

/* spm_splat_add: splats [0, n) into the 64-bit sums acc (SPM_PATH_CH a
 * pixel) at the unit 2^-shift; counters[2] counts non-finite splats. */
#define SPM_SPLAT_ADD_ARGS(X, S)                                        \
    X(__global const uint *, cl_mem, spx) S                             \
    X(__global const float *, cl_mem, sval) S                           \
    X(uint, spm_u32, n) S                                               \
    X(int, cl_int, shift) S                                             \
    X(__global long *, cl_mem, acc) S                                   \
    X(__global uint *, cl_mem, counters)

/* spm_splat_convert: the npix pixels' sums into pass, acc back to zero. */
#define SPM_SPLAT_CONVERT_ARGS(X, S)                                    \
    X(__global long *, cl_mem, acc) S                                   \
    X(uint, spm_u32, npix) S                                            \
    X(int, cl_int, shift) S                                             \
    X(__global float *, cl_mem, pass)

/* The work-group size of every launch. */
#define SPM_LOCAL_SIZE 64

/* Counters the kernels add to (one buffer of SPM_NCOUNTERS uints, zeroed a pass). */
#define SPM_COUNTER_TRUNCATED 0
#define SPM_COUNTER_STACK 1
#define SPM_COUNTER_NONFINITE 2
#define SPM_NCOUNTERS 4
/* the ray replay's, in a buffer of its own of SPM_RAYS_NCOUNTERS */
#define SPM_COUNTER_NODES 4
#define SPM_COUNTER_TRIS 5
#define SPM_RAYS_NCOUNTERS 8
#endif
