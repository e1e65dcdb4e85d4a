/* Pass images of the OpenCL backend: repeatable bit for bit with the same
 * seed, different with another, close to the CPU reference backend's, with
 * consistent statistics; device errors are reported, not fatal. */
#include "cl_testlib.h"
#include "testutil.h"

#define W 32
#define H 24
#define SPP 4
#define SEED 5u

static int pass_image(const cl_test_scene *s, int mode, spm_u32 seed, spm_u32 first, float *img,
                      spm_pass_stats *st)
{
    spm_cl_renderer *r;
    spm_error err;
    memset(st, 0, sizeof *st);
    if (spm_cl_create(0, &s->geom, &s->tables, mode, seed, &r, &err)) {
        CHECK(0, "spm_cl_create: %s", err.msg);
        return 1;
    }
    int rc = spm_cl_pass(r, first, SPP, img, st, &err);
    CHECK(rc == 0, "spm_cl_pass: %s", err.msg);
    spm_cl_destroy(r);
    return rc;
}

static void repeatability(const cl_test_scene *s)
{
    size_t np = (size_t)W * H * 3;
    float *a = spm_xcalloc(np, sizeof *a), *b = spm_xcalloc(np, sizeof *b),
          *c = spm_xcalloc(np, sizeof *c);
    spm_pass_stats st;
    pass_image(s, SPM_MODE_ML, SEED, 0, a, &st);
    pass_image(s, SPM_MODE_ML, SEED, 0, b, &st);
    pass_image(s, SPM_MODE_ML, SEED + 1, 0, c, &st);
    CHECK(memcmp(a, b, np * sizeof *a) == 0, "same seed, different pass images");
    CHECK(memcmp(a, c, np * sizeof *a) != 0, "another seed gave the same image");

    /* statistics: every path counted once, at some level */
    uint64_t sum = 0;
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        for (int k = 0; k < 3; k++)
            sum += st.level_paths[l][k];
    CHECK(st.paths == (uint64_t)W * H * SPP, "paths %llu", (unsigned long long)st.paths);
    CHECK(sum == st.paths, "level counts sum to %llu of %llu", (unsigned long long)sum,
          (unsigned long long)st.paths);
    CHECK(st.trace_s > 0.0 && st.shade_s > 0.0 && st.accum_s > 0.0,
          "stage times %g %g %g", st.trace_s, st.shade_s, st.accum_s);
    CHECK(st.nonfinite == 0, "%llu non-finite samples", (unsigned long long)st.nonfinite);
    free(a);
    free(b);
    free(c);
}

/* The whole pass against the CPU backend: equal up to the rare diverged path
 * (test_cl_trace: ~1e-4 of paths) and per-path rounding (test_cl_shade: a few
 * ulps). One diverged path moves its pixel by at most its own sample, about
 * 1/(npix*spp) of the image total for a typical sample, so the summed
 * absolute difference over the image stays below 1% of the summed Y. */
static void against_cpu(const cl_test_scene *s, int mode)
{
    size_t npix = (size_t)W * H;
    float *g = spm_xcalloc(npix * 3, sizeof *g), *c = spm_xcalloc(npix * 3, sizeof *c);
    spm_pass_stats st, cst;
    memset(&cst, 0, sizeof cst);
    pass_image(s, mode, SEED, SPP, g, &st);
    spm_render_plan plan;
    spm_error err;
    spm_backend *b = spm_render_plan_init(&plan, &s->geom, &s->tables, mode, SEED, &err)
                         ? NULL
                         : spm_backend_cpu_create(&plan, &err);
    CHECK(b && b->pass(b, SPP, SPP, c, &cst, &err) == 0, "cpu backend: %s", err.msg);
    if (b) {
        b->destroy(b);
        spm_render_plan_free(&plan);
    }
    double diff = 0.0, total = 0.0;
    size_t identical = 0;
    for (size_t i = 0; i < npix * 3; i++) {
        diff += fabs((double)g[i] - (double)c[i]);
        identical += g[i] == c[i];
        if (i % 3 == 1)
            total += c[i];
    }
    printf("mode %d: image difference %.3g of total Y %.4g; %zu of %zu values identical\n", mode,
           diff, total, identical, npix * 3);
    CHECK(total > 0.0, "black image");
    CHECK(diff <= 0.01 * total, "mode %d: OpenCL and CPU images differ by %g (total Y %g)", mode,
          diff, total);
    CHECK(st.truncated == cst.truncated, "truncated %llu vs %llu",
          (unsigned long long)st.truncated, (unsigned long long)cst.truncated);
    free(g);
    free(c);
}

static void device_errors(const cl_test_scene *s)
{
    spm_cl_renderer *r = NULL;
    spm_error err;
    int rc = spm_cl_create(999, &s->geom, &s->tables, SPM_MODE_ML, SEED, &r, &err);
    CHECK(rc != 0 && r == NULL, "device 999 accepted");
    CHECK(strstr(err.msg, "999") && strstr(err.msg, "available: 0:"),
          "error does not list the devices: %s", err.msg);

    /* injected failure: device 0's second pass fails, reported as an error */
    setenv("SPECMIP_CL_FAIL", "0:1", 1);
    rc = spm_cl_create(0, &s->geom, &s->tables, SPM_MODE_ML, SEED, &r, &err);
    unsetenv("SPECMIP_CL_FAIL");
    CHECK(rc == 0, "spm_cl_create: %s", err.msg);
    if (rc)
        return;
    float *img = spm_xcalloc((size_t)W * H * 3, sizeof *img);
    spm_pass_stats st;
    memset(&st, 0, sizeof st);
    CHECK(spm_cl_pass(r, 0, 1, img, &st, &err) == 0, "first pass: %s", err.msg);
    err.msg[0] = 0;
    CHECK(spm_cl_pass(r, 1, 1, img, &st, &err) != 0, "injected failure did not fail");
    CHECK(strstr(err.msg, "injected") != NULL, "message: %s", err.msg);
    spm_cl_destroy(r);
    free(img);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    cl_test_scene s;
    if (cl_test_scene_open(&s, W, H))
        return 1;
    repeatability(&s);
    for (int m = 0; m < SPM_MODE_COUNT; m++)
        against_cpu(&s, m);
    device_errors(&s);
    cl_test_scene_close(&s);
    TEST_END();
}
