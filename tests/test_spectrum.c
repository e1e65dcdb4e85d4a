/* Area-preserving resampling and spectral levels: integrals against an
 * independent trapezoid sum of the input, a 1 nm line, bounded reflectances,
 * coverage rules and the bin-integrated CIE weights. */
#include "colour.h"
#include "csv.h"
#include "testutil.h"
#include <stdint.h>
#include <string.h>

static const char *data(const char *rel)
{
    static char buf[4096];
    return spm_data_path(rel, buf, sizeof buf);
}

/* Integral over [380, 780] of the piecewise-linear input by the trapezoid rule
 * on the samples: independent of the bin code. Requires 380 and 780 to be
 * sample points or the samples to lie inside them. */
static double trapezoid(const double *wl, const double *v, size_t n)
{
    double sum = 0.0;
    for (size_t i = 0; i + 1 < n; i++)
        if (wl[i] >= SPM_LAMBDA_MIN && wl[i + 1] <= SPM_LAMBDA_MAX)
            sum += 0.5 * (v[i] + v[i + 1]) * (wl[i + 1] - wl[i]);
    return sum;
}

/* A level's bin width in nm. */
static int level_nm(int l)
{
    return (SPM_LAMBDA_MAX - SPM_LAMBDA_MIN) / SPM_LEVEL_BINS(l);
}

static double level_integral(const spm_spectrum *s, int level)
{
    double bins[SPM_TRUTH_BINS], sum = 0.0;
    spm_spectrum_level(s, level, bins);
    for (int b = 0; b < SPM_LEVEL_BINS(level); b++)
        sum += bins[b];
    return sum * level_nm(level);
}

/* Relative 1e-5 is the bound; the double arithmetic here reaches ~1e-14. */
static void check_area(const double *wl, const double *v, size_t n, spm_kind kind,
                       const char *what)
{
    spm_spectrum s;
    spm_error err;
    int rc = spm_spectrum_from_samples(wl, v, n, kind, what, &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    double want = trapezoid(wl, v, n), truth = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        truth += s.nm1[i];
    CHECK(fabs(truth - want) <= 1e-5 * want, "%s: truth integral %.12g vs %.12g", what, truth,
          want);
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        double got = level_integral(&s, l);
        CHECK(fabs(got - want) <= 1e-5 * want, "%s level %d: integral %.12g vs %.12g", what, l,
              got, want);
    }
}

static void check_area_file(const char *rel, spm_kind kind)
{
    spm_csv c;
    spm_error err;
    int rc = spm_csv_load(data(rel), &c, &err);
    CHECK(rc == 0, "%s", err.msg);
    if (rc)
        return;
    double wl[1024], v[1024];
    size_t n = c.nrows < 1024 ? c.nrows : 1024;
    for (size_t r = 0; r < n; r++) {
        wl[r] = c.data[r * 2];
        v[r] = c.data[r * 2 + 1];
    }
    check_area(wl, v, n, kind, rel);
    spm_csv_free(&c);
}

static uint64_t rng_state = 12345;
static double uniform(void) /* xorshift64*: a fixed, seeded sequence */
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}

static void test_area(void)
{
    check_area_file("spectra/illuminant_A_1nm.csv", SPM_KIND_EMISSION);
    check_area_file("spectra/illuminant_D65.csv", SPM_KIND_EMISSION);
    char rel[64];
    for (int i = 1; i <= 12; i++) {
        snprintf(rel, sizeof rel, "spectra/illuminant_F%d.csv", i);
        check_area_file(rel, SPM_KIND_EMISSION);
    }
    check_area_file("spectra/lightsource_nist_lps.csv", SPM_KIND_EMISSION);
    /* smooth: a Gaussian sampled every 10 nm */
    double wl[512], v[512];
    size_t n = 0;
    for (double x = 380; x <= 780; x += 10, n++) {
        wl[n] = x;
        v[n] = exp(-0.5 * pow((x - 550) / 40.0, 2));
    }
    check_area(wl, v, n, SPM_KIND_EMISSION, "gaussian");
    /* random: irregular spacing (0.1..3 nm steps) and random values */
    for (int trial = 0; trial < 20; trial++) {
        n = 0;
        for (double x = 380; n < 511; x += 0.1 + 2.9 * uniform()) {
            wl[n] = x < 780 ? x : 780;
            v[n++] = 5.0 * uniform();
            if (x >= 780)
                break;
        }
        check_area(wl, v, n, trial % 2 ? SPM_KIND_EMISSION : SPM_KIND_REFLECTANCE, "random");
    }
}

