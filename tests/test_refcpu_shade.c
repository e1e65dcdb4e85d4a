/* CPU reference shade stage: every mode on a hand-made record against the
 * shading formula evaluated in double, a record of every stored factor kind
 * likewise, hero-wavelength placement and its convergence to truth. Float sums of at most 400 positive terms carry a
 * relative error below 400 * 2^-24 = 2.4e-5: tolerance 1e-4 relative. */
#include "colour.h"
#include "spm_rng.h"
#include "refcpu.h"
#include "testutil.h"
#include <complex.h>
#include <stdlib.h>
#include <string.h>

#define NC 4
#define REL 1e-4

/* Colour c's value in lane l of a representation with n lanes: distinct per
 * colour and lane, in (0, 1]. */
static double val(int c, int l, int n)
{
    return 0.2 + 0.15 * c + 0.4 * (double)l / n;
}

static double weight(int ch, int l, int n)
{
    return (1.0 + ch + (double)((l * 7) % 5)) / n;
}

static float *table(int lanes, int stride)
{
    float *t = calloc((size_t)NC * stride, sizeof *t);
    for (int c = 0; c < NC; c++)
        for (int l = 0; l < lanes; l++)
            t[c * stride + l] = (float)val(c, l, lanes);
    return t;
}

static void make_tables(spm_tables *t)
{
    memset(t, 0, sizeof *t);
    t->ncolours = NC;
    t->nspikes = 3;
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        t->lvl[l] = table(nb, nb);
        t->mlc_lvl[l] = table(nb + t->nspikes, nb + SPM_MAX_SPIKES);
        for (int ch = 0; ch < 3; ch++)
            for (int b = 0; b < nb; b++)
                t->cmf_lvl[l][ch][b] = (float)weight(ch, b, nb);
    }
    for (int ch = 0; ch < 3; ch++)
        for (int k = 0; k < t->nspikes; k++)
            t->spike_cmf[ch][k] = (float)(0.3 + 0.1 * k + ch);
    t->truth = table(SPM_TRUTH_BINS, SPM_TRUTH_BINS);
    t->rgb = table(3, 4);
    for (int ch = 0; ch < 3; ch++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            t->cmf_truth[ch][i] = (float)weight(ch, i, SPM_TRUTH_BINS);
    spm_tables_fill_hero(t);
}

static void free_tables(spm_tables *t)
{
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        free(t->lvl[l]), free(t->mlc_lvl[l]);
    free(t->truth);
    free(t->rgb);
}

/* first emission 2; vertices (refl 0, light 2, c 0.5), (refl 1, none),
 * (refl 0, light 2, c 0.25); background 3 with weight 2. */
static spm_path make_path(void)
{
    spm_path p;
    memset(&p, 0, sizeof p);
    p.h = (spm_path_head){3, SPM_END_ESCAPED, 2, 1.0f, 3, 2.0f, 0, 0};
    p.v[0] = (spm_vertex){0u | (2u << 16), 0.5f};
    p.v[1] = (spm_vertex){1u | (SPM_NONE << 16), 0.0f};
    p.v[2] = (spm_vertex){0u | (2u << 16), 0.25f};
    return p;
}

/* spm_path_head's formula in double for lane l of n. */
static double expect_lane(int l, int n)
{
    double r0 = val(0, l, n), r1 = val(1, l, n), e = val(2, l, n), bg = val(3, l, n);
    double L = e;
    double P = r0;
    L += P * e * 0.5;
    P *= r1 * r0;
    L += P * e * 0.25;
    return L + P * bg * 2.0;
}

static void check_xyz(const float *xyz, const double *ex, const char *what)
{
    for (int ch = 0; ch < 3; ch++)
        CHECK(fabs(xyz[ch] - ex[ch]) <= REL * fabs(ex[ch]), "%s: channel %d %.8g vs %.8g", what,
              ch, xyz[ch], ex[ch]);
}

