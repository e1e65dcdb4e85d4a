/* Strategies that must agree: on scenes/strategies.scene (rough and smooth
 * conductors, a rough coating, rough and smooth glass under a large dim and a
 * small bright light, each two triangles picked by power), the full MIS
 * estimator, light sampling alone and the material's lobe alone
 * (SPECMIP_TEST_STRATEGY, host/cpu/refcpu_trace.c) estimate the same image.
 *
 * Each strategy renders the scene (CPU reference, rgb: the strategies are
 * colour-independent) under SEEDS seeds; per 4x4-pixel block the mean
 * luminance over the seeds and its standard error; MIS against each strategy
 * alone block by block, z = (m_a - m_b) / sqrt(se_a^2 + se_b^2), must stay
 * within the two-sided normal bound at the Sidak-corrected level for all the
 * blocks of both pairs (ALPHA overall). The seeds are fixed, so the result is
 * deterministic; ALPHA is the chance a correct estimator fails on a seed set.
 *
 * A bug the kernels and the reference share is seen here: MIS weighted with
 * the wrong light density (the light-pick probability dropped at a lobe's
 * emitter hit) darkens the glossy highlights in MIS alone (tools/mutants.txt
 * mis-light-pick). The strategies must also differ per seed (a switch that
 * did nothing would agree trivially). */
#include <stdlib.h>
#include "render_testlib.h"
#include "stats_testlib.h"
#include "testutil.h"

#define SIZE 32
#define BLOCK 4
#define NB ((SIZE / BLOCK) * (SIZE / BLOCK))
#define SEEDS 12
#define SPP 96
#define ALPHA 1e-3

static const char *const strategies[3] = {NULL, "light", "lobe"};

/* Block means of the luminance of one render, into b[NB]; 0 or 1 on failure. */
static int render_blocks(const char *strategy, spm_u32 seed, double *b)
{
    if (strategy)
        setenv("SPECMIP_TEST_STRATEGY", strategy, 1);
    else
        unsetenv("SPECMIP_TEST_STRATEGY");
    rt_render_job j = {"strategies.scene", SPM_MODE_RGB, SPP, seed, SIZE, 0.0, "cpu"};
    rt_render_out o;
    if (rt_render(&j, &o, NULL, NULL))
        return 1;
    for (int i = 0; i < NB; i++)
        b[i] = 0.0;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            const float *c = &o.img.rgb[3 * ((size_t)y * SIZE + (size_t)x)];
            double lum = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            b[(y / BLOCK) * (SIZE / BLOCK) + x / BLOCK] += lum / (BLOCK * BLOCK);
        }
    free(o.img.rgb);
    return 0;
}

int main(void)
{
    static double blk[3][SEEDS][NB];
    for (int s = 0; s < 3; s++)
        for (int k = 0; k < SEEDS; k++)
            if (render_blocks(strategies[s], 1000u + (spm_u32)k, blk[s][k])) {
                CHECK(0, "render %s seed %d", strategies[s] ? strategies[s] : "mis", k);
                TEST_END();
            }
    unsetenv("SPECMIP_TEST_STRATEGY");
    double mean[3][NB], se[3][NB];
    for (int s = 0; s < 3; s++)
        for (int i = 0; i < NB; i++) {
            double m = 0.0, v = 0.0;
            for (int k = 0; k < SEEDS; k++)
                m += blk[s][k][i] / SEEDS;
            for (int k = 0; k < SEEDS; k++)
                v += (blk[s][k][i] - m) * (blk[s][k][i] - m) / (SEEDS - 1);
            mean[s][i] = m;
            se[s][i] = sqrt(v / SEEDS);
        }
    double zmax_allowed = st_normal_two_sided(st_sidak(ALPHA, 2 * NB));
    for (int s = 1; s < 3; s++) {
        double worst = 0.0, total_a = 0.0, total_b = 0.0;
        int at = -1, differ = 0;
        for (int i = 0; i < NB; i++) {
            double d = mean[0][i] - mean[s][i];
            double e = sqrt(se[0][i] * se[0][i] + se[s][i] * se[s][i]);
            double z = e > 0.0 ? fabs(d) / e : (d != 0.0 ? INFINITY : 0.0);
            if (z > worst)
                worst = z, at = i;
            total_a += mean[0][i], total_b += mean[s][i];
            differ += blk[0][0][i] != blk[s][0][i];
        }
        printf("mis vs %-5s: image mean %.5f vs %.5f, worst block %d: |z| %.2f (bound %.2f)\n",
               strategies[s], total_a / NB, total_b / NB, at, worst, zmax_allowed);
        CHECK(worst <= zmax_allowed, "mis vs %s: block %d (%.5f +- %.5f vs %.5f +- %.5f), |z| %.2f > %.2f",
              strategies[s], at, mean[0][at], se[0][at], mean[s][at], se[s][at], worst, zmax_allowed);
        CHECK(differ > NB / 4, "mis vs %s: only %d of %d blocks differ for one seed: the switch did nothing?",
              strategies[s], differ, NB);
        CHECK(total_a > 0.0, "the image is black");
    }
    TEST_END();
}