static void test_line(void)
{
    spm_spectrum s;
    spm_error err;
    int rc = spm_spectrum_load(data("tests/data/spectra/line546.csv"), NULL, SPM_KIND_EMISSION,
                               &s, &err);
    CHECK(rc == 0, "%s", err.msg);
    /* The triangle 545-547 nm has area 1; it must stay in the bins it
     * covers at every level (545-546 and 546-547 nm at 1 nm, the one holding
     * 545-550 nm above), with every other bin exactly zero. */
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        double bins[SPM_TRUTH_BINS], area = 0.0;
        spm_spectrum_level(&s, l, bins);
        int first = (545 - SPM_LAMBDA_MIN) / level_nm(l), last = (546 - SPM_LAMBDA_MIN) / level_nm(l);
        int nonzero = 0;
        for (int b = 0; b < SPM_LEVEL_BINS(l); b++) {
            nonzero += bins[b] != 0.0;
            if (b >= first && b <= last)
                area += bins[b] * level_nm(l);
        }
        CHECK(nonzero == last - first + 1, "level %d: %d non-zero bins", l, nonzero);
        CHECK_NEAR(area, 1.0, 1e-12, "line area in its bins");
    }
}

static void check_bounded(const spm_spectrum *s, const char *what)
{
    /* 1e-12: the segment integrals may round a few ulps above a value of 1. */
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        double bins[SPM_TRUTH_BINS], mx = 0.0, mn = 1.0;
        spm_spectrum_level(s, l, bins);
        for (int b = 0; b < SPM_LEVEL_BINS(l); b++) {
            mx = bins[b] > mx ? bins[b] : mx;
            mn = bins[b] < mn ? bins[b] : mn;
        }
        CHECK(mx <= 1.0 + 1e-12 && mn >= 0.0, "%s level %d: range %.17g..%.17g", what, l, mn, mx);
    }
    CHECK(spm_spectrum_max(s) <= 1.0 + 1e-12, "%s truth max %.17g", what, spm_spectrum_max(s));
}

static void test_bounded(void)
{
    double wl[400], v[400];
    for (int trial = 0; trial < 20; trial++) {
        size_t n = 0;
        for (double x = 370; x < 800 && n < 400; x += 0.3 + 7 * uniform(), n++) {
            wl[n] = x;
            double u = uniform();
            v[n] = u < 0.3 ? 1.0 : u; /* many samples exactly at 1 */
        }
        spm_spectrum s;
        spm_error err;
        CHECK(spm_spectrum_from_samples(wl, v, n, SPM_KIND_REFLECTANCE, "bounded", &s, &err) == 0,
              "%s", err.msg);
        check_bounded(&s, "random reflectance");
    }
    spm_csv c;
    spm_error err;
    if (spm_csv_load(data("spectra/colorchecker_n_ohta.csv"), &c, &err) == 0) {
        for (int col = 1; col < c.ncols; col++) {
            spm_spectrum s;
            CHECK(spm_spectrum_from_csv(&c, col, "colorchecker", SPM_KIND_REFLECTANCE, &s, &err) ==
                      0,
                  "%s", err.msg);
            check_bounded(&s, c.names[col]);
        }
        spm_csv_free(&c);
    } else {
        CHECK(0, "%s", err.msg);
    }
}

static void test_coverage(void)
{
    spm_spectrum r, e;
    spm_error err;
    const char *p = data("tests/data/spectra/partial_irregular_crlf.csv");
    CHECK(spm_spectrum_load(p, NULL, SPM_KIND_REFLECTANCE, &r, &err) == 0, "%s", err.msg);
    CHECK(spm_spectrum_load(p, NULL, SPM_KIND_EMISSION, &e, &err) == 0, "%s", err.msg);
    /* samples span 400 (0.2) .. 700 (0.4) */
    CHECK_NEAR(r.nm1[0], 0.2, 1e-15, "reflectance extended by its first value");
    CHECK_NEAR(r.nm1[399], 0.4, 1e-15, "reflectance extended by its last value");
    CHECK_NEAR(e.nm1[0], 0.0, 0.0, "emission zero below its samples");
    CHECK_NEAR(e.nm1[399], 0.0, 0.0, "emission zero above its samples");
    CHECK_NEAR(e.nm1[20], r.nm1[20], 1e-15, "same inside the samples");
    /* 512 nm is a sample (0.9) between 433.5 (0.35) and 600.25 (0.6): bin
     * [511, 512] holds the mean of the line from 0.35 to 0.9 over it. */
    double slope = (0.9 - 0.35) / (512 - 433.5);
    CHECK_NEAR(r.nm1[131], 0.9 - 0.5 * slope, 1e-12, "interpolated bin mean");

    double wl[2] = {300, 370}, v[2] = {0.5, 0.5};
    int rc = spm_spectrum_from_samples(wl, v, 2, SPM_KIND_REFLECTANCE, "outside", &r, &err);
    CHECK(rc != 0 && strncmp(err.msg, "outside:", 8) == 0, "no samples inside: %s", err.msg);
    double wl2[2] = {500, 500};
    rc = spm_spectrum_from_samples(wl2, v, 2, SPM_KIND_REFLECTANCE, "dup", &r, &err);
    CHECK(rc != 0, "duplicate wavelength accepted");
    double vneg[2] = {0.5, -0.1}, wl3[2] = {500, 600};
    rc = spm_spectrum_from_samples(wl3, vneg, 2, SPM_KIND_EMISSION, "neg", &r, &err);
    CHECK(rc != 0, "negative value accepted");
    double vnan[2] = {0.5, NAN};
    rc = spm_spectrum_from_samples(wl3, vnan, 2, SPM_KIND_EMISSION, "nan", &r, &err);
    CHECK(rc != 0, "NaN accepted");
}

