/* Statistics for the tests that judge estimators by their noise: the Sidak
 * correction, the normal and chi-squared tails. Each test draws from fixed
 * seeds, so it is deterministic; the significance says how unlikely a
 * correct implementation is to fail for a given seed set (Mitsuba 3's
 * ChiSquareTest uses the same correction). */
#ifndef SPM_STATS_TESTLIB_H
#define SPM_STATS_TESTLIB_H
#include <math.h>

/* The per-test level that keeps the chance of any false alarm among n tests
 * at alpha: 1 - (1 - alpha)^(1/n). */
static inline double st_sidak(double alpha, int n)
{
    return 1.0 - pow(1.0 - alpha, 1.0 / (double)n);
}

/* z with P(|Z| > z) = p for a standard normal Z: erfc(z / sqrt 2) = p, by bisection. */
static inline double st_normal_two_sided(double p)
{
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (erfc(mid / sqrt(2.0)) > p)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* The regularised upper incomplete gamma function Q(a, x) (Numerical Recipes'
 * series below a + 1, Lentz's continued fraction above). */
static inline double st_gamma_q(double a, double x)
{
    if (x <= 0.0)
        return 1.0;
    double lg = lgamma(a);
    if (x < a + 1.0) {
        double ap = a, sum = 1.0 / a, del = sum;
        for (int n = 0; n < 10000 && fabs(del) > fabs(sum) * 1e-15; n++) {
            ap += 1.0;
            del *= x / ap;
            sum += del;
        }
        return 1.0 - sum * exp(-x + a * log(x) - lg);
    }
    double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; i++) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < 1e-300)
            d = 1e-300;
        c = b + an / c;
        if (fabs(c) < 1e-300)
            c = 1e-300;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (fabs(del - 1.0) < 1e-15)
            break;
    }
    return exp(-x + a * log(x) - lg) * h;
}

/* P(X > x) for X chi-squared with dof degrees of freedom. */
static inline double st_chi2_sf(double x, double dof)
{
    return st_gamma_q(0.5 * dof, 0.5 * x);
}
#endif
