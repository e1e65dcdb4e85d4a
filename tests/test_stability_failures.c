/* The bundled scenes built to break a method (their files say which and why).
 * There the bounds of test_stability_bias.c cannot hold, so this test checks
 * that the failure is real (the bound is exceeded where the scene says) and
 * that it is DETECTED: the pretest or the per-occurrence levels choose finer
 * levels, and the per-level path counts (what --stats prints) show paths there.
 * Same seed for all modes: same paths, differences are bias only.
 * T is the pretest threshold (2.0 ΔE00); the reasons for the bounds used here
 * (p99 <= T, mean <= T / 2 against ref) are in test_stability_bias.c. */
#include "testutil.h"
#include "render_testlib.h"

#define T 2.0
#define SIZE 48
#define SPP 8

/* What the tests read from the open set-up. */
typedef struct {
    const char *colour;   /* the colour to look at */
    int found;
    spm_pretest_result pretest;
    int nspikes;
    float spike_wl[SPM_MAX_SPIKES];
} inspect_ctx;

static void inspect(const spm_render_setup *s, void *arg)
{
    inspect_ctx *c = arg;
    int i = rt_colour(&s->scene, c->colour);
    c->found = i >= 0;
    if (i >= 0)
        c->pretest = s->tables.pretest[i];
    c->nspikes = s->tables.nspikes;
    memcpy(c->spike_wl, s->tables.spike_wl, sizeof c->spike_wl);
}

static int render(const char *scene, int mode, double threshold, rt_render_out *o, inspect_ctx *c)
{
    rt_render_job j = {scene, mode, SPP, 1, SIZE, threshold, NULL};
    int rc = rt_render(&j, o, c ? inspect : NULL, c);
    CHECK(!rc, "%s %s: render failed", scene, spm_mode_name(mode));
    return rc;
}

static spm_de_stats compare(const char *scene, const char *what, const rt_render_out *a,
                            const rt_render_out *b)
{
    spm_de_stats d;
    memset(&d, 0, sizeof d);
    CHECK(!rt_compare(&a->img, &b->img, &d), "%s %s: compare failed", scene, what);
    printf("%-20s %-12s dE00 mean %.3f p99 %.3f max %.3f\n", scene, what, d.mean, d.p99, d.max);
    return d;
}

/* A light 4 nm wide (587-591 nm) over reflectance steps inside it. ref's 5 nm
 * bins cannot resolve it (ref vs truth measured mean 1.1, p99 3.1), so:
 * ml must detect it - the pretest, which measures every level against 1 nm,
 * keeps the line at level 0 (1 nm) and the line's paths are shaded there, set
 * by the emitter - and so hold p99 <= T against truth at T = 1 and 2, where
 * a 5 nm top of the chain could not (ml vs truth p99 2.3 at both: ref's
 * error); mlc carries the line as a spike lane at its centroid and beats ref
 * against truth. */
static void narrowline(void)
{
    const char *sc = "narrowline.scene";
    rt_render_out truth, ref, ml, ml1, mlc;
    inspect_ctx c = {"line589", 0, {0}, 0, {0}};
    if (render(sc, SPM_MODE_TRUTH, 0, &truth, NULL) | render(sc, SPM_MODE_REF, 0, &ref, NULL) |
        render(sc, SPM_MODE_ML, 0, &ml, &c) | render(sc, SPM_MODE_ML, 1.0, &ml1, NULL) |
        render(sc, SPM_MODE_MLC, 0, &mlc, NULL))
        goto out;
    spm_de_stats rt = compare(sc, "ref/truth", &truth, &ref);
    CHECK(rt.p99 > T / 2, "narrowline: ref vs truth p99 %.3f: the scene no longer breaks 5 nm bins",
          rt.p99);
    CHECK(c.found && c.pretest.level == 0, "narrowline: pretest level of the line %d, not 0",
          c.pretest.level);
    /* the line lights every path that reaches the light: most of the image.
     * A path's level is set by the first colour met that asks for it, so
     * count level 0 set by either. */
    unsigned long long l0 = ml.run.total.level_paths[0][SPM_SETBY_EMITTER] +
                            ml.run.total.level_paths[0][SPM_SETBY_REFLECTOR];
    printf("narrowline ml: %llu of %llu paths at level 0\n", l0,
           (unsigned long long)ml.run.total.paths);
    CHECK(l0 * 2 > ml.run.total.paths, "narrowline: only %llu paths at level 0", l0);
    spm_de_stats mt = compare(sc, "ml/truth", &truth, &ml);
    spm_de_stats mt1 = compare(sc, "ml(T=1)/truth", &truth, &ml1);
    CHECK(mt.p99 <= T && mt.mean <= T / 2, "narrowline: ml vs truth mean %.3f p99 %.3f", mt.mean,
          mt.p99);
    CHECK(mt1.p99 <= 1.0, "narrowline: ml (threshold 1) vs truth p99 %.3f > 1", mt1.p99);
    int lane = -1;
    for (int k = 0; k < c.nspikes; k++)
        if (fabs(c.spike_wl[k] - 589.0) <= 1.0)
            lane = k;
    CHECK(lane >= 0, "narrowline: no spike lane at 589 +- 1 nm (%d lanes)", c.nspikes);
    spm_de_stats ct = compare(sc, "mlc/truth", &truth, &mlc);
    CHECK(ct.mean < rt.mean, "narrowline: mlc vs truth mean %.3f not below ref's %.3f", ct.mean,
          rt.mean);
out:
    spm_image_free(&truth.img), spm_image_free(&ref.img), spm_image_free(&ml.img),
        spm_image_free(&ml1.img), spm_image_free(&mlc.img);
}

