/* Pretests: trivial and spiky cases; over every bundled spectrum, the errors
 * and levels the pretest reports against their recomputation here and
 * monotonicity in the threshold; context C with two lights; determinism. */
#include "colour.h"
#include "csv.h"
#include "pretest.h"
#include "testutil.h"
#include <dirent.h>
#include <stdlib.h>
#include <string.h>

static const char *data(const char *rel)
{
    static char buf[4096];
    return spm_data_path(rel, buf, sizeof buf);
}

static int run1(const spm_spectrum *s, const spm_spectrum *light, double threshold,
                spm_pretest_result *r)
{
    spm_pretest_opts o;
    spm_pretest_defaults(&o);
    o.threshold = threshold;
    const spm_spectrum *set[2] = {s, light};
    spm_pretest_result res[2];
    spm_pretest_run(set, light ? 2 : 1, &o, res);
    *r = res[0];
    return r->level;
}

static void test_equal_energy(void)
{
    spm_spectrum ee, d65;
    spm_error err;
    spm_pretest_result r;
    spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &ee);
    CHECK(run1(&ee, NULL, 2.0, &r) == SPM_DEFAULT_COARSEST, "equal-energy light: level %d",
          r.level);
    CHECK(r.err[SPM_DEFAULT_COARSEST] < 1e-9, "equal-energy light error %g",
          r.err[SPM_DEFAULT_COARSEST]);
    spm_spectrum_constant(0.5, SPM_KIND_REFLECTANCE, &ee);
    CHECK(spm_spectrum_load(data("spectra/illuminant_D65_1nm.csv"), NULL, SPM_KIND_EMISSION, &d65,
                            &err) == 0, "%s", err.msg);
    CHECK(run1(&ee, &d65, 2.0, &r) == SPM_DEFAULT_COARSEST, "grey under D65: level %d", r.level);
}

/* F11 lighting the ColorChecker (a scene's set): context C multiplies its
 * lines with the patches, which 20 nm bins cannot follow at threshold 2. (F11
 * seen on its own keeps its energy per 20 nm bin and passes: about 1.2.) */
static void test_f11(const spm_spectrum *patches, int npatches)
{
    static spm_spectrum f11;
    spm_error err;
    CHECK(spm_spectrum_load(data("spectra/illuminant_F11.csv"), NULL, SPM_KIND_EMISSION, &f11,
                            &err) == 0, "%s", err.msg);
    const spm_spectrum *set[64];
    int n = 0;
    for (int i = 0; i < npatches && n < 63; i++)
        set[n++] = &patches[i];
    set[n++] = &f11;
    spm_pretest_opts o;
    spm_pretest_defaults(&o);
    spm_pretest_result r[64];
    spm_pretest_run(set, n, &o, r);
    CHECK(npatches == 24 && r[n - 1].level < 3, "F11 with %d patches: level %d (errors %g %g)",
          npatches, r[n - 1].level, r[n - 1].err[2], r[n - 1].err[3]);
}

typedef struct {
    spm_spectrum s[128];
    char names[128][300];
    int n;
} bundle;

/* Every bundled light (alone) and every ColorChecker patch. */
static void load_bundle(bundle *b)
{
    b->n = 0;
    DIR *d = opendir(data("spectra"));
    CHECK(d != NULL, "cannot list spectra/");
    if (!d)
        return;
    for (struct dirent *e; (e = readdir(d)) != NULL && b->n < 100;) {
        if (strncmp(e->d_name, "illuminant_", 11) && strncmp(e->d_name, "lightsource_", 12))
            continue;
        char rel[512];
        spm_error err;
        snprintf(rel, sizeof rel, "spectra/%s", e->d_name);
        int rc = spm_spectrum_load(data(rel), NULL, SPM_KIND_EMISSION, &b->s[b->n], &err);
        CHECK(rc == 0, "%s", err.msg);
        if (!rc)
            snprintf(b->names[b->n++], sizeof b->names[0], "%s", e->d_name);
    }
    closedir(d);
    spm_csv c;
    spm_error err;
    if (spm_csv_load(data("spectra/colorchecker_n_ohta.csv"), &c, &err) == 0) {
        for (int col = 1; col < c.ncols && b->n < 128; col++) {
            CHECK(spm_spectrum_from_csv(&c, col, "cc", SPM_KIND_REFLECTANCE, &b->s[b->n], &err) ==
                      0, "%s", err.msg);
            snprintf(b->names[b->n++], sizeof b->names[0], "%s", c.names[col]);
        }
        spm_csv_free(&c);
    }
    CHECK(b->n > 60, "only %d bundled spectra", b->n);
}

