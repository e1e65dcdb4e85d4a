/* The OpenCL kernels render a scene the same in any unit (scale_testlib.h):
 * bit for bit when every coordinate is multiplied by 2^-10 or 2^10, within
 * Monte Carlo noise by 10^-3 or 10^3. Records and per-path XYZ from the
 * trace and shade kernels, the image from a whole pass. */
#include "cl_testlib.h"
#include "scale_testlib.h"

static int render(double scale, int spp, sc_render *r, sc_world *w1)
{
    sc_world w;
    if (sc_world_build(&w, scale))
        return 1;
    sc_render_alloc(r, spp);
    spm_cl_renderer *cl;
    spm_error err;
    int rc = spm_cl_create(0, &w.g, &w.t, SPM_MODE_REF, SC_SEED, &cl, &err);
    if (!rc) {
        spm_pass_stats st;
        memset(&st, 0, sizeof st);
        rc = spm_cl_trace(cl, 0, (spm_u32)spp, r->paths, r->levels, &err) ||
             spm_cl_shade(cl, 0, (spm_u32)spp, r->paths, r->levels, r->xyz, &err) ||
             spm_cl_pass(cl, 0, (spm_u32)spp, r->image, &st, &err);
        spm_cl_destroy(cl);
    }
    if (rc)
        printf("scale %g: %s\n", scale, err.msg);
    if (w1 && !rc)
        *w1 = w;
    else
        sc_world_free(&w);
    return rc;
}

static void run(const double scales[3], int spp, int exact)
{
    sc_render r[3];
    sc_world w1;
    int ok = 1;
    for (int k = 0; k < 3; k++)
        if (render(scales[k], spp, &r[k], k == 1 ? &w1 : NULL)) {
            CHECK(0, "scale %g renders", scales[k]);
            ok = 0;
        }
    if (!ok)
        return;
    if (exact)
        sc_check_exact("OpenCL", r, &w1);
    else
        sc_check_noise("OpenCL", r, spp, &w1);
    for (int k = 0; k < 3; k++)
        sc_render_free(&r[k]);
    sc_world_free(&w1);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    spm_quiet_warnings = 1;
    run((const double[]){1.0 / 1024.0, 1.0, 1024.0}, 64, 1);
    run((const double[]){1e-3, 1.0, 1e3}, 256, 0);
    TEST_END();
}
