/* The harness the material types' kernel tests share (test_cl_conductor,
 * test_cl_dielectric, test_cl_coated): the box comparison -- the kernel's trace against the
 * reference's, path by path (records, the type's vertex words, level bytes),
 * and each mode's shade kernel against the reference's shading of the same
 * records. Each test keeps its own tolerances and counts (tb_box's hooks). */
#ifndef TYPEBOX_TESTLIB_H
#define TYPEBOX_TESTLIB_H
#include "cl_testlib.h"
#include "spm_rng.h"
#include "testutil.h"

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

/* the kernel's trace against the reference's (cp, cl): cl_test_modes' check */
static void tb_box_trace(void *ctx, const cl_test_scene *s, spm_cl_renderer *r,
                         const spm_path *cp, const uint8_t *cl, size_t n)
{
    const tb_box *b = ctx;
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
    int failed = cl_test_modes(&s, b->seed, (spm_u32)b->spp, b->shade_rel, "box", tb_box_trace,
                               (void *)b);
    CHECK(failed == 0, "%d modes shade %s off the reference", failed, b->scene);
    cl_test_scene_close(&s);
}
#endif
