/* Spectral records, per path: each spectral mode's shade kernel, compiled
 * for spectral output, against the CPU reference's spectral shading of the
 * same records (spm_ref_trace), bin by bin; and the records' XYZ equal the
 * records the same kernel writes without spectral output (the bins leave
 * the image's colour alone). */
#include "cl_testlib.h"
#include "render_plan.h"
#include "testutil.h"

#define W 16
#define H 16
#define SPP 8
#define SEED 11u

/* The kernel's bins are sums of lane * factor products in the map's order,
 * as the reference's, but from lanes that differ by a few ulps (fma and
 * summation order, see test_cl_shade.c); hero's lane factor is a reciprocal
 * the kernel multiplies by where the reference divides (one more rounding).
 * So: 8 ulps of the path's largest bin plus 2 per summed lane (at most 5,
 * truth's 1 nm lanes into a 5 nm bin). */
#define ULPS 18.0

static int shade_cl(const cl_test_scene *s, const spm_render_plan *plan, const spm_path *paths,
                    const uint8_t *levels, spm_u32 first, float *out)
{
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create_plan(0, plan, &r, &err)) {
        CHECK(0, "%s: spm_cl_create_plan: %s", plan->mode->name, err.msg);
        return 1;
    }
    (void)s;
    int rc = spm_cl_shade(r, first, SPP, paths, levels, out, &err);
    CHECK(rc == 0, "%s: spm_cl_shade: %s", plan->mode->name, err.msg);
    spm_cl_destroy(r);
    return rc;
}

static void check_mode(const cl_test_scene *s, int mode, int nm)
{
    const char *name = spm_mode_name(mode);
    size_t n = (size_t)W * H * SPP;
    spm_render_plan plan, plain;
    spm_error err;
    if (spm_render_plan_init(&plan, &s->geom, &s->tables, mode, SEED, &err) ||
        spm_render_plan_init(&plain, &s->geom, &s->tables, mode, SEED, &err) ||
        spm_render_plan_spectral(&plan, nm, &err)) {
        CHECK(0, "%s: plan: %s", name, err.msg);
        return;
    }
    int ch = plan.pix_ch, nb = plan.nspec;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *ref = spm_xcalloc(n * (size_t)ch, sizeof *ref), *got = spm_xcalloc(n * (size_t)ch, sizeof *got);
    float *xyz = spm_xcalloc(n * 3, sizeof *xyz);
    spm_trace_params p = cl_test_params(s, SEED, 3 * SPP, SPP);
    spm_ref_trace(&s->geom, s->tables.materials, plan.lvlk, &p, paths, levels);
    spm_ref_shade_spectral(plan.mode, plan.shade, plan.spec, ch, &p, 0, paths, levels, n, ref);
    if (shade_cl(s, &plan, paths, levels, p.first_sample, got) ||
        shade_cl(s, &plain, paths, levels, p.first_sample, xyz))
        goto done;
    size_t bad = 0, lit = 0, worst_i = 0, xyz_diff = 0;
    int worst_b = 0;
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const float *a = &ref[i * (size_t)ch + 3], *b = &got[i * (size_t)ch + 3];
        double m = 0.0;
        for (int k = 0; k < nb; k++)
            m = fmax(m, fabs((double)a[k]));
        lit += m > 0.0;
        double ulp = m > 0.0 ? m * ldexp(1.0, -23) : ldexp(1.0, -149);
        for (int k = 0; k < nb; k++) {
            double e = fabs((double)b[k] - (double)a[k]) / ulp;
            bad += !(e <= ULPS);
            if (!(e <= worst))
                worst = e, worst_i = i, worst_b = k;
        }
        for (int c = 0; c < 3; c++)
            xyz_diff += got[i * (size_t)ch + c] != xyz[3 * i + c];
    }
    printf("%-5s %d nm: %zu paths (%zu with light), %d bins, worst %.2f ulps of the path's "
           "largest bin (path %zu, bin %d)\n", name, nm, n, lit, nb, worst, worst_i, worst_b);
    CHECK(lit > n / 4, "%s: too few lit paths to compare", name);
    CHECK(bad == 0, "%s %d nm: %zu bins beyond %.0f ulps (worst %.1f: path %zu bin %d %g vs %g)",
          name, nm, bad, ULPS, worst, worst_i, worst_b, got[worst_i * (size_t)ch + 3 + worst_b],
          ref[worst_i * (size_t)ch + 3 + worst_b]);
    CHECK(xyz_diff == 0, "%s: %zu XYZ components differ with spectral output", name, xyz_diff);
done:
    spm_render_plan_free(&plan);
    spm_render_plan_free(&plain);
    free(paths);
    free(levels);
    free(ref);
    free(got);
    free(xyz);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    cl_test_scene s;
    char path[4096];
    /* spiky light: mlc has spike lanes */
    if (cl_test_scene_load(&s, spm_data_path("scenes/cornell_spiky.scene", path, sizeof path), W, H))
        return 1;
    int modes = 0;
    for (int m = 0; m < SPM_MODE_COUNT; m++)
        for (int nm = 1; nm <= 5; nm += 4)
            if (spm_mode_spec_ok(spm_mode(m), nm)) {
                check_mode(&s, m, nm);
                modes++;
            }
    CHECK(modes == 6, "%d mode and bin width pairs (truth twice, ref, ml, mlc, hero)", modes);
    CHECK(s.tables.nspikes > 0, "the scene has no spike lanes");
    cl_test_scene_close(&s);
    TEST_END();
}
