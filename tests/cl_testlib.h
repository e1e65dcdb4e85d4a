/* Shared set-up of the OpenCL tests: the default scene at a small size, its
 * geometry and tables, pass parameters, and record comparison helpers. */
#ifndef SPM_CL_TESTLIB_H
#define SPM_CL_TESTLIB_H
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "refcpu.h"
#include "spm_rng.h"
#include "backend_cl.h"

typedef struct {
    spm_scene scene;
    spm_geometry geom;
    spm_tables tables;
} cl_test_scene;

/* No OpenCL platform is a failure, with a line saying so (CI has PoCL). */
static inline int cl_test_have_device(void)
{
    spm_cl_device *list;
    int n;
    spm_error err;
    if (spm_cl_devices(&list, &n, &err)) {
        printf("no OpenCL device, cannot test the OpenCL backend: %s\n", err.msg);
        return 0;
    }
    free(list);
    return 1;
}

/* The scene at `path` (NULL: the default scene) at w x h. */
static inline int cl_test_scene_load(cl_test_scene *s, const char *path, int w, int h)
{
    spm_error err;
    spm_pretest_opts po;
    spm_quiet_warnings = 1;
    spm_pretest_defaults(&po);
    memset(s, 0, sizeof *s);
    if (path ? spm_scene_load(path, &s->scene, &err) : spm_scene_default(&s->scene, &err)) {
        printf("%s: %s\n", path ? path : "default scene", err.msg);
        return 1;
    }
    s->scene.width = w;
    s->scene.height = h;
    if (spm_geometry_build(&s->scene, &s->geom, &err) ||
        spm_tables_build(&s->scene, &po, &s->tables, &err)) {
        printf("scene set-up: %s\n", err.msg);
        return 1;
    }
    return 0;
}

static inline int cl_test_scene_open(cl_test_scene *s, int w, int h)
{
    return cl_test_scene_load(s, NULL, w, h);
}

static inline void cl_test_scene_close(cl_test_scene *s)
{
    spm_tables_free(&s->tables);
    spm_geometry_free(&s->geom);
    spm_scene_free(&s->scene);
}

static inline spm_trace_params cl_test_params(const cl_test_scene *s, spm_u32 seed, spm_u32 first,
                                       spm_u32 spp)
{
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.cam = s->geom.cam;
    p.ntris = (spm_u32)s->geom.ntris;
    p.nemitters = (spm_u32)s->geom.nemitters;
    p.emit_power = (spm_u32)s->geom.emit_power;
    p.bg_up = s->tables.bg_up;
    p.bg_down = s->tables.bg_down;
    p.seed = seed;
    p.first_sample = first;
    p.spp_per_pass = spp;
    return p;
}

/* The camera ray of path i (spm_shared.h spm_camera), in double: what a
 * closed form recomputes independently of either backend. */
static inline void cl_test_camera_dir(const spm_trace_params *p, size_t i, double d[3])
{
    spm_u32 pixel, sample;
    spm_ref_path_key(p, i, &pixel, &sample);
    const spm_camera *c = &p->cam;
    double w = c->width, h = c->height;
    double cx = 2.0 * ((pixel % (spm_u32)c->width) + (double)spm_rng(p->seed, pixel, sample,
                                                                      SPM_DIM_CAM_X)) / w - 1.0;
    double cy = 1.0 - 2.0 * ((pixel / (spm_u32)c->width) +
                             (double)spm_rng(p->seed, pixel, sample, SPM_DIM_CAM_Y)) / h;
    double l = 0.0;
    for (int k = 0; k < 3; k++) {
        d[k] = c->dir[k] + c->tan_half * (c->right[k] * cx + c->up[k] * cy * h / w);
        l += d[k] * d[k];
    }
    for (int k = 0; k < 3; k++)
        d[k] /= sqrt(l);
}

/* Traces and shades every path of the scene's image (spp per pixel, seed) in
 * truth on the OpenCL backend (cl 1) or the CPU reference (cl 0), into paths
 * and xyz (one each per path); 0, or 1 with a line saying why. */
