/* The coated material's host part (coated.h). */
#include "coated.h"
#include <math.h>
#include <string.h>

double spm_dielectric_fresnel(double eta, double c)
{
    c = c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c;
    double s2 = (1.0 - c * c) / (eta * eta);
    if (s2 >= 1.0)
        return 1.0; /* total internal reflection */
    double ct = sqrt(1.0 - s2);
    double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* integral over mu in [mu0, 1] of F(eta, mu) 2 mu dmu. The integrand has a
 * square-root kink at mu0 (the critical angle's cosine, or 0), so the
 * variable is u with mu = mu0 + (1 - mu0) u^2 (smooth in u), and the rule
 * composite Simpson on 2^16 intervals: against 2^18 the integral moves by
 * less than 1e-12 for eta in [1, 4]. */
static double fresnel_moment(double eta, double mu0)
{
    const int n = 1 << 16;
    double h = 1.0 / n, sum = 0.0, w = 1.0 - mu0;
    for (int i = 0; i <= n; i++) {
        double u = i * h, mu = mu0 + w * u * u;
        double f = spm_dielectric_fresnel(eta, mu) * 2.0 * mu * 2.0 * w * u; /* dmu = 2 w u du */
        sum += f * (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0);
    }
    return sum * h / 3.0;
}

double spm_coat_fdr_internal(double eta)
{
    if (!(eta > 1.0))
        return 0.0; /* index 1: no boundary */
    double muc = sqrt(1.0 - 1.0 / (eta * eta)); /* below it, F = 1 */
    return muc * muc + fresnel_moment(1.0 / eta, muc);
}

double spm_coat_fdr_external(double eta)
{
    if (!(eta > 1.0))
        return 0.0;
    return fresnel_moment(eta, 0.0);
}

void spm_coat_effective(const spm_spectrum *R, double fdr_i, spm_spectrum *out)
{
    memset(out, 0, sizeof *out);
    out->kind = SPM_KIND_REFLECTANCE;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double r = R ? R->nm1[i] : 0.0;
        out->nm1[i] = r * (1.0 - fdr_i) / (1.0 - fdr_i * r);
    }
}
