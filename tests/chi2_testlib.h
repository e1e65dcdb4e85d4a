/* A chi-squared goodness-of-fit harness for direction samplers (as Mitsuba
 * 3's ChiSquareTest and pbrt-v4's BSDF tests): a sampler is two functions,
 * sample(wo, u) -> wi with the density it claims, and pdf(wo, wi), both in
 * the local frame (normal +z). The harness draws N directions from fixed
 * seeds into a (theta, phi) grid, integrates pdf over each cell (a sub-grid
 * midpoint rule in cos theta and phi), pools the cells expected to hold fewer
 * than CHI2_MIN_EXPECTED, and tests the counts against the expectations with
 * Pearson's statistic at the Sidak-corrected level. It also checks that the
 * integral of pdf over the sphere is the fraction of draws that gave a
 * direction (1 for a sampler that never fails), and that each drawn
 * direction's claimed density and weight agree with pdf and eval. */
#ifndef SPM_CHI2_TESTLIB_H
#define SPM_CHI2_TESTLIB_H
#include <stdint.h>
#include <stdlib.h>
#include "stats_testlib.h"
#include "testutil.h"

#define CHI2_THETA 40
#define CHI2_PHI 80
/* sub-cells per cell side for the integral: the rough dielectric's refraction
 * at grazing incidence (alpha 0.5, wo_z 0.26) needs them; its integral moves
 * 0.97864, 0.97716, 0.97628 at 6, 16, 40 against 0.97584 of 400000 draws */
#define CHI2_SUB 40
#define CHI2_MIN_EXPECTED 5.0

typedef struct {
    const char *name;
    void *ctx;
    /* wi from wo and three uniform numbers; 0 when it gives no direction.
     * *pdf: the density it claims (solid angle), *w its weight f cos / pdf
     * (or NULL-free: always written). */
    int (*sample)(void *ctx, const double wo[3], const double u[3], double wi[3], double *pdf,
                  double *w);
    double (*pdf)(void *ctx, const double wo[3], const double wi[3]);
    /* f(wo, wi) |cos wi| in the same units as w * pdf; NULL: no eval check */
    double (*eval)(void *ctx, const double wo[3], const double wi[3]);
} chi2_sampler;

