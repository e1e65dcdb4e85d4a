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
#include "backend_cl.h"
#include "spm_rng.h"

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
    p.light_tree = s->geom.ntree > 0;
    p.bg_up = s->tables.bg_up;
    p.bg_down = s->tables.bg_down;
    p.seed = seed;
    p.first_sample = first;
    p.spp_per_pass = spp;
    return p;
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

/* The kernel's trace against the reference's, path by path: spp samples of
 * every pixel of s (mode 0's level table), the reference's records into cp
 * (n = pixels x spp of them); *diverged the paths whose records differ,
 * *level_diff those with equal records but other level bytes. 1 when the
 * kernels did not run (a line printed). */
static inline int cl_test_trace_diff(cl_test_scene *s, spm_u32 seed, int spp, spm_path *cp,
                                     size_t *diverged, size_t *level_diff)
{
    size_t n = (size_t)s->geom.cam.width * s->geom.cam.height * spp;
    spm_path *gp = spm_xcalloc(n, sizeof *gp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    spm_trace_params p = cl_test_params(s, seed, 0, (spm_u32)spp);
    spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, 0), &p, cp, cl);
    spm_cl_renderer *r;
    spm_error err;
    int rc = spm_cl_create(0, &s->geom, &s->tables, 0, seed, &r, &err);
    if (!rc) {
        rc = spm_cl_trace(r, 0, (spm_u32)spp, gp, gl, &err);
        spm_cl_destroy(r);
    }
    if (rc)
        printf("opencl: %s\n", err.msg);
    *diverged = *level_diff = 0;
    for (size_t i = 0; !rc && i < n; i++) {
        int d = cl_test_path_differs(&gp[i], &cp[i]);
        *diverged += d;
        *level_diff += !d && gl[i] != cl[i];
    }
    free(gp);
    free(gl);
    free(cl);
    return rc;
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
/* ---- furnaces: an object under a uniform sky ------------------------------ */

/* Renders scene s (w x h, spp, seed) in truth on backend cl (0: the CPU
 * reference) into paths and xyz (w h spp of each). Returns 0 or 1 (said). */
static inline int cl_test_render_truth(cl_test_scene *s, int cl, spm_u32 seed, int w, int h,
                                       int spp, spm_path *paths, float *xyz)
{
    size_t n = (size_t)w * h * spp;
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

/* The camera ray of path i, in double. */
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

/* Y of the upper background's colour */
static inline double cl_test_bg_y(const cl_test_scene *s)
{
    const float *bg = s->tables.truth + (size_t)s->tables.bg_up * SPM_TRUTH_BINS;
    double y = 0.0;
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        y += bg[b] * s->tables.cmf_truth[1][b];
    return y;
}

/* The mean over the paths that meet an object of a path's Y over the
 * background's, less want[i] (NULL: 1), its standard error, how many met. */
static inline void cl_test_ratio_stats(const spm_path *paths, const float *xyz, size_t n,
                                       double ybg, const double *want, double *mean, double *se,
                                       size_t *met)
{
    double s = 0.0, s2 = 0.0;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (paths[i].h.nvert == 0)
            continue;
        double r = xyz[3 * i + 1] / ybg - (want ? want[i] : 1.0);
        s += r;
        s2 += r * r;
        m++;
    }
    *met = m;
    *mean = m ? s / (double)m : 0.0;
    *se = m > 1 ? sqrt((s2 / (double)m - *mean * *mean) / (double)(m - 1)) : 1.0;
}

/* One backend's furnace: the mean over the paths that meet an object of a
 * path's Y over the background's less want[i], its standard error, how many
 * met, how many satisfy the caller's count (0 without one); failed: it did
 * not render. */
typedef struct {
    double mean, se;
    size_t met, counted;
    int failed;
} cl_test_furnace_result;

/* Renders s (w x h, spp, seed) in truth on the reference (res[0]) and the
 * kernels (res[1]) against want (NULL: 1 for every path); count (may be
 * NULL) says whether a path counts. */
static inline void cl_test_furnace(cl_test_scene *s, spm_u32 seed, int w, int h, int spp,
                                   const double *want, int (*count)(const spm_path *, void *),
                                   void *ctx, cl_test_furnace_result res[2])
{
    size_t n = (size_t)w * h * spp;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    double ybg = cl_test_bg_y(s);
    for (int cl = 0; cl < 2; cl++) {
        memset(&res[cl], 0, sizeof res[cl]);
        res[cl].failed = cl_test_render_truth(s, cl, seed, w, h, spp, paths, xyz);
        if (res[cl].failed)
            continue;
        cl_test_ratio_stats(paths, xyz, n, ybg, want, &res[cl].mean, &res[cl].se, &res[cl].met);
        for (size_t i = 0; count && i < n; i++)
            res[cl].counted += count(&paths[i], ctx) != 0;
    }
    free(paths);
    free(xyz);
}

/* The furnace's want[] for a plane y = 0 under the camera: albedo(ctx, mu)
 * at NTAB + 1 cosines across the range of the camera rays' |d_y| (linear
 * between), for each of the w h spp paths; *lo, *hi the range. */