/* One saturated reflectance everywhere: a path's colour is R^k. The pretest's
 * context B sees R^k drift at coarse levels (level_k finer for larger k) and
 * the level feeler puts the paths that meet the wall often at a finer level.
 * Context B covers every occurrence count a path can have, so the long chains
 * (one path in seven meets the wall 9 times or more) are held to the
 * threshold too: against truth on the same paths, p99 <= T at T = 1 and 2
 * (with a table that stopped at k = 8 the error ignored the threshold: p99
 * 1.8 at both). ml with the per-occurrence levels must also beat ml forced to
 * the coarsest level everywhere (threshold 1000: no level is rejected). */
static void saturated_box(void)
{
    const char *sc = "saturated_box.scene";
    rt_render_out truth, ref, ml, ml1, coarse;
    inspect_ctx c = {"sat_yellow", 0, {0}, 0, {0}};
    if (render(sc, SPM_MODE_TRUTH, 0, &truth, NULL) | render(sc, SPM_MODE_REF, 0, &ref, NULL) |
        render(sc, SPM_MODE_ML, 0, &ml, &c) | render(sc, SPM_MODE_ML, 1.0, &ml1, NULL) |
        render(sc, SPM_MODE_ML, 1000.0, &coarse, NULL))
        goto out;
    CHECK(c.found, "saturated_box: no colour sat_yellow");
    int l1 = c.pretest.level_k[0], lmax = c.pretest.level_k[SPM_PRETEST_KMAX - 1];
    printf("saturated_box: pretest level for k = 1: %d, for k = %d: %d\n", l1, SPM_PRETEST_KMAX,
           lmax);
    CHECK(lmax < l1, "saturated_box: the pretest does not ask finer levels for repeated reflection");
    unsigned long long finer = 0;
    for (int l = 0; l < l1 && l < SPM_NUM_LEVELS; l++)
        finer += ml.run.total.level_paths[l][SPM_SETBY_REFLECTOR];
    printf("saturated_box ml: %llu of %llu paths finer than level %d, set by the wall\n", finer,
           (unsigned long long)ml.run.total.paths, l1);
    CHECK(finer > 0, "saturated_box: no path at a finer level than the k = 1 level");
    spm_de_stats rt = compare(sc, "ref/truth", &truth, &ref);
    spm_de_stats mt = compare(sc, "ml/truth", &truth, &ml);
    spm_de_stats mt1 = compare(sc, "ml(T=1)/truth", &truth, &ml1);
    /* ref's own error against truth (measured p99 0.15) is well under T = 1:
     * the error here is the coarse levels' */
    CHECK(rt.p99 < 0.5, "saturated_box: ref vs truth p99 %.3f", rt.p99);
    CHECK(mt.p99 <= T, "saturated_box: ml vs truth p99 %.3f > %.3f", mt.p99, T);
    CHECK(mt1.p99 <= 1.0, "saturated_box: ml (threshold 1) vs truth p99 %.3f > 1", mt1.p99);
    spm_de_stats d = compare(sc, "ml/ref", &ref, &ml);
    spm_de_stats dc = compare(sc, "ml(all L2)/ref", &ref, &coarse);
    CHECK(d.mean <= T / 2, "saturated_box: ml vs ref mean %.3f > %.3f", d.mean, T / 2);
    CHECK(d.mean < dc.mean, "saturated_box: per-occurrence levels (%.3f) no better than the "
                            "coarsest level (%.3f)", d.mean, dc.mean);
out:
    spm_image_free(&truth.img), spm_image_free(&ref.img), spm_image_free(&ml.img),
        spm_image_free(&ml1.img), spm_image_free(&coarse.img);
}