/* The pretest's error recomputed here from the spectrum and colour APIs alone,
 * as pretest.c defines it: s at `level` (each bin held over the 1 nm bins it
 * covers) to the power k, times f0 at 1 nm (NULL: no other factor), against
 * the same product with s at level 0, its own 1 nm values; both scaled by the
 * factor that takes the 1 nm product to Y = 50 and taken to CIELAB against the
 * D65 white of Y = 100. */
static double expect_error(const spm_spectrum *s, int level, int k, const double *f0,
                           spm_metric metric)
{
    double sl[SPM_TRUTH_BINS], xyz[2][3] = {{0}};
    spm_spectrum_level(s, level, sl);
    const double(*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    int per = SPM_TRUTH_BINS / SPM_LEVEL_BINS(level);
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double p0 = f0 ? f0[i] : 1.0, pl = p0;
        for (int j = 0; j < k; j++) {
            p0 *= s->nm1[i];
            pl *= sl[i / per];
        }
        for (int c = 0; c < 3; c++) {
            xyz[0][c] += p0 * w[c][i];
            xyz[1][c] += pl * w[c][i];
        }
    }
    if (!(xyz[0][1] > 0.0)) /* a product without luminance is not seen */
        return 0.0;
    if (!(xyz[1][1] > 0.0)) /* all luminance lost: as far as black from white */
        return 100.0;
    double white[3], lab[2][3];
    spm_white_d65(white);
    for (int c = 0; c < 3; c++)
        white[c] *= 100.0;
    double f = 50.0 / xyz[0][1]; /* both by the level-0 product's factor */
    for (int p = 0; p < 2; p++) {
        double scaled[3] = {xyz[p][0] * f, xyz[p][1] * f, xyz[p][2] * f};
        spm_xyz_to_lab(scaled, white, lab[p]);
    }
    return metric == SPM_METRIC_DEAB ? spm_delta_e_ab(lab[0], lab[1])
                                     : spm_delta_e_2000(lab[0], lab[1]);
}

/* The two computations differ only in rounding (the order of each XYZ sum's
 * terms and of the scaling): relative ~1e-15 on XYZ, which the Lab and dE00
 * formulas (slopes of order 100 around Y = 50) leave far below 1e-9. */
#define ERR_TOL 1e-9

/* The coarsest level in 1..coarsest whose error e[l] is within thr, else 0
 * (README: the coarsest level whose worst error stays within the threshold).
 * *unclear is set when an error is too close to thr to tell. */
static int expect_level(const double *e, int coarsest, double thr, int *unclear)
{
    int best = 0;
    for (int l = 1; l <= coarsest; l++) {
        if (fabs(e[l] - thr) <= ERR_TOL)
            *unclear = 1;
        if (e[l] <= thr)
            best = l;
    }
    return best;
}

static double maxd(double a, double b) { return a > b ? a : b; }

/* Thresholds around the values in e[1..]: just below and above each, so a
 * level chosen on the wrong side of its error shows. */
static int thresholds_around(const double *e, double *thr)
{
    int n = 0;
    thr[n++] = 0.0;
    thr[n++] = 1e9;
    for (int l = 1; l < SPM_NUM_LEVELS; l++)
        if (e[l] > 1e-6) {
            thr[n++] = e[l] * 0.99;
            thr[n++] = e[l] * 1.01;
        }
    return n;
}

/* A light alone (no reflectance: contexts B and C are A, s by itself): every
 * error the pretest reports is that of s against its level 0, and the level
 * is the coarsest passing one, for each allowed coarsest level. A reflectance
 * under D65 alone in the set (context C has no other reflectance): context B
 * is s^k under D65, the error per k and level and the levels per k follow. */
