/* Strategies that must agree: on scenes/strategies.scene (rough and smooth
 * conductors, a rough coating, rough and smooth glass under a large dim and a
 * small bright light, each two triangles picked by power) and on
 * scenes/emissive_texture.scene (a room lit by a textured light: the texel a
 * light sample's point looks up against the one a lobe's ray hits), the full
 * MIS estimator, light sampling alone and the material's lobe alone
 * (SPECMIP_TEST_STRATEGY, host/cpu/refcpu_trace.c) estimate the same image.
 *
 * Each strategy renders the scene (CPU reference, rgb: the strategies are
 * colour-independent) under SEEDS seeds; per block (4, 8, 16 and 32 pixels
 * a side) the difference of MIS and each strategy alone per seed (the same
 * paths, weighed differently), its mean over the seeds and standard error;
 * z = mean / se must stay within the two-sided normal bound at the
 * Sidak-corrected level for all the blocks of both pairs under both samplers (ALPHA overall). The seeds are fixed, so the result is
 * deterministic; ALPHA is the chance a correct estimator fails on a seed set.
 *
 * A bug the kernels and the reference share is seen here: MIS weighted with
 * the wrong light density (the light-pick probability dropped at a lobe's
 * emitter hit) darkens the glossy highlights in MIS alone (tools/mutants.txt
 * mis-light-pick). The strategies must also differ per seed (a switch that
 * did nothing would agree trivially). All of it by the power selection and
 * through the light tree, whose pmf at a lobe's emitter hit is the walk's
 * from the vertex that sampled the lobe. */
#include <stdlib.h>
#include "render_testlib.h"
#include "stats_testlib.h"
#include "testutil.h"

#define SIZE 32
#define NB (64 + 16 + 4 + 1) /* blocks of 4, 8, 16 and 32 pixels a side */
#define SEEDS 16
#define SPP 96
#define ALPHA 1e-3

static const char *const strategies[3] = {NULL, "light", "lobe"};

/* Block means of the luminance of one render, into b[NB] (the 4x4 blocks,
 * then 8x8, 16x16 and the whole image: a bias spread thin over the image
 * shows at the coarser scales); 0 or 1 on failure. */
static int render_blocks(const char *scene, const char *strategy, int sampler, spm_u32 seed,
                         double *b)
{
    if (strategy)
        setenv("SPECMIP_TEST_STRATEGY", strategy, 1);
    else
        unsetenv("SPECMIP_TEST_STRATEGY");
    rt_render_job j = {scene, SPM_MODE_RGB, SPP, seed, SIZE, 0.0, "cpu"};
    rt_light_sampler = sampler;
    rt_render_out o;
    if (rt_render(&j, &o, NULL, NULL))
        return 1;
    for (int i = 0; i < NB; i++)
        b[i] = 0.0;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            const float *c = &o.img.rgb[3 * ((size_t)y * SIZE + (size_t)x)];
            double lum = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            int at = 0;
            for (int side = 4; side <= SIZE; side *= 2) {
                int per_row = SIZE / side;
                b[at + (y / side) * per_row + x / side] += lum / (side * side);
                at += per_row * per_row;
            }
        }
    free(o.img.rgb);
    return 0;
}

/* The three strategies on one scene under one light sampler, compared
 * pairwise per block. */
static void compare(const char *scene, int sampler)
{
    static double blk[3][SEEDS][NB];
    const char *sname = sampler == SPM_LIGHT_SAMPLER_TREE ? "tree" : "power";
    for (int s = 0; s < 3; s++)
        for (int k = 0; k < SEEDS; k++)
            if (render_blocks(scene, strategies[s], sampler, 1000u + (spm_u32)k, blk[s][k])) {
                CHECK(0, "%s: render %s seed %d", scene, strategies[s] ? strategies[s] : "mis", k);
                return;
            }
    unsetenv("SPECMIP_TEST_STRATEGY");
    /* the strategies trace the same paths (the same random numbers) and only
     * weigh them differently, so the differences per seed are far less noisy
     * than either image: a paired test on them */
    double zmax_allowed = st_normal_two_sided(st_sidak(ALPHA, 4 * NB));
    for (int s = 1; s < 3; s++) {
        double worst = 0.0, dm_at = 0.0, se_at = 0.0, image[2] = {0.0, 0.0};
        int at = -1, differ = 0;
        for (int i = 0; i < NB; i++) {
            double dm = 0.0, v = 0.0;
            for (int k = 0; k < SEEDS; k++)
                dm += (blk[0][k][i] - blk[s][k][i]) / SEEDS;
            for (int k = 0; k < SEEDS; k++) {
                double d = blk[0][k][i] - blk[s][k][i] - dm;
                v += d * d / (SEEDS - 1);
            }
            double se = sqrt(v / SEEDS);
            double z = se > 0.0 ? fabs(dm) / se : (dm != 0.0 ? INFINITY : 0.0);
            if (z > worst)
                worst = z, at = i, dm_at = dm, se_at = se;
            differ += blk[0][0][i] != blk[s][0][i];
        }
        for (int k = 0; k < SEEDS; k++)
            image[0] += blk[0][k][NB - 1] / SEEDS, image[1] += blk[s][k][NB - 1] / SEEDS;
        printf("%s (%s): mis vs %-5s: image mean %.5f vs %.5f, worst block %d: difference %.5f "
               "+- %.5f, |z| %.2f (bound %.2f)\n", scene, sname, strategies[s], image[0], image[1],
               at, dm_at, se_at, worst, zmax_allowed);
        CHECK(worst <= zmax_allowed, "%s (%s): mis vs %s: block %d differs by %.5f +- %.5f, |z| %.2f > %.2f",
              scene, sname, strategies[s], at, dm_at, se_at, worst, zmax_allowed);
        CHECK(differ > NB / 4, "%s: mis vs %s: only %d of %d blocks differ for one seed: the "
              "switch did nothing?", scene, strategies[s], differ, NB);
        CHECK(image[0] > 0.0, "the image is black");
    }
}

int main(int argc, char **argv)
{
    rt_keep_scene = 1; /* each scene's pretest once, not per strategy and seed */
    if (argc > 1) { /* one scene of scenes/, by name */
        compare(argv[1], SPM_LIGHT_SAMPLER_POWER);
        rt_kept_free();
        TEST_END();
    }
    compare("strategies.scene", SPM_LIGHT_SAMPLER_POWER);
    compare("strategies.scene", SPM_LIGHT_SAMPLER_TREE);
    compare("emissive_texture.scene", SPM_LIGHT_SAMPLER_POWER);
    rt_kept_free();
    TEST_END();
}