static void shade_one(const spm_tables *t, int mode, uint8_t level, float xyz[3])
{
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.spp_per_pass = 1;
    spm_path path = make_path();
    spm_ref_shade(t, mode, &p, 0, &path, &level, 1, xyz);
}

static void test_binned_modes(const spm_tables *t)
{
    float xyz[3];
    double ex[3];
    /* ref: its level (5 nm); ml: the path's level byte (set-by bits ignored),
     * level 0 truth's 1 nm bins */
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        for (int ch = 0; ch < 3; ch++) {
            ex[ch] = 0;
            for (int b = 0; b < nb; b++)
                ex[ch] += expect_lane(b, nb) * weight(ch, b, nb);
        }
        char what[64];
        snprintf(what, sizeof what, "ml at level %d", l);
        shade_one(t, SPM_MODE_ML, (uint8_t)(l | (SPM_SETBY_REFLECTOR << SPM_SETBY_SHIFT)), xyz);
        check_xyz(xyz, ex, what);
        if (l == SPM_REF_LEVEL) {
            shade_one(t, SPM_MODE_REF, 3, xyz); /* ref ignores the level byte */
            check_xyz(xyz, ex, "ref");
        }
        /* mlc: smooth bins then the spike lanes */
        int n = nb + t->nspikes;
        for (int ch = 0; ch < 3; ch++) {
            ex[ch] = 0;
            for (int k = 0; k < n; k++)
                ex[ch] += expect_lane(k, n) *
                          (k < nb ? weight(ch, k, nb) : t->spike_cmf[ch][k - nb]);
        }
        snprintf(what, sizeof what, "mlc at level %d", l);
        shade_one(t, SPM_MODE_MLC, (uint8_t)l, xyz);
        check_xyz(xyz, ex, what);
    }
    for (int ch = 0; ch < 3; ch++) {
        ex[ch] = 0;
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            ex[ch] += expect_lane(i, SPM_TRUTH_BINS) * weight(ch, i, SPM_TRUTH_BINS);
    }
    shade_one(t, SPM_MODE_TRUTH, 0, xyz);
    check_xyz(xyz, ex, "truth");
    /* rgb: linear sRGB lanes, XYZ through the sRGB matrix */
    double rgb[3] = {expect_lane(0, 3), expect_lane(1, 3), expect_lane(2, 3)};
    spm_linear_srgb_to_xyz(rgb, ex);
    shade_one(t, SPM_MODE_RGB, 0, xyz);
    check_xyz(xyz, ex, "rgb");
}

/* A record of every stored factor kind (spm_shared.h SPM_FACTOR_KINDS), each
 * vertex with the hit its sampled ray counted, shaded in truth against the
 * kinds' formulas in double: a conductor (eta colour 0, k colour 1, cosines
 * 0.8 for its lobe and 0.6 for its light sample, whose emission 2 weighs
 * 0.5; hit 3, 0.3), a dielectric (sigma colour 1, 0.7 inside; emission 2,
 * 0.25; hit 2, 0.2), a plain vertex (colour 0; hit 3, 0.1, a coated lobe's),
 * then the background 3 with weight 2. The Fresnel here is the complex
 * formula (test_cl_conductor's), not the reference's real one. */
static double fresnel_complex(double eta, double k, double c)
{
    double complex n = eta + I * k;
    double complex ct = csqrt(1.0 - (1.0 - c * c) / (n * n));
    double complex rs = (c - n * ct) / (c + n * ct), rp = (n * c - ct) / (n * c + ct);
    return 0.5 * (creal(rs * conj(rs)) + creal(rp * conj(rp)));
}

static double expect_kinds(int l, int n)
{
    double eta = val(0, l, n), k = val(1, l, n), e = val(2, l, n), h = val(3, l, n);
    double L = e, P = 1.0;
    L += P * fresnel_complex(eta, k, 0.6) * e * 0.5;
    P *= fresnel_complex(eta, k, 0.8);
    L += P * h * 0.3;
    L += P * e * 0.25;
    P *= exp(-val(1, l, n) * 0.7);
    L += P * e * 0.2;
    P *= val(0, l, n);
    L += P * h * 0.1;
    return L + P * h * 2.0;
}