static void test_errors_and_levels(const bundle *b, const spm_spectrum *d65, double *worst_diff)
{
    const double *d65_0 = d65->nm1;
    int checked = 0;
    for (int i = 0; i < b->n; i++) {
        int is_light = b->s[i].kind == SPM_KIND_EMISSION;
        /* e_k[k-1][l]: the error of s^k; e_upto[k-1][l]: the worst for j <= k */
        double e_k[SPM_PRETEST_KMAX][SPM_NUM_LEVELS] = {{0}},
               e_upto[SPM_PRETEST_KMAX][SPM_NUM_LEVELS] = {{0}};
        for (int k = 1; k <= SPM_PRETEST_KMAX; k++)
            for (int l = 1; l < SPM_NUM_LEVELS; l++) {
                e_k[k - 1][l] = is_light ? expect_error(&b->s[i], l, 1, NULL, SPM_METRIC_DE00)
                                         : expect_error(&b->s[i], l, k, d65_0, SPM_METRIC_DE00);
                e_upto[k - 1][l] = maxd(e_k[k - 1][l], k > 1 ? e_upto[k - 2][l] : 0.0);
            }
        const double *worst = e_upto[SPM_PRETEST_KMAX - 1];
        double thr[2 + 2 * SPM_NUM_LEVELS];
        int nthr = thresholds_around(worst, thr);
        for (int coarsest = SPM_DEFAULT_COARSEST; coarsest < SPM_NUM_LEVELS; coarsest++)
            for (int t = 0; t < nthr; t++) {
                spm_pretest_opts o;
                spm_pretest_defaults(&o);
                o.threshold = thr[t];
                o.coarsest_level = coarsest;
                const spm_spectrum *set[2] = {&b->s[i], d65};
                spm_pretest_result res[2], *r = &res[0];
                spm_pretest_run(set, is_light ? 1 : 2, &o, res);
                for (int l = 1; l < SPM_NUM_LEVELS; l++) {
                    double d = fabs(r->err[l] - worst[l]);
                    *worst_diff = maxd(*worst_diff, d);
                    CHECK(d <= ERR_TOL, "%s level %d: pretest error %.9g, recomputed %.9g",
                          b->names[i], l, r->err[l], worst[l]);
                    for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
                        d = fabs(r->err_k[k][l] - e_k[k][l]);
                        *worst_diff = maxd(*worst_diff, d);
                        CHECK(d <= ERR_TOL, "%s level %d k %d: pretest error %.9g, recomputed %.9g",
                              b->names[i], l, k + 1, r->err_k[k][l], e_k[k][l]);
                    }
                }
                int unclear = 0, want = expect_level(worst, coarsest, thr[t], &unclear);
                CHECK(unclear || r->level == want,
                      "%s, threshold %g, coarsest %d: level %d, errors %g %g %g %g say %d",
                      b->names[i], thr[t], coarsest, r->level, worst[1], worst[2], worst[3],
                      worst[4], want);
                for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
                    unclear = 0;
                    want = expect_level(e_upto[k], coarsest, thr[t], &unclear);
                    CHECK(unclear || r->level_k[k] == want,
                          "%s, threshold %g: level_k[%d] %d, errors for k <= %d say %d",
                          b->names[i], thr[t], k, r->level_k[k], k + 1, want);
                }
                checked++;
            }
    }
    CHECK(checked > 500, "only %d pretests checked", checked);
}

/* Two lights and one reflectance r: the reflectance's error is the worse of
 * its two lights' (context B); a light's is the worse of itself alone (A) and
 * of the light times r^m, m = 1..4 (context C: its 64 random sequences of 1..4
 * reflectances, here all r, draw every m). Returns how much C adds to F11's
 * error at 20 nm. */
static double two_lights(const spm_spectrum *patch, const spm_spectrum *d65,
                         const spm_spectrum *f11, const char *name)
{
    const spm_spectrum *set[3] = {patch, d65, f11};
    spm_pretest_opts o;
    spm_pretest_defaults(&o);
    spm_pretest_result r[3];
    spm_pretest_run(set, 3, &o, r);
    const double *l0[2] = {d65->nm1, f11->nm1}, *p0 = patch->nm1;
    double c_adds = 0.0;
    for (int l = 1; l < SPM_NUM_LEVELS; l++) {
        double want = 0.0;
        for (int k = 1; k <= SPM_PRETEST_KMAX; k++)
            for (int li = 0; li < 2; li++)
                want = maxd(want, expect_error(patch, l, k, l0[li], SPM_METRIC_DE00));
        CHECK(fabs(r[0].err[l] - want) <= ERR_TOL, "%s under D65 and F11, level %d: %.9g vs %.9g",
              name, l, r[0].err[l], want);
        for (int li = 0; li < 2; li++) {
            double f[SPM_TRUTH_BINS];
            for (int bb = 0; bb < SPM_TRUTH_BINS; bb++)
                f[bb] = 1.0;
            double a = expect_error(set[1 + li], l, 1, NULL, SPM_METRIC_DE00);
            want = a;
            for (int m = 1; m <= 4; m++) {
                for (int bb = 0; bb < SPM_TRUTH_BINS; bb++)
                    f[bb] *= p0[bb];
                want = maxd(want, expect_error(set[1 + li], l, 1, f, SPM_METRIC_DE00));
            }
            CHECK(fabs(r[1 + li].err[l] - want) <= ERR_TOL,
                  "%s with %s, level %d: %.9g vs %.9g", li ? "F11" : "D65", name, l,
                  r[1 + li].err[l], want);
            if (li == 1 && l == SPM_DEFAULT_COARSEST)
                c_adds = want - a;
        }
    }
    return c_adds;
}

