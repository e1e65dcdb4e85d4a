/* `specmip bench --rays`: traversal alone, on the rays a render traces.
 * The CPU reference traces a scene's paths and records every ray it casts
 * (camera and bounce rays: closest hit; shadow rays: "is the closest hit the
 * emitter or nothing"), each with the triangle it leaves. The rays are
 * replayed through kernels/rays.cl (the renderer's traversal, traverse.clh),
 * through the reference's traversal and, when built with it, through Embree
 * 3; closest-hit and shadow rays are timed separately and the answers
 * compared ray by ray. A ray file (--rays-save / --rays-load) keeps a ray
 * set; it names the geometry it was made on by a hash. */
#ifndef SPM_BENCH_RAYS_H
#define SPM_BENCH_RAYS_H
#include <stddef.h>
#include "geometry.h"
#include "render_plan.h"
#include "util.h"

/* rays[0 .. nclosest) closest-hit rays, then n - nclosest shadow rays. */
typedef struct {
    spm_ray *rays;
    size_t n, nclosest;
} spm_rayset;

/* One traversal's answers and costs per ray set. */
typedef struct {
    double closest_s, shadow_s;         /* fastest of the repeats, traversal only */
    double nodes_closest, nodes_shadow; /* per ray (-1: not counted) */
    double tris_closest, tris_shadow;   /* triangle tests per ray (-1: not counted) */
    unsigned stack_overflows;
    size_t tree_bytes;                  /* the tree's device buffer (nodes and leaf planes) */
} spm_rays_timing;

/* Records the rays of spp samples per pixel of the plan's scene (pass 0,
 * the plan's seed), traced by the CPU reference. 0, or an exit code
 * (interrupted: 130) with err filled. */
int spm_rays_record(const spm_render_plan *plan, int spp, spm_rayset *rs, spm_error *err);
void spm_rayset_free(spm_rayset *rs);
/* FNV-1a over the triangles and nodes: a ray file fits only this geometry. */
spm_u32 spm_rays_geometry_hash(const spm_geometry *g);
/* 0, or 1 with err naming the file (bad or foreign file: an input error). */
int spm_rays_save(const char *path, const spm_geometry *g, const spm_rayset *rs, spm_error *err);
int spm_rays_load(const char *path, const spm_geometry *g, spm_rayset *rs, spm_error *err);

/* The replay's program: this file, built with each of these options (the
 * timed build, the counting one of --rays-stats, and the two of the packet
 * variant and of the quantised tree). */
extern const char spm_rays_program_file[];
extern const char *const spm_rays_program_defines[6];
/* Replays through kernels/rays.cl on OpenCL device `device`: the fastest of
 * `repeat` timed launches per ray kind, after a warm-up; with stats, one more
 * run of the counting build for nodes and triangle tests. hits[n] receives
 * the answers. each, when not NULL, is called after every launch pair (the
 * warm-up's too) with its run number: the benchmark times Embree there, so
 * both sides are timed under the same machine load. 0, or 1 with err filled. */
int spm_rays_replay_cl(int device, const spm_geometry *g, const spm_rayset *rs, int repeat,
                       int stats, int *hits, spm_rays_timing *tm, char *devname, size_t devlen,
                       void (*each)(void *ctx, int run), void *ctx, spm_error *err);
/* The same through the CPU reference's traversal (spm_bvh_intersect), one
 * thread: a closest-hit ray's answer is its hit, a shadow ray's its closest
 * hit. nodes_* counts box tests there (a different unit from the kernel's).
 * Stops early when a stop is requested (interrupt.h). */
void spm_rays_replay_ref(const spm_geometry *g, const spm_rayset *rs, int *hits,
                         spm_rays_timing *tm);
/* Rays whose answers differ: a closest-hit ray's triangle, a shadow ray's
 * verdict (occluded: an answer other than -1 and the emitter). */
void spm_rays_compare(const spm_rayset *rs, const int *a, const int *b, size_t *closest_bad,
                      size_t *shadow_bad);
/* Of the rays whose answers differ, those where the two answers are
 * triangles that share a vertex (the ray passes by their common edge or
 * vertex and each side took one of them), or where the one triangle hit
 * shares a vertex with the ray's origin triangle (a hit beside the point the
 * ray leaves, decided by rounding). A closest-hit ray's answer is its
 * triangle, a shadow ray's its occluder. */
size_t spm_rays_differ_adjacent(const spm_geometry *g, const spm_rayset *rs, const int *a,
                                const int *b);

/* Embree 3 (built with SPM_HAVE_EMBREE; otherwise open fails saying so): the
 * same geometry and rays, rtcIntersect1 / rtcOccluded1 on `threads` threads,
 * BVH build quality `quality` (0 low, 1 medium, 2 high), the origin triangle
 * (and a shadow ray's emitter) skipped by a context filter; info describes
 * the set-up. Open builds the scene (NULL with err filled on failure); each
 * run times one pass over each ray kind, writing hits as above (a shadow
 * ray's answer: -1 unoccluded, else INT_MAX); close names each shadow ray's
 * occluder in hits, untimed, and frees. 0, or 1 with err filled. */
typedef struct spm_rays_embree spm_rays_embree;
spm_rays_embree *spm_rays_embree_open(const spm_geometry *g, const spm_rayset *rs, int threads,
                                      int quality, int *hits, char *info, size_t infolen,
                                      spm_error *err);
int spm_rays_embree_run(spm_rays_embree *e, double *closest_s, double *shadow_s, spm_error *err);
int spm_rays_embree_close(spm_rays_embree *e, spm_error *err);
/* Later runs (and close) trace rs, answers into hits; NULL: no rays. */
void spm_rays_embree_bind(spm_rays_embree *e, const spm_rayset *rs, int *hits);

typedef struct {
    const char *scene;     /* NULL: the built-in scene */
    int width, height, spp;
    spm_u32 seed;
    int device, repeat, threads;
    int group;             /* the replay's work-group size; 0: the renderer's (SPM_LOCAL_SIZE) */
    int packet;            /* 1: the packet variant (kernels/traverse_packet.clh) */
    int quant;             /* 1: the quantised tree (kernels/traverse_quant.clh) */
    int sort;              /* 1: each kind sorted by direction octant and origin first */
    int wavefront;         /* > 0: bounces of the wavefront study instead (bench_wavefront.h) */
    int stats, embree, embree_quality, json;
    const char *save, *load;
} spm_rays_opts;

/* The whole benchmark: prints a table (or, with json, one JSON object) on
 * stdout. Returns the exit code, err filled on failure. */
int spm_bench_rays(const spm_rays_opts *o, spm_error *err);
#endif
