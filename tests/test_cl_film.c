/* Pass images of the OpenCL backend: repeatable bit for bit with the same
 * seed, different with another, close to the CPU reference backend's, with
 * consistent statistics; device errors are reported, not fatal. */
#include "backend_cpu.h"
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

/* The whole pass against the CPU backend, explained path by path. The same
 * samples are traced and shaded on each side (test hooks and the reference
 * functions, which the passes run batch by batch) and the records compared:
 * a path diverges when its trace records differ discretely or beyond
 * cl_test_path_differs's weights (a ray within ulps of an edge: PoCL's
 * cos/sin are not glibc's; test_cl_trace), or its level byte differs. Every
 * other path differs only by rounding (the shade kernel's fma contraction and
 * lane sum order, test_cl_shade; the direction's last bits). Both accumulate
 * steps add a pixel's samples in sample order in float, so per pixel channel
 *   |OpenCL - CPU| <= sum over diverged paths of |kernel| + |reference|
 *                   + sum over the others of |kernel - reference|
 *                   + spp half-ulps of each side's sum of |samples|
 * (triangle inequality plus one rounding per addition). Measured (PoCL 5,
 * Xeon, every mode): 0 diverged paths, the others' records differ by 2.2e-8
 * to 2.2e-7 of their summed |XYZ|, the images by 5.5e-8 to 5.2e-7 of total
 * Y, the worst pixel at 0.75 of its bound. Scaling one sample's Y by 1+1e-4
 * in the accumulate kernel puts its pixel at 50-70 times its bound; losing
 * 0.5% of Y there, at 1e4 times. */
#define MAX_DIVERGENT_FRACTION 1e-3
/* The undiverged paths' summed |kernel - reference| against their summed
 * |XYZ|: a few ulps (2^-23 relative each) per path, measured at most 2.2e-7;
 * 1e-5 leaves 45x headroom and catches a shade step off by 1e-5 of the light. */
#define MAX_ROUNDING_REL 1e-5

static void against_cpu(const cl_test_scene *s, int mode)
{
    size_t npix = (size_t)W * H, n = npix * SPP;
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

    /* the same samples, path by path */
    spm_path *gp = spm_xcalloc(n, sizeof *gp), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    float *gx = spm_xcalloc(3 * n, sizeof *gx), *cx = spm_xcalloc(3 * n, sizeof *cx);
    spm_cl_renderer *r;
    int rc = spm_cl_create(0, &s->geom, &s->tables, mode, SEED, &r, &err);
    if (!rc) {
        rc = spm_cl_trace(r, SPP, SPP, gp, gl, &err) ||
             spm_cl_shade(r, SPP, SPP, gp, gl, gx, &err);
        spm_cl_destroy(r);
    }
    CHECK(rc == 0, "kernel records: %s", err.msg);
    spm_trace_params p = cl_test_params(s, SEED, SPP, SPP);
    spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, mode), &p, cp, cl);
    spm_ref_shade(&s->tables, mode, &p, 0, cp, cl, n, cx);

    size_t diverged = 0, over = 0, identical = 0;
    double diff = 0.0, total = 0.0, bound_sum = 0.0, round_diff = 0.0, round_abs = 0.0;
    double worst = 0.0; /* the largest |difference| / bound of a pixel channel */
    for (size_t px = 0; px < npix; px++) {
        double bound[3] = {0.0, 0.0, 0.0}, abs_g[3] = {0.0, 0.0, 0.0}, abs_c[3] = {0.0, 0.0, 0.0};
        for (size_t i = px * SPP; i < (px + 1) * SPP; i++) {
            int d = cl_test_path_differs(&gp[i], &cp[i]) || gl[i] != cl[i];
            diverged += d;
            for (int k = 0; k < 3; k++) {
                double a = gx[3 * i + k], e = cx[3 * i + k];
                abs_g[k] += fabs(a);
                abs_c[k] += fabs(e);
                if (d) {
                    bound[k] += fabs(a) + fabs(e);
                } else {
                    bound[k] += fabs(a - e);
                    round_diff += fabs(a - e);
                    round_abs += fabs(e);
                }
            }
        }
        for (int k = 0; k < 3; k++) {
            size_t j = 3 * px + (size_t)k;
            double e = fabs((double)g[j] - (double)c[j]);
            bound[k] += SPP * ldexp(1.0, -24) * (abs_g[k] + abs_c[k]);
            over += !(e <= bound[k]);
            if (bound[k] > 0.0 && e / bound[k] > worst)
                worst = e / bound[k];
            else if (bound[k] == 0.0 && e > 0.0)
                worst = INFINITY;
            diff += e;
            bound_sum += bound[k];
            identical += g[j] == c[j];
        }
        total += c[3 * px + 1];
    }
    printf("mode %d: %zu of %zu paths diverged; undiverged records differ by %.2g of their "
           "|XYZ|; image difference %.3g (%.2g of total Y %.4g) against a bound of %.3g, worst "
           "pixel at %.2g of its bound; %zu of %zu values identical\n",
           mode, diverged, n, round_abs > 0 ? round_diff / round_abs : 0.0, diff, diff / total,
           total, bound_sum, worst, identical, npix * 3);
    CHECK(total > 0.0 && round_abs > 0.0, "black image");
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "mode %d: %zu of %zu paths diverged",
          mode, diverged, n);
    CHECK(round_diff <= MAX_ROUNDING_REL * round_abs,
          "mode %d: undiverged paths' records differ by %g of their |XYZ|", mode,
          round_diff / round_abs);
    CHECK(over == 0, "mode %d: %zu pixel values differ beyond what diverged paths and rounding "
          "explain (worst at %g of its bound; total difference %g, bound %g)", mode, over, worst,
          diff, bound_sum);
    CHECK(st.truncated == cst.truncated, "truncated %llu vs %llu",
          (unsigned long long)st.truncated, (unsigned long long)cst.truncated);
    free(g);
    free(c);
    free(gp);
    free(cp);
    free(gl);
    free(cl);
    free(gx);
    free(cx);
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