static void test_two_lights(const bundle *b, const spm_spectrum *d65)
{
    const spm_spectrum *f11 = NULL;
    for (int i = 0; i < b->n; i++)
        if (!strcmp(b->names[i], "illuminant_F11.csv"))
            f11 = &b->s[i];
    CHECK(f11 != NULL, "F11 in the bundle");
    if (!f11)
        return;
    double most = 0.0;
    for (int i = 0; i < b->n; i++)
        if (b->s[i].kind == SPM_KIND_REFLECTANCE)
            most = maxd(most, two_lights(&b->s[i], d65, f11, b->names[i]));
    /* F11's lines times a coloured patch: for some patch context C must decide */
    CHECK(most > 0.1, "context C never raises F11's 20 nm error (at most %g)", most);
}

/* Over the bundle: a higher threshold never picks a finer level, and at
 * threshold 2 the bundle does not collapse onto one level. */
static void test_monotone(const bundle *b, spm_spectrum *d65)
{
    const double thr[] = {0.25, 0.5, 1, 2, 3, 5, 10};
    int spread[SPM_NUM_LEVELS] = {0};
    for (int i = 0; i < b->n; i++) {
        int is_light = b->s[i].kind == SPM_KIND_EMISSION, prev = -1;
        for (size_t t = 0; t < sizeof thr / sizeof thr[0]; t++) {
            spm_pretest_result r;
            int lvl = run1(&b->s[i], is_light ? NULL : d65, thr[t], &r);
            CHECK(lvl >= prev, "%s: threshold %g picks level %d, finer than %d", b->names[i],
                  thr[t], lvl, prev);
            prev = lvl;
            if (thr[t] == 2.0)
                spread[lvl]++;
        }
    }
    CHECK(spread[0] + spread[1] + spread[2] > 0 && spread[3] > 0,
          "levels at threshold 2: %d %d %d %d", spread[0], spread[1], spread[2], spread[3]);
}

static void test_set_and_determinism(const bundle *b)
{
    /* A scene-like set: all ColorChecker patches under F11 and D65. */
    const spm_spectrum *set[40];
    int n = 0;
    for (int i = 0; i < b->n && n < 38; i++)
        if (b->s[i].kind == SPM_KIND_REFLECTANCE)
            set[n++] = &b->s[i];
    for (int i = 0; i < b->n && n < 40; i++)
        if (!strcmp(b->names[i], "illuminant_F11.csv") || !strcmp(b->names[i], "illuminant_D65.csv"))
            set[n++] = &b->s[i];
    spm_pretest_opts o;
    spm_pretest_defaults(&o);
    spm_pretest_result r1[40], r2[40], r3[40];
    spm_pretest_run(set, n, &o, r1);
    spm_pretest_run(set, n, &o, r2);
    CHECK(memcmp(r1, r2, sizeof(spm_pretest_result) * (size_t)n) == 0, "same seed, same result");
    o.seed = 7;
    spm_pretest_run(set, n, &o, r3);
    int differ = 0;
    for (int i = 0; i < n; i++)
        differ += memcmp(r1[i].err, r3[i].err, sizeof r1[i].err) != 0;
    CHECK(differ > 0, "another seed draws other sequences (context C)");
    o.seed = 1;
    o.metric = SPM_METRIC_DEAB;
    spm_pretest_run(set, n, &o, r3);
    CHECK(r3[0].err[3] != r1[0].err[3], "the metric is used: %g vs %g", r3[0].err[3], r1[0].err[3]);
    if (getenv("SPM_PRETEST_VERBOSE")) {
        const char *names[40];
        for (int i = 0; i < n; i++)
            names[i] = "x";
        spm_pretest_print(stdout, names, r1, n, &o);
    }
}

int main(void)
{
    spm_quiet_warnings = 1;
    static bundle b;
    spm_spectrum d65;
    spm_error err;
    CHECK(spm_spectrum_load(data("spectra/illuminant_D65_1nm.csv"), NULL, SPM_KIND_EMISSION, &d65,
                            &err) == 0, "%s", err.msg);
    test_equal_energy();
    load_bundle(&b);
    test_monotone(&b, &d65);
    double worst_diff = 0.0;
    test_errors_and_levels(&b, &d65, &worst_diff);
    printf("pretest errors against their recomputation: largest difference %.3g\n", worst_diff);
    test_two_lights(&b, &d65);
    test_set_and_determinism(&b);
    int first_patch = 0;
    while (first_patch < b.n && b.s[first_patch].kind != SPM_KIND_REFLECTANCE)
        first_patch++;
    test_f11(&b.s[first_patch], b.n - first_patch);
    TEST_END();
}