static inline int cl_test_render_truth(cl_test_scene *s, spm_u32 seed, int cl, int spp,
                                       spm_path *paths, float *xyz)
{
    size_t n = (size_t)s->geom.cam.width * s->geom.cam.height * spp;
    spm_trace_params p = cl_test_params(s, seed, 0, (spm_u32)spp);
    uint8_t *levels = spm_xcalloc(n, 1);
    int rc = 0;
    if (!cl) {
        spm_ref_trace(&s->geom, s->tables.materials, NULL, &p, paths, levels);
        memset(levels, 0, n);
        spm_ref_shade(&s->tables, SPM_MODE_TRUTH, &p, 0, paths, levels, n, xyz);
    } else {
        spm_cl_renderer *r;
        spm_error err;
        rc = spm_cl_create(0, &s->geom, &s->tables, SPM_MODE_TRUTH, seed, &r, &err);
        if (!rc) {
            rc = spm_cl_trace(r, 0, (spm_u32)spp, paths, levels, &err) ||
                 spm_cl_shade(r, 0, (spm_u32)spp, paths, levels, xyz, &err);
            spm_cl_destroy(r);
        }
        if (rc)
            printf("opencl: %s\n", err.msg);
    }
    free(levels);
    return rc;
}

static inline const uint8_t *cl_test_lvlk(const spm_tables *t, int mode)
{
    return spm_mode_lvlk(spm_mode(mode), t);
}

static inline uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* Hash of a record's meaningful part: head without padding, written vertices. */
static inline uint64_t cl_test_path_hash(const spm_path *p)
{
    uint64_t h = 1469598103934665603ull;
    h = fnv(h, &p->h, offsetof(spm_path_head, pad0));
    spm_u32 n = p->h.nvert <= SPM_MAX_DEPTH ? p->h.nvert : SPM_MAX_DEPTH;
    return fnv(h, p->v, n * sizeof p->v[0]);
}

/* Kernel against CPU reference, one path record. The kernel's ray arithmetic
 * is the reference's operation by operation (contraction off, correctly
 * rounded divide/sqrt); cos/sin may differ by a few ulps (OpenCL allows 4), so
 * a bounce direction can differ in its last bits. That moves a weight by far
 * less than 1e-4 relative unless a cosine is itself tiny (grazing), and flips
 * a discrete decision (which triangle, shadowed or not) only for a ray within
 * ulps of an edge: the callers bound how many paths may do that. */
#define CL_TEST_WEIGHT_REL 1e-4

static inline int cl_test_close_rel(float a, float b)
{
    float m = fabsf(a) > fabsf(b) ? fabsf(a) : fabsf(b);
    return fabsf(a - b) <= CL_TEST_WEIGHT_REL * m;
}

/* 0: same path; 1: diverged (a discrete difference or a weight beyond tolerance). */
static inline int cl_test_path_differs(const spm_path *a, const spm_path *b)
{
    if (a->h.nvert != b->h.nvert || a->h.end != b->h.end || a->h.first_emit != b->h.first_emit ||
        a->h.bg != b->h.bg || !cl_test_close_rel(a->h.first_emit_c, b->h.first_emit_c) ||
        !cl_test_close_rel(a->h.bg_c, b->h.bg_c))
        return 1;
    for (spm_u32 j = 0; j < a->h.nvert && j < SPM_MAX_DEPTH; j++)
        if (a->v[j].ids != b->v[j].ids || !cl_test_close_rel(a->v[j].c, b->v[j].c))
            return 1;
    return 0;
}

/* Shaded XYZ of n paths, got against ref: each component's difference
 * relative to the largest of its path's reference components (absolute where
 * the reference is all zero). Returns how many exceed rel, *worst the largest
 * difference. */
static inline size_t cl_test_shade_diff(const float *ref, const float *got, size_t n, double rel,
                                        double *worst)
{
    size_t bad = 0;
    *worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        double big = 0.0;
        for (int c = 0; c < 3; c++)
            big = fmax(big, fabs(ref[3 * i + c]));
        for (int c = 0; c < 3; c++) {
            double e = big > 0.0 ? fabs(got[3 * i + c] - ref[3 * i + c]) / big
                                 : fabs(got[3 * i + c]);
            *worst = fmax(*worst, e);
            bad += !(e <= rel);
        }
    }
    return bad;
}
#endif
