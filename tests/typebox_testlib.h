/* The harness the material types' kernel tests share (test_cl_conductor,
 * test_cl_dielectric, test_cl_coated): a path's camera ray in double for the
 * closed forms, and the box comparison -- the kernel's trace against the
 * reference's, path by path (records, the type's vertex words, level bytes),
 * and each mode's shade kernel against the reference's shading of the same
 * records. Each test keeps its own tolerances and counts (tb_box's hooks). */
#ifndef TYPEBOX_TESTLIB_H
#define TYPEBOX_TESTLIB_H
#include "cl_testlib.h"
#include "spm_rng.h"
#include "testutil.h"

/* The camera ray of path i (spm_shared.h spm_camera), in double. */
static void tb_camera_dir(const spm_trace_params *p, size_t i, double d[3])
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

/* as test_cl_trace: a path may diverge only where a few ulps of cos/sin move
 * a ray across an edge; 1 in 1000 is a generous ceiling */
#define TB_MAX_DIVERGENT_FRACTION 1e-3

/* A box comparison: the scene (tests/data/scenes), its size and seed, the
 * shade stage's bound relative to a path's largest component, and the type's
 * hooks: words_differ, whether two records of the same path differ in the
 * type's words beyond its tolerances; count, called for every path of the
 * reference's trace with the kernel's record (diverged: the two took
 * different paths); report, printing and checking the type's counts. */
typedef struct {
    const char *scene;
    int w, h, spp;
    spm_u32 seed;
    double shade_rel;
    int (*words_differ)(const spm_path *kernel, const spm_path *ref);
    void (*count)(const cl_test_scene *s, const spm_path *kernel, const spm_path *ref, int diverged,
                  void *ctx);
    void (*report)(size_t n, void *ctx);
    void *ctx;
} tb_box;

/* the kernel's trace against the reference's (cp, cl) */
static void tb_box_trace(const tb_box *b, const cl_test_scene *s, spm_cl_renderer *r, size_t n,
                         const spm_path *cp, const uint8_t *cl)
{
    spm_path *gp = spm_xcalloc(n, sizeof *gp);
    uint8_t *gl = spm_xcalloc(n, 1);
    spm_error err;
    int rc = spm_cl_trace(r, 0, (spm_u32)b->spp, gp, gl, &err);
    CHECK(rc == 0, "spm_cl_trace: %s", err.msg);
    size_t diverged = 0, xdiff = 0, level_diff = 0;
    for (size_t i = 0; !rc && i < n; i++) {
        int d = cl_test_path_differs(&gp[i], &cp[i]);
        diverged += d;
        xdiff += !d && b->words_differ(&gp[i], &cp[i]);
        level_diff += !d && gl[i] != cl[i];
        b->count(s, &gp[i], &cp[i], d, b->ctx);
    }
    printf("box trace: %zu paths; %zu diverged, %zu vertex words differ, %zu level bytes "
           "differ\n", n, diverged, xdiff, level_diff);
    b->report(n, b->ctx);
    CHECK((double)diverged <= TB_MAX_DIVERGENT_FRACTION * (double)n, "%zu paths diverged",
          diverged);
    CHECK(xdiff == 0, "%zu paths' vertex words differ", xdiff);
    CHECK(level_diff == 0, "%zu level bytes differ", level_diff);
    free(gp);
    free(gl);
}

static void tb_box_run(const tb_box *b)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/scenes/%s", SPM_SOURCE_DIR, b->scene);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, b->w, b->h)) {
        CHECK(0, "%s loads", b->scene);
        return;
    }
    size_t n = (size_t)b->w * b->h * b->spp;
    spm_path *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *cl = spm_xcalloc(n, 1);
    float *ref = spm_xcalloc(3 * n, sizeof *ref), *got = spm_xcalloc(3 * n, sizeof *got);
    spm_trace_params p = cl_test_params(&s, b->seed, 0, (spm_u32)b->spp);
    for (int mode = 0; mode < SPM_MODE_COUNT; mode++) {
        spm_cl_renderer *r;
        spm_error err;
        if (spm_cl_create(0, &s.geom, &s.tables, mode, b->seed, &r, &err)) {
            CHECK(0, "spm_cl_create: %s", err.msg);
            continue;
        }
        const char *name = spm_mode(mode)->name;
        spm_ref_trace(&s.geom, s.tables.materials, cl_test_lvlk(&s.tables, mode), &p, cp, cl);
        if (mode == 0) /* the records do not depend on the mode (test_cl_trace) */
            tb_box_trace(b, &s, r, n, cp, cl);
        spm_ref_shade(&s.tables, mode, &p, 0, cp, cl, n, ref);
        int rc = spm_cl_shade(r, 0, (spm_u32)b->spp, cp, cl, got, &err);
        CHECK(rc == 0, "%s: spm_cl_shade: %s", name, err.msg);
        double worst = 0.0;
        size_t bad = rc ? 0 : cl_test_shade_diff(ref, got, n, b->shade_rel, &worst);
        printf("box shade %-5s: worst %.3g relative\n", name, worst);
        CHECK(bad == 0, "%s: %zu components beyond %g (worst %.3g)", name, bad, b->shade_rel,
              worst);
        spm_cl_destroy(r);
    }
    free(cp);
    free(cl);
    free(ref);
    free(got);
    cl_test_scene_close(&s);
}
#endif
