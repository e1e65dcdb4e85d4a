/* The kernels' texel spectrum (kernels/texture.clh, not yet wired into the
 * path) against the host: every bin of every level of seeded texels, against
 * the host's Gauss-Legendre in double (the same rule: float rounding only)
 * and, independently, against the 1 nm sums of the model (the truth's bin
 * means: the rule's own error, under 2e-4 by test_rgb2spec_table). */
#include "cl_core.h"
#include "rgb2spec_table.h"
#include "testutil.h"
#include <stdint.h>
#include <stdlib.h>

enum { N = 256 };
static const int order[SPM_NUM_LEVELS] = {1, 2, 3, 4, 6};

static uint64_t rng = 0x2545f4914f6cdd1dull;
static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

int main(void)
{
    spm_error err;
    spm_cl_device *list;
    int nd;
    if (spm_cl_devices(&list, &nd, &err)) {
        printf("no OpenCL device: %s\n", err.msg);
        return 1;
    }
    free(list);
    const spm_rgb2spec_table *t = spm_rgb2spec_srgb(&err);
    CHECK(t != NULL, "table: %s", err.msg);
    spm_cl_ctx c;
    cl_program prog;
    cl_kernel k;
    const char *files[] = {"tests/cl_texture.cl"};
    if (!t || spm_cl_ctx_create(0, &c, &err) || spm_cl_build(&c, files, 1, "", &prog, &err) ||
        spm_cl_kernel(prog, "texel_bins", &k, &err)) {
        printf("set-up: %s\n", err.msg);
        return 1;
    }
    static float texels[N][4], out[N * SPM_TRUTH_BINS];
    static double coef[N][3], scale[N];
    for (int i = 0; i < N; i++) {
        double rgb[3] = {uniform(), uniform(), uniform()};
        if (i % 4 == 0)
            rgb[i % 3] = 0.0; /* the cube's faces: the steepest texels */
        if (i % 2) /* an unbounded texel: a scale above 1 */
            for (int m = 0; m < 3; m++)
                rgb[m] *= 3.0;
        spm_rgb2spec_texel(t, i % 2 ? SPM_TEXEL_UNBOUNDED : SPM_TEXEL_REFLECTANCE, rgb, coef[i],
                           &scale[i]);
        for (int m = 0; m < 3; m++) /* the device's coefficients, and the host's from them */
            coef[i][m] = texels[i][m] = (float)coef[i][m];
        texels[i][3] = (float)scale[i];
    }
    cl_mem in, res;
    if (spm_cl_buffer(&c, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof texels, texels, "texels",
                      &in, &err) ||
        spm_cl_buffer(&c, CL_MEM_WRITE_ONLY, sizeof out, NULL, "bins", &res, &err)) {
        printf("buffers: %s\n", err.msg);
        return 1;
    }
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        cl_int level = l;
        double secs;
        int bins = SPM_LEVEL_BINS(l);
        if (spm_cl_arg(k, 0, sizeof in, &in, "texels", &err) ||
            spm_cl_arg(k, 1, sizeof level, &level, "level", &err) ||
            spm_cl_arg(k, 2, sizeof res, &res, "out", &err) ||
            spm_cl_launch(&c, k, N, 0, &secs, "texel_bins", &err) ||
            spm_cl_read(&c, res, sizeof(float) * N * bins, out, "bins", &err)) {
            CHECK(0, "level %d: %s", l, err.msg);
            continue;
        }
        double worst_rule = 0, worst_truth = 0;
        for (int i = 0; i < N; i++) {
            double g[SPM_TRUTH_BINS], s[SPM_TRUTH_BINS];
            spm_sigmoid_level_gauss(coef[i], l, order[l], g);
            spm_sigmoid_level_sum(coef[i], l, s);
            for (int b = 0; b < bins; b++) {
                double d = out[i * bins + b] / scale[i];
                worst_rule = fmax(worst_rule, fabs(d - g[b]));
                worst_truth = fmax(worst_truth, fabs(d - s[b]));
            }
        }
        printf("level %d: kernel vs host rule max %.3g, vs the 1 nm sums max %.3g\n", l,
               worst_rule, worst_truth);
        /* float: S's argument is rounded at |z| up to a few hundred (measured 1.2e-6) */
        CHECK(worst_rule < 1e-5, "level %d: kernel vs host Gauss-Legendre %g", l, worst_rule);
        CHECK(worst_truth < 2e-4, "level %d: kernel vs the 1 nm sums %g", l, worst_truth);
    }
    spm_cl_release_mem(in);
    spm_cl_release_mem(res);
    spm_cl_release_kernel(k);
    spm_cl_release_program(prog);
    spm_cl_ctx_release(&c);
    TEST_END();
}