static void test_factor_kinds(const spm_tables *t)
{
    spm_path p;
    memset(&p, 0, sizeof p);
    p.h = (spm_path_head){3, SPM_END_ESCAPED, 2, 1.0f, 3, 2.0f, 0, 0};
    p.v[0] = (spm_vertex){0u | (2u << 16), 0.5f};
    p.x[0] = (spm_vertex_ext){SPM_VX_IDS(SPM_FK_FRESNEL, 1u) | SPM_VX_HIT_BITS(3u), 0.8f, 0.6f,
                              0.3f};
    p.v[1] = (spm_vertex){1u | (2u << 16), 0.25f};
    p.x[1] = (spm_vertex_ext){SPM_VX_IDS(SPM_FK_ABSORB, SPM_NONE) | SPM_VX_HIT_BITS(2u), 0.7f,
                              0.0f, 0.2f};
    p.v[2] = (spm_vertex){0u | (SPM_NONE << 16), 0.0f};
    p.x[2] = (spm_vertex_ext){SPM_VX_IDS(SPM_FK_PLAIN, SPM_NONE) | SPM_VX_HIT_BITS(3u), 0.0f,
                              0.0f, 0.1f};
    CHECK(SPM_VX_KIND(p.x[0]) == SPM_FK_FRESNEL && SPM_VX_COL(p.x[0]) == 1u &&
              SPM_VX_HIT(p.x[0]) == 3u && SPM_VX_LAMBDA(p.x[1]) == SPM_NONE &&
              SPM_VX_KIND(p.x[2]) == SPM_FK_PLAIN,
          "the record's fields read back");
    spm_trace_params tp;
    memset(&tp, 0, sizeof tp);
    tp.spp_per_pass = 1;
    uint8_t level = 0;
    float xyz[3];
    double ex[3] = {0, 0, 0};
    for (int ch = 0; ch < 3; ch++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            ex[ch] += expect_kinds(i, SPM_TRUTH_BINS) * weight(ch, i, SPM_TRUTH_BINS);
    spm_ref_shade(t, SPM_MODE_TRUTH, &tp, 0, &p, &level, 1, xyz);
    check_xyz(xyz, ex, "factor kinds (truth)");
}

/* Hero lanes land where pbrt-v4's visible density truncated to 380-780 nm
 * puts them, recomputed here in double from its closed form: lane k at
 * x = frac(u + k/4), wavelength 538 + atanh(t0 + x dt)/a; each reads the 1 nm
 * bin holding it, weighed by truth's weight of that bin over the density
 * a sech^2(a (l - 538)) / dt and 4. The reference works in float: its y and
 * density carry a relative error of a few 1e-7, far inside REL; a lane within
 * float rounding of a bin edge could land in the neighbouring bin, which
 * these seeds do not meet (the check would say so). */
static void test_hero_lanes(const spm_tables *t)
{
    enum { N = 64 };
    const double a = 0.0072, c = 538.0;
    const double t0 = tanh(a * (380.0 - c)), dt = tanh(a * (780.0 - c)) - t0;
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.seed = 17u;
    p.spp_per_pass = N;
    p.first_sample = 5;
    static spm_path paths[N];
    float xyz[3 * N];
    uint8_t lv[N] = {0};
    for (int i = 0; i < N; i++)
        paths[i] = make_path();
    spm_ref_shade(t, SPM_MODE_HERO, &p, 0, paths, lv, N, xyz);
    int ok = 1;
    for (int i = 0; i < N; i++) {
        double u = spm_rng(p.seed, 0, p.first_sample + (spm_u32)i, SPM_DIM_HERO), ex[3] = {0};
        for (int k = 0; k < SPM_HERO_LANES; k++) {
            double x = fmod(u + k / 4.0, 1.0);
            double lambda = c + atanh(t0 + x * dt) / a;
            double ch2 = cosh(a * (lambda - c)), pdf = a / (ch2 * ch2) / dt;
            int bin = (int)floor(lambda - 380.0);
            for (int ch = 0; ch < 3; ch++)
                ex[ch] += expect_lane(bin, SPM_TRUTH_BINS) * weight(ch, bin, SPM_TRUTH_BINS) /
                          pdf / 4;
        }
        for (int ch = 0; ch < 3; ch++)
            ok &= fabs(xyz[3 * i + ch] - ex[ch]) <= REL * ex[ch];
    }
    CHECK(ok, "hero: lanes at frac(u + i/4) through the truncated visible density, "
              "1 nm bins weighed by truth's weights over the density and 4");
}

/* The kernel's direct index (tables.c): for samples anywhere in a cell, y
 * computed as the kernel does lies in the cell's entry bin or the next, as
 * decided by the edges. Nine samples per cell, both ends included. */
static void test_hero_index(const spm_tables *t)
{
    int bad = 0, worst_k = -1;
    for (int k = 0; k < SPM_HERO_CELLS; k++) {
        float lo = (float)k / SPM_HERO_CELLS, hi = nextafterf((float)(k + 1) / SPM_HERO_CELLS, 0);
        for (int q = 0; q <= 8; q++) {
            float x = q == 8 ? hi : lo + (hi - lo) * (float)q / 8.0f;
            float y = t->hero_t0 + x * t->hero_dt;
            int bin = 0;
            while (bin < SPM_TRUTH_BINS - 1 && y >= t->hero_edge[bin + 1])
                bin++;
            int e = (int)t->hero_index[(int)(x * SPM_HERO_CELLS)];
            if (bin < e || bin > e + 1)
                bad++, worst_k = k;
        }
    }
    CHECK(bad == 0, "hero index: %d samples outside their cell's bin or the next (cell %d)", bad,
          worst_k);
}

/* Hero converges to truth on the same record: E[value(l) w(l) / pdf(l)] over
 * the density is the integral of the piecewise-constant 1 nm value and
 * weight, truth's sum. The weights vary within every 5 nm bin, so a hero
 * that read level-0 bins or other CMF weights would miss by far more than
 * the bound of 5 standard errors of the mean. */
static void test_hero_converges(const spm_tables *t)
{
    enum { N = 20000 };
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.seed = 3u;
    p.spp_per_pass = N;
    spm_path *paths = malloc(N * sizeof *paths);
    float *xyz = malloc(3 * N * sizeof *xyz);
    uint8_t *lv = calloc(N, 1);
    for (int i = 0; i < N; i++)
        paths[i] = make_path();
    spm_ref_shade(t, SPM_MODE_HERO, &p, 0, paths, lv, N, xyz);
    for (int ch = 0; ch < 3; ch++) {
        double s = 0, s2 = 0, ex = 0;
        for (int i = 0; i < N; i++)
            s += xyz[3 * i + ch], s2 += (double)xyz[3 * i + ch] * xyz[3 * i + ch];
        double mean = s / N, sem = sqrt((s2 / N - mean * mean) / (N - 1));
        for (int l = 0; l < SPM_TRUTH_BINS; l++)
            ex += expect_lane(l, SPM_TRUTH_BINS) * weight(ch, l, SPM_TRUTH_BINS);
        CHECK(fabs(mean - ex) <= 5 * sem, "hero channel %d mean %.6f vs truth %.6f (sem %.2g)",
              ch, mean, ex, sem);
    }
    free(paths), free(xyz), free(lv);
}

int main(void)
{
    spm_tables t;
    make_tables(&t);
    test_binned_modes(&t);
    test_factor_kinds(&t);
    test_hero_lanes(&t);
    test_hero_index(&t);
    test_hero_converges(&t);
    free_tables(&t);
    TEST_END();
}