/* A fixed-seed generator (splitmix64): the tests draw the same numbers every run. */
static inline double chi2_u01(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static inline void chi2_cell(const double wi[3], int *it, int *ip)
{
    double z = wi[2] < -1.0 ? -1.0 : wi[2] > 1.0 ? 1.0 : wi[2];
    double th = acos(z), ph = atan2(wi[1], wi[0]);
    if (ph < 0.0)
        ph += 2.0 * M_PI;
    *it = (int)(th / M_PI * CHI2_THETA);
    *ip = (int)(ph / (2.0 * M_PI) * CHI2_PHI);
    *it = *it < CHI2_THETA ? *it : CHI2_THETA - 1;
    *ip = *ip < CHI2_PHI ? *ip : CHI2_PHI - 1;
}

/* Integral of pdf over each cell into e[] (CHI2_THETA x CHI2_PHI); returns the sum. */
static inline double chi2_integrate(const chi2_sampler *s, const double wo[3], double *e)
{
    double total = 0.0;
    for (int it = 0; it < CHI2_THETA; it++) {
        double t0 = M_PI * it / CHI2_THETA, t1 = M_PI * (it + 1) / CHI2_THETA;
        double z0 = cos(t0), z1 = cos(t1); /* in cos theta the area element is flat */
        for (int ip = 0; ip < CHI2_PHI; ip++) {
            double p0 = 2.0 * M_PI * ip / CHI2_PHI, dp = 2.0 * M_PI / CHI2_PHI / CHI2_SUB;
            double dz = (z0 - z1) / CHI2_SUB, sum = 0.0;
            for (int a = 0; a < CHI2_SUB; a++)
                for (int b = 0; b < CHI2_SUB; b++) {
                    double z = z0 - (a + 0.5) * dz, ph = p0 + (b + 0.5) * dp;
                    double r = sqrt(fmax(0.0, 1.0 - z * z));
                    double wi[3] = {r * cos(ph), r * sin(ph), z};
                    sum += s->pdf(s->ctx, wo, wi);
                }
            e[it * CHI2_PHI + ip] = sum * dz * dp;
            total += e[it * CHI2_PHI + ip];
        }
    }
    return total;
}

/* Runs the checks for one sampler at wo with n draws from seed; alpha_cell:
 * the Sidak-corrected level of this test. Returns the p-value. */
static inline double chi2_run(const chi2_sampler *s, const double wo[3], long n, uint64_t seed,
                              double alpha_test)
{
    static double obs[CHI2_THETA * CHI2_PHI], expct[CHI2_THETA * CHI2_PHI];
    for (int i = 0; i < CHI2_THETA * CHI2_PHI; i++)
        obs[i] = 0.0;
    long got = 0, bad_pdf = 0, bad_w = 0;
    double worst_pdf = 0.0, worst_w = 0.0;
    for (long k = 0; k < n; k++) {
        double u[3] = {chi2_u01(&seed), chi2_u01(&seed), chi2_u01(&seed)}, wi[3], pdf, w;
        if (!s->sample(s->ctx, wo, u, wi, &pdf, &w))
            continue;
        got++;
        int it, ip;
        chi2_cell(wi, &it, &ip);
        obs[it * CHI2_PHI + ip] += 1.0;
        /* the density it claims and its weight against pdf and eval (float
         * arithmetic against double: measured within 4.4e-4 relative over the
         * cases of test_chi2.c; bound 1e-2, one in 10000 outliers allowed) */
        double p = s->pdf(s->ctx, wo, wi);
        if (pdf > 0.0) {
            double r = fabs(pdf / p - 1.0);
            worst_pdf = fmax(worst_pdf, r);
            bad_pdf += !(r <= 1e-2);
        }
        if (s->eval) {
            double f = s->eval(s->ctx, wo, wi), r = fabs(w * p / f - 1.0);
            worst_w = r > worst_w ? r : worst_w;
            bad_w += !(r <= 1e-2);
        }
    }
    double mass = chi2_integrate(s, wo, expct);
    /* Pearson's statistic over the cells, those expected below the minimum pooled */
    double stat = 0.0, pool_o = 0.0, pool_e = 0.0;
    int cells = 0;
    for (int i = 0; i < CHI2_THETA * CHI2_PHI; i++) {
        double e = expct[i] * (double)n;
        if (e < CHI2_MIN_EXPECTED) {
            pool_o += obs[i], pool_e += e;
        } else {
            stat += (obs[i] - e) * (obs[i] - e) / e;
            cells++;
        }
    }
    /* the pool also holds the draws that gave no direction: n - got against n (1 - mass) */
    pool_o += (double)(n - got);
    pool_e += (double)n * (1.0 - mass);
    if (pool_e > 0.0) {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        cells++;
    }
    double pval = st_chi2_sf(stat, cells - 1);
    double frac = (double)got / (double)n, se = sqrt(frac * (1.0 - frac) / (double)n) + 1e-9;
    printf("%-34s wo_z %.2f: chi2 %.1f over %d cells, p %.3g (reject below %.2g); "
           "int pdf %.5f, drawn %.5f; pdf off %.1e, weight off %.1e\n",
           s->name, wo[2], stat, cells, pval, alpha_test, mass, frac, worst_pdf, worst_w);
    CHECK(pval >= alpha_test, "%s wo_z %.2f: chi2 %.1f over %d cells, p %.3g < %.3g", s->name,
          wo[2], stat, cells, pval, alpha_test);
    /* the pdf's integral against the fraction that gave a direction: the
     * quadrature's error (above) plus 5 standard errors of the fraction */
    CHECK(fabs(mass - frac) <= 2e-3 + 5.0 * se, "%s wo_z %.2f: int pdf %.5f but %.5f drew a direction",
          s->name, wo[2], mass, frac);
    CHECK(bad_pdf <= got / 10000 + 2, "%s: %ld claimed densities off pdf (worst %.2g)", s->name,
          bad_pdf, worst_pdf);
    CHECK(bad_w <= got / 10000 + 2, "%s: %ld weights off eval / pdf (worst %.2g)", s->name, bad_w,
          worst_w);
    CHECK(got >= 10000, "%s: only %ld of %ld draws gave a direction", s->name, got, n);
    return pval;
}
#endif