static inline double *cl_test_plane_want(const cl_test_scene *s, spm_u32 seed, int spp,
                                         double (*albedo)(void *, double), void *ctx,
                                         double *lo, double *hi)
{
    enum { NTAB = 64 };
    spm_trace_params p = cl_test_params(s, seed, 0, (spm_u32)spp);
    size_t n = (size_t)p.cam.width * (size_t)p.cam.height * (size_t)spp;
    double tab[NTAB + 1];
    double *want = spm_xcalloc(n, sizeof *want);
    *lo = 1.0, *hi = 0.0;
    for (size_t i = 0; i < n; i++) {
        double d[3];
        cl_test_camera_dir(&p, i, d);
        *lo = fmin(*lo, fabs(d[1]));
        *hi = fmax(*hi, fabs(d[1]));
    }
    for (int k = 0; k <= NTAB; k++)
        tab[k] = albedo(ctx, *lo + (*hi - *lo) * k / NTAB);
    for (size_t i = 0; i < n; i++) {
        double d[3];
        cl_test_camera_dir(&p, i, d);
        double u = (fabs(d[1]) - *lo) / (*hi - *lo) * NTAB;
        int k = (int)u < NTAB ? (int)u : NTAB - 1;
        want[i] = tab[k] + (u - k) * (tab[k + 1] - tab[k]);
    }
    return want;
}

/* A UV sphere of radius 1 at the origin, flat triangles of material mat, to
 * scene file f: 24 bands of 48 quads (fans at the poles). */
static inline void cl_test_write_sphere(FILE *f, const char *mat)
{
    const int nt = 24, np = 48;
    for (int i = 0; i < nt; i++)
        for (int k = 0; k < np; k++) {
            double v[4][3];
            for (int c = 0; c < 4; c++) {
                double th = M_PI * (i + (c == 2 || c == 3)) / nt;
                double ph = 2.0 * M_PI * (k + (c == 1 || c == 2)) / np;
                v[c][0] = sin(th) * cos(ph), v[c][1] = cos(th), v[c][2] = sin(th) * sin(ph);
            }
            if (i > 0)
                fprintf(f, "tri %s %.9g %.9g %.9g  %.9g %.9g %.9g  %.9g %.9g %.9g\n", mat,
                        v[0][0], v[0][1], v[0][2], v[1][0], v[1][1], v[1][2], v[2][0], v[2][1],
                        v[2][2]);
            if (i < nt - 1)
                fprintf(f, "tri %s %.9g %.9g %.9g  %.9g %.9g %.9g  %.9g %.9g %.9g\n", mat,
                        v[0][0], v[0][1], v[0][2], v[2][0], v[2][1], v[2][2], v[3][0], v[3][1],
                        v[3][2]);
        }
}
/* ---- kernels against the reference, every mode --------------------------- */

/* Compares the kernel's trace of the first mode's pass with the reference's
 * records cp and level bytes cl (n paths), by the caller's CHECKs. */
typedef void (*cl_test_trace_check)(void *ctx, const cl_test_scene *s, spm_cl_renderer *r,
                                    const spm_path *cp, const uint8_t *cl, size_t n);

/* For every mode on scene s (seed, spp, its test size): the reference traces
 * with the mode's level table, check(ctx, ...) compares the kernel's trace in
 * the first mode, and the shade kernel shades the reference's records against
 * the reference's shading, each component within rel of its path's largest
 * (cl_test_shade_diff), printed with the label what. Returns the modes that
 * failed (a renderer not made, a shade error or a component beyond rel). */
static inline int cl_test_modes(cl_test_scene *s, spm_u32 seed, spm_u32 spp, double rel,
                                const char *what, cl_test_trace_check check, void *ctx)
{
    spm_trace_params p = cl_test_params(s, seed, 0, spp);
    size_t n = (size_t)p.cam.width * (size_t)p.cam.height * spp;
    spm_path *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *cl = spm_xcalloc(n, 1);
    float *ref = spm_xcalloc(3 * n, sizeof *ref), *got = spm_xcalloc(3 * n, sizeof *got);
    int failed = 0;
    for (int mode = 0; mode < SPM_MODE_COUNT; mode++) {
        spm_cl_renderer *r;
        spm_error err;
        const char *name = spm_mode(mode)->name;
        if (spm_cl_create(0, &s->geom, &s->tables, mode, seed, &r, &err)) {
            printf("%s %s: spm_cl_create: %s\n", what, name, err.msg);
            failed++;
            continue;
        }
        spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, mode), &p, cp, cl);
        if (mode == 0)
            check(ctx, s, r, cp, cl, n);
        spm_ref_shade(&s->tables, mode, &p, 0, cp, cl, n, ref);
        int rc = spm_cl_shade(r, 0, spp, cp, cl, got, &err);
        double worst = 0.0;
        size_t bad = rc ? 0 : cl_test_shade_diff(ref, got, n, rel, &worst);
        printf("%s shade %-5s: worst %.3g relative, %zu components beyond %g%s%s\n", what, name,
               worst, bad, rel, rc ? "; spm_cl_shade: " : "", rc ? err.msg : "");
        failed += rc || bad;
        spm_cl_destroy(r);
    }
    free(cp);
    free(cl);
    free(ref);
    free(got);
    return failed;
}
#endif