static void test_cmf(void)
{
    spm_error err;
    CHECK(spm_cmf_init(&err) == 0, "%s", err.msg);
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        double lw[3][SPM_TRUTH_BINS];
        spm_cmf_level(l, lw);
        int width = level_nm(l);
        for (int k = 0; k < 3; k++)
            for (int b = 0; b < SPM_LEVEL_BINS(l); b++) {
                double sum = 0.0;
                for (int j = 0; j < width; j++)
                    sum += w[k][b * width + j];
                CHECK_NEAR(lw[k][b], sum, 1e-15, "level weight = sum of truth weights");
            }
        /* equal-energy emission 1 -> Y = 1 at every level */
        double ones[SPM_TRUTH_BINS], xyz[3];
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            ones[b] = 1.0;
        spm_xyz_bins(ones, l, xyz);
        CHECK_NEAR(xyz[1], 1.0, 1e-12, "equal-energy Y at a level");
    }
    /* Normalisation against an independent trapezoid of y-bar over 380-780
     * from the table itself; y-bar(555) = 1 in the table. */
    spm_csv c;
    if (spm_csv_load(data("spectra/cie1931_2deg_cmf_1nm.csv"), &c, &err) == 0) {
        double wl[600], y[600];
        for (size_t r = 0; r < c.nrows && r < 600; r++) {
            wl[r] = c.data[r * 4];
            y[r] = c.data[r * 4 + 2];
        }
        double integral = trapezoid(wl, y, c.nrows < 600 ? c.nrows : 600), p[3];
        spm_cmf_point(555.0, p);
        CHECK_NEAR(p[1], 1.0 / integral, 1e-12, "cmf_point(555) = 1 / integral of y-bar");
        spm_cmf_point(900.0, p);
        CHECK(p[0] == 0 && p[1] == 0 && p[2] == 0, "cmf_point outside the table is zero");
        spm_csv_free(&c);
    } else {
        CHECK(0, "%s", err.msg);
    }
}

static void test_blackbody(void)
{
    /* CIE A is a Planck radiator at 2848 K with c2 = 1.435e-2 m K, i.e. 2856 K
     * with today's c2: same chromaticity as A (0.44757, 0.40745) to the
     * tolerance of the white point test (see test_colour.c). */
    spm_spectrum bb;
    spm_spectrum_blackbody(2848.0 * 1.4387768775e-2 / 1.435e-2, &bb);
    double xyz[3];
    spm_xyz_emission(&bb, xyz);
    double sum = xyz[0] + xyz[1] + xyz[2];
    CHECK_NEAR(xyz[0] / sum, 0.44757, 5e-5, "blackbody x");
    CHECK_NEAR(xyz[1] / sum, 0.40745, 5e-5, "blackbody y");
    /* Mean over 559-561 nm = value at 560 up to the curvature term (~1e-6). */
    CHECK_NEAR(0.5 * (bb.nm1[179] + bb.nm1[180]), 1.0, 1e-5, "relative to 560 nm");
    double l1[SPM_NM5_BINS], mean = 0.0;
    spm_spectrum_level(&bb, 1, l1);
    for (int b = 0; b < SPM_NM5_BINS; b++)
        mean += l1[b] / SPM_NM5_BINS;
    CHECK_NEAR(spm_spectrum_mean(&bb), mean, 1e-12, "mean = mean of the 5 nm level");
}

int main(void)
{
    spm_quiet_warnings = 1;
    test_area();
    test_line();
    test_bounded();
    test_coverage();
    test_cmf();
    test_blackbody();
    TEST_END();
}
