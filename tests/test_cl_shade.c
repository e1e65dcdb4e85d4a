/* Each shade kernel on the CPU reference's records against the CPU shading,
 * per path. Records and level bytes come from spm_ref_trace, so both sides
 * shade exactly the same input. */
#include "cl_testlib.h"
#include "render_setup.h"
#include "testutil.h"

/* 7 samples a pixel: hero's kernel divides a path's index by spp with a
 * multiply and shifts, trivial for a power of two. Batches of BATCH_PIX
 * pixels end inside the lit image, in a part work-group (1407 paths: 63 of
 * the last 64), whose part vector of 16 hero draws from fewer indices. */
#define BATCH_PIX 201
#define W 23
#define H 24
#define SPP 7
#define SEED 11u

/* Both sides compute the same products and sums in float, but not in the same
 * order: the kernel fuses L += P*E*c into one fma (one rounding instead of
 * two) and sums the XYZ dot product as vector lanes then a pairwise
 * horizontal sum, where the CPU adds lanes left to right. Each rounding is
 * half an ulp of its partial result: the products along a path of a few
 * vertices differ by a few ulps, and re-ordering an n-lane sum of positive
 * terms typically moves it by about log2(n) ulps. So the bound is
 * 4 + 2 log2(lanes) ulps of the largest XYZ component (2^-23 relative each):
 * 7 for rgb, 8 for hero, 17 for 80 bins, 21 for truth's 400. The largest
 * component, not each, because rgb's matrix has negative entries whose
 * cancellation can leave a component small against its terms. hero's lanes
 * add no more: both sides compute y, the density and the weights with the
 * same uncontracted float operations, and pick each lane's 1 nm bin by
 * comparing y with the same bin edges, so atanh's rounding, which differs
 * between the OpenCL library and the C one, never changes which bin a lane
 * reads (a lane in the wrong bin would be off by percents, not ulps). */
static double ulps_allowed(int lanes)
{
    return 4.0 + 2.0 * log2((double)lanes);
}

static void check_mode(const cl_test_scene *s, int mode, const char *name, int lanes)
{
    const double allowed = ulps_allowed(lanes);
    size_t n = (size_t)W * H * SPP;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *ref = spm_xcalloc(3 * n, sizeof *ref), *got = spm_xcalloc(3 * n, sizeof *got);
    spm_trace_params p = cl_test_params(s, SEED, 3 * SPP, SPP);
    spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, mode), &p, paths, levels);
    spm_ref_shade(&s->tables, mode, &p, 0, paths, levels, n, ref);

    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s->geom, &s->tables, mode, SEED, &r, &err)) {
        CHECK(0, "%s: spm_cl_create: %s", name, err.msg);
        goto done;
    }
    spm_cl_set_batch_paths(r, (size_t)BATCH_PIX * SPP);
    int rc = spm_cl_shade(r, p.first_sample, SPP, paths, levels, got, &err);
    CHECK(rc == 0, "%s: spm_cl_shade: %s", name, err.msg);
    spm_cl_destroy(r);

    size_t bad = 0, nonzero = 0, worst_i = 0;
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        double m = 0.0;
        for (int c = 0; c < 3; c++)
            m = fmax(m, fabs((double)ref[3 * i + c]));
        nonzero += m > 0.0;
        double ulp = m > 0.0 ? m * ldexp(1.0, -23) : ldexp(1.0, -149);
        for (int c = 0; c < 3; c++) {
            double e = fabs((double)got[3 * i + c] - (double)ref[3 * i + c]) / ulp;
            if (!(e <= allowed))
                bad++;
            if (!(e <= worst)) {
                worst = e;
                worst_i = i;
            }
        }
    }
    printf("%-5s: %zu paths (%zu non-black), worst %.2f ulps of the largest component "
           "(path %zu)\n", name, n, nonzero, worst, worst_i);
    CHECK(nonzero > n / 4, "%s: too few lit paths to compare", name);
    CHECK(bad == 0, "%s: %zu components beyond %.1f ulps (worst %.1f at path %zu: "
          "%g %g %g vs %g %g %g)", name, bad, allowed, worst, worst_i, got[3 * worst_i],
          got[3 * worst_i + 1], got[3 * worst_i + 2], ref[3 * worst_i], ref[3 * worst_i + 1],
          ref[3 * worst_i + 2]);
done:
    free(paths);
    free(levels);
    free(ref);
    free(got);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    cl_test_scene s;
    if (cl_test_scene_open(&s, W, H))
        return 1;
    /* lanes per XYZ sum: the most a shade table of the mode has (truth 400,
     * ref/ml at most level 0's 80, mlc plus its spikes), hero its wavelengths */
    for (int m = 0; m < SPM_MODE_COUNT; m++) {
        const spm_mode_desc *d = spm_mode(m);
        int lanes = 0;
        for (int sl = 0; sl < spm_mode_nslots(d); sl++) {
            spm_shade_table tab = {0};
            d->layout(&s.tables, spm_mode_slot_level(d, sl), &tab);
            lanes = tab.lanes > lanes ? tab.lanes : lanes;
        }
        check_mode(&s, m, d->name, d->per_path ? SPM_HERO_LANES : lanes);
    }
    cl_test_scene_close(&s);
    TEST_END();
}