/* A closed box of 0.97 magenta with steep 5 nm edges inside 20 nm bins: long
 * chains again, but here a coarse level's error in R^k is mostly one of
 * luminance (a 20 nm bin's mean raised to the k-th power is darker than the
 * mean of R^k), which the pretest measured as nothing while it scaled each
 * product to its own luminance: ml vs truth p99 4.4 at T = 2. Even 5 nm bins
 * miss it on the longest chains (ref vs truth p99 1.6), so at T = 1 only the
 * 1 nm top of the chain holds the bound (ml vs truth p99 1.65 with a 5 nm
 * top): ml must hold p99 <= T against truth at T = 1 and 2, with the long
 * chains' paths at level 0, set by the wall. */
static void magenta_box(void)
{
    const char *sc = "magenta_box.scene";
    rt_render_out truth, ref, ml, ml1;
    if (render(sc, SPM_MODE_TRUTH, 0, &truth, NULL) | render(sc, SPM_MODE_REF, 0, &ref, NULL) |
        render(sc, SPM_MODE_ML, 0, &ml, NULL) | render(sc, SPM_MODE_ML, 1.0, &ml1, NULL))
        goto out;
    spm_de_stats rt = compare(sc, "ref/truth", &truth, &ref);
    spm_de_stats mt = compare(sc, "ml/truth", &truth, &ml);
    spm_de_stats mt1 = compare(sc, "ml(T=1)/truth", &truth, &ml1);
    CHECK(rt.p99 > 1.0, "magenta_box: ref vs truth p99 %.3f: the scene no longer breaks 5 nm bins",
          rt.p99);
    CHECK(mt.p99 <= T, "magenta_box: ml vs truth p99 %.3f > %.3f", mt.p99, T);
    CHECK(mt1.p99 <= 1.0, "magenta_box: ml (threshold 1) vs truth p99 %.3f > 1", mt1.p99);
    unsigned long long l0 = ml1.run.total.level_paths[0][SPM_SETBY_REFLECTOR];
    printf("magenta_box ml (T=1): %llu of %llu paths at level 0, set by the wall\n", l0,
           (unsigned long long)ml1.run.total.paths);
    CHECK(l0 > 0, "magenta_box: no path at level 0 at threshold 1");
out:
    spm_image_free(&truth.img), spm_image_free(&ref.img), spm_image_free(&ml.img),
        spm_image_free(&ml1.img);
}

/* Mean of a per-pixel map over columns [x0, x1). */
static double half_mean(const double *map, int x0, int x1)
{
    double s = 0.0;
    for (int y = 0; y < SIZE; y++)
        for (int x = x0; x < x1; x++)
            s += map[y * SIZE + x];
    return s / ((double)SIZE * (x1 - x0));
}

/* Two metameric greys under D65 (left half) and F11 (right half): rgb reduces
 * both to one D65-referred RGB, so it is wrong under F11 - and nothing in rgb can
 * notice. The failure is real (rgb vs truth p99 > T) and lies in the F11 half,
 * while the spectral modes hold the bound there (ml and mlc vs truth). */
static void metameric(void)
{
    const char *sc = "metameric.scene";
    rt_render_out truth, rgb, ml, mlc;
    if (render(sc, SPM_MODE_TRUTH, 0, &truth, NULL) | render(sc, SPM_MODE_RGB, 0, &rgb, NULL) |
        render(sc, SPM_MODE_ML, 0, &ml, NULL) | render(sc, SPM_MODE_MLC, 0, &mlc, NULL))
        goto out;
    double *map = NULL;
    spm_de_stats d;
    CHECK(!rt_compare_map(&truth.img, &rgb.img, &d, &map), "metameric: compare failed");
    if (!map)
        goto out;
    double left = half_mean(map, 0, SIZE / 2), right = half_mean(map, SIZE / 2, SIZE);
    printf("metameric rgb/truth: dE00 mean %.3f p99 %.3f; left (D65) %.3f, right (F11) %.3f\n",
           d.mean, d.p99, left, right);
    free(map);
    CHECK(d.p99 > T, "metameric: rgb vs truth p99 %.3f: the scene no longer breaks rgb", d.p99);
    CHECK(right > 2 * left, "metameric: rgb's error not in the F11 half (%.3f vs %.3f)", right,
          left);
    spm_de_stats m = compare(sc, "ml/truth", &truth, &ml);
    spm_de_stats mc = compare(sc, "mlc/truth", &truth, &mlc);
    CHECK(m.p99 <= T && mc.p99 <= T, "metameric: spectral modes vs truth p99 %.3f, %.3f", m.p99,
          mc.p99);
out:
    spm_image_free(&truth.img), spm_image_free(&rgb.img), spm_image_free(&ml.img),
        spm_image_free(&mlc.img);
}

int main(void)
{
    narrowline();
    saturated_box();
    magenta_box();
    metameric();
    TEST_END();
}
