/* Pretests: trivial and spiky cases, monotonicity in the threshold over every
 * bundled spectrum, determinism, and the per-k table's ordering. */
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
    CHECK(run1(&ee, NULL, 2.0, &r) == 2, "equal-energy light: level %d", r.level);
    CHECK(r.err[2] < 1e-9, "equal-energy light error %g", r.err[2]);
    spm_spectrum_constant(0.5, SPM_KIND_REFLECTANCE, &ee);
    CHECK(spm_spectrum_load(data("spectra/illuminant_D65_1nm.csv"), NULL, SPM_KIND_EMISSION, &d65,
                            &err) == 0, "%s", err.msg);
    CHECK(run1(&ee, &d65, 2.0, &r) == 2, "grey under D65: level %d", r.level);
}

/* F11 lighting the ColorChecker (a scene's set): context C multiplies its
 * lines with the patches, which level 2 cannot follow at threshold 2. (F11
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
    CHECK(npatches == 24 && r[n - 1].level < 2, "F11 with %d patches: level %d (errors %g %g)",
          npatches, r[n - 1].level, r[n - 1].err[1], r[n - 1].err[2]);
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
            for (int k = 1; k < SPM_PRETEST_KMAX; k++)
                CHECK(r.level_k[k] <= r.level_k[k - 1], "%s: level_k not non-increasing",
                      b->names[i]);
            CHECK(r.level == r.level_k[SPM_PRETEST_KMAX - 1], "%s: level vs level_k", b->names[i]);
            CHECK(r.err[0] == 0.0, "%s: level 0 against itself %g", b->names[i], r.err[0]);
            if (thr[t] == 2.0)
                spread[lvl]++;
        }
    }
    /* The bundle is varied: at threshold 2 it must not collapse onto one level. */
    CHECK(spread[0] + spread[1] > 0 && spread[2] > 0, "levels at threshold 2: %d %d %d",
          spread[0], spread[1], spread[2]);
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
    CHECK(r3[0].err[2] != r1[0].err[2], "the metric is used: %g vs %g", r3[0].err[2], r1[0].err[2]);
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
    test_set_and_determinism(&b);
    int first_patch = 0;
    while (first_patch < b.n && b.s[first_patch].kind != SPM_KIND_REFLECTANCE)
        first_patch++;
    test_f11(&b.s[first_patch], b.n - first_patch);
    TEST_END();
}
