/* The dielectric's closed forms, host and CPU reference (no device):
 *  - its Fresnel reflectance (the reference's, float) against the angle form
 *    rs = sin(t - i) / sin(t + i), rp = tan(i - t) / tan(i + t) in double,
 *    with total internal reflection past the critical angle;
 *  - the rough lobe's white furnace: the mean of its weights (reflection or
 *    refraction chosen by F, the refraction's 1 / e^2 included) over
 *    stratified samples against the quadrature of the single-scatter BSDF
 *    (Walter et al. 2007's GGX reflection and transmission, height-correlated
 *    G2) times |cos_i| over the sphere, written here in double; from outside
 *    and from inside the glass;
 *  - the absorption pretest judges exp(-sigma d) of each level's bin means of
 *    sigma (what the shade stage computes) over the lengths up to the
 *    object's size, recomputed here. */
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "materials.h"
#include "tables.h"
#include "refcpu_dielectric.h"
#include "testutil.h"

/* the float Fresnel: measured worst 1.8e-6 absolute over this grid; bound 1e-5 */
#define FRESNEL_TOL 1e-5

static double fresnel_angles(double c, double e)
{
    double ti = acos(c), st = sin(ti) / e;
    if (st >= 1.0)
        return 1.0;
    double tt = asin(st);
    if (ti == 0.0) { /* normal incidence: ((e - 1) / (e + 1))^2 */
        double r = (e - 1.0) / (e + 1.0);
        return r * r;
    }
    double rs = sin(tt - ti) / sin(tt + ti), rp = tan(ti - tt) / tan(ti + tt);
    return 0.5 * (rs * rs + rp * rp);
}

static void test_fresnel(void)
{
    const double es[] = {1.33, 1.5, 2.4, 1.0 / 1.33, 1.0 / 1.5, 1.0 / 2.4};
    double worst = 0.0;
    int tir = 0, n = 0;
    for (int a = 0; a < 6; a++)
        for (int i = 0; i <= 200; i++) {
            double c = i / 200.0;
            if (c == 0.0)
                continue; /* grazing: 1 either way */
            float ct;
            double got = spm_ref_diel_fresnel((float)c, (float)es[a], &ct);
            double want = fresnel_angles(c, es[a]);
            worst = fmax(worst, fabs(got - want));
            tir += want == 1.0 && got == 1.0;
            n++;
        }
    printf("fresnel: %d cases (%d past the critical angle), worst %.3g\n", n, tir, worst);
    CHECK(worst <= FRESNEL_TOL, "Fresnel off by %g", worst);
    CHECK(tir > 100, "total internal reflection seen %d times", tir);
}

/* A vertex frame whose normal is +z and tangent +x, wo at polar angle th. */
static spm_ref_cond frame(double th, double ph, float alpha)
{
    spm_tri t;
    memset(&t, 0, sizeof t);
    t.n[2] = 1.0f;
    t.t[0] = 1.0f;
    float d[3] = {(float)-(sin(th) * cos(ph)), (float)-(sin(th) * sin(ph)), (float)-cos(th)};
    spm_ref_cond c;
    spm_ref_cond_make(&t, d, alpha, &c);
    return c;
}

static double lambda_d(double a, double z)
{
    double t2 = (1.0 - z * z) / (z * z);
    return 0.5 * (-1.0 + sqrt(1.0 + a * a * t2));
}

static double ggx_d(double a, double z)
{
    double t = z * z * (a * a - 1.0) + 1.0;
    return a * a / (M_PI * t * t);
}

/* The BSDF times |cos_i| at wi: reflection F D G2 / (4 wo_z) with h =
 * unit(wo + wi); transmission (wi_z < 0) with the generalised half vector
 * m = unit(e wi + wo) (turned to +z), (1 - F(wo.m)) D G2 |wi.m| |wo.m| /
 * (wo_z (wi.m + wo.m / e)^2) / e^2 (radiance: 1 / e^2). */
static double bsdf_cos(double a, double e, const double wo[3], const double wi[3])
{
    double g2 = 1.0 / (1.0 + lambda_d(a, wo[2]) + lambda_d(a, fabs(wi[2])));
    if (wi[2] > 0.0) {
        double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
        double l = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        double ch = (wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]) / l;
        return fresnel_angles(fmin(ch, 1.0), e) * ggx_d(a, h[2] / l) * g2 / (4.0 * wo[2]);
    }
    double m[3] = {e * wi[0] + wo[0], e * wi[1] + wo[1], e * wi[2] + wo[2]};
    double l = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    if (m[2] < 0.0)
        l = -l;
    for (int k = 0; k < 3; k++)
        m[k] /= l;
    double om = wo[0] * m[0] + wo[1] * m[1] + wo[2] * m[2];
    double im = wi[0] * m[0] + wi[1] * m[1] + wi[2] * m[2];
    if (!(om > 0.0) || !(im < 0.0))
        return 0.0;
    double den = im + om / e;
    return (1.0 - fresnel_angles(fmin(om, 1.0), e)) * ggx_d(a, m[2]) * g2 * fabs(im) * om /
           (wo[2] * den * den) / (e * e);
}

/* Mean weight over 256 x 256 visible normals times 8 strata of the choice
 * against the midpoint quadrature (2400 x 720 cells a hemisphere, in
 * cos theta and phi). Measured worst difference 3.0e-3 (alpha 0.2 inside the
 * glass, where the transmitted lobe is narrowest); bound 5e-3. Without the
 * refraction's 1 / e^2 the sums are off by 0.3 or more; weighing the choice
 * by F again, by 0.04 or more. */
static void test_furnace(void)
{
    const float alphas[] = {0.2f, 0.5f, 1.0f};
    const double ths[] = {0.0, 0.8, 1.3};
    const double es[] = {1.5, 1.0 / 1.5};
    double worst = 0.0;
    for (int ie = 0; ie < 2; ie++)
        for (int a = 0; a < 3; a++)
            for (int t = 0; t < 3; t++) {
                spm_ref_cond c = frame(ths[t], 0.3, alphas[a]);
                double wo[3] = {c.wo[0], c.wo[1], c.wo[2]};
                const int nu = 2400, np = 720;
                double integral = 0.0;
                for (int i = 0; i < nu; i++) {
                    double z = (i + 0.5) / nu, r = sqrt(1.0 - z * z);
                    for (int j = 0; j < np; j++) {
                        double ph = 2.0 * M_PI * (j + 0.5) / np;
                        double up[3] = {r * cos(ph), r * sin(ph), z};
                        double dn[3] = {r * cos(ph), r * sin(ph), -z};
                        integral += bsdf_cos(alphas[a], es[ie], wo, up) +
                                    bsdf_cos(alphas[a], es[ie], wo, dn);
                    }
                }
                integral *= 2.0 * M_PI / ((double)nu * np);
                const int ns = 256, nc = 8;
                double mean = 0.0;
                for (int i = 0; i < ns; i++)
                    for (int j = 0; j < ns; j++)
                        for (int q = 0; q < nc; q++) {
                            float out[3], wt, wg, pdf;
                            float uc = (q + (float)((i * 7 + j * 13) % 16 + 0.5f) / 16.0f) / nc;
                            if (spm_ref_diel_lobe(&c, (float)es[ie], (i + 0.5f) / ns,
                                                  (j + 0.5f) / ns, uc, out, &wt, &wg, &pdf))
                                mean += (double)wt * wg;
                        }
                mean /= (double)ns * ns * nc;
                double e = fabs(mean - integral);
                worst = fmax(worst, e);
                printf("furnace e %.3f alpha %.2f theta_o %.2f: lobe %.5f, quadrature %.5f\n",
                       es[ie], alphas[a], ths[t], mean, integral);
                CHECK(e <= 5e-3, "furnace e %g alpha %g theta %g: %g vs %g", es[ie], alphas[a],
                      ths[t], mean, integral);
            }
    printf("furnace: worst %.3g\n", worst);
}

/* The smooth lobe: reflection with probability F at the mirror direction,
 * else refraction by Snell's law with weight 1 / e^2. */
static void test_smooth(void)
{
    spm_ref_cond c = frame(0.6, 1.1, 0.0f);
    float out[3], wt, wg, pdf, ct;
    float f = spm_ref_diel_fresnel(c.wo[2], 1.5f, &ct);
    int up = spm_ref_diel_lobe(&c, 1.5f, 0.3f, 0.7f, 0.5f * f, out, &wt, &wg, &pdf);
    CHECK(up && wt == 1.0f && wg == 1.0f && fabs(out[2] - cos(0.6)) < 1e-6,
          "smooth reflection: %d %g %g z %g", up, wt, wg, out[2]);
    up = spm_ref_diel_lobe(&c, 1.5f, 0.3f, 0.7f, 0.5f + 0.5f * f, out, &wt, &wg, &pdf);
    double st = sin(0.6) / 1.5;
    CHECK(up && fabs(wt - 1.0 / 2.25) < 1e-6 && fabs(out[2] + sqrt(1.0 - st * st)) < 1e-6 &&
              fabs(out[0] + st * cos(1.1)) < 1e-6,
          "smooth refraction: %d %g dir %g %g %g", up, wt, out[0], out[1], out[2]);
    /* from inside past the critical angle (asin(1 / 1.5) = 0.73): always reflects */
    spm_ref_cond g = frame(1.0, 0.0, 0.0f);
    up = spm_ref_diel_lobe(&g, 1.0f / 1.5f, 0.3f, 0.7f, 0.999f, out, &wt, &wg, &pdf);
    CHECK(up && out[2] > 0.0f && wt == 1.0f, "total internal reflection: %d z %g", up, out[2]);
}

static void xyz_of(const double *f, double xyz[3])
{
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int c = 0; c < 3; c++) {
        xyz[c] = 0.0;
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            xyz[c] += f[b] * w[c][b];
    }
}

/* Context A under one equal-energy light (the only spectrum of the set): the
 * pretest's error at each level must be the worst over its six lengths of
 * exp of the level's bin means against exp of the 1 nm sigma, recomputed;
 * and it must grow with the object's size (a longer path through the glass
 * bends the exponential more). */
static void test_pretest(void)
{
    double wl[81], vs[81];
    for (int i = 0; i <= 80; i++) { /* a swing every 5 nm: inside every bin of 10 nm or more */
        wl[i] = 380 + 5 * i;
        vs[i] = i % 2 ? 2.0 : 30.0;
    }
    spm_spectrum sigma, light;
    spm_error err;
    int rc = spm_spectrum_from_samples(wl, vs, 81, SPM_KIND_REFLECTANCE, "sigma", &sigma, &err);
    CHECK(rc == 0, "spectrum: %s", err.msg);
    spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &light);
    const spm_spectrum *set[1] = {&light};
    spm_pretest_opts o;
    spm_pretest_defaults(&o);
    o.coarsest_level = 4;
    const double fr[] = {1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0};
    double s0[SPM_TRUTH_BINS], sl[SPM_TRUTH_BINS], prev = 0.0;
    spm_spectrum_level(&sigma, 0, s0);
    for (int sz = 0; sz < 2; sz++) {
        double dmax = sz ? 0.2 : 0.01;
        spm_pretest_result r;
        spm_dielectric_pretest(set, 1, &sigma, dmax, 1, &o, &r);
        double at4 = 0.0;
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
            spm_spectrum_level(&sigma, l, sl);
            double want = 0.0;
            for (int a = 0; a < 6; a++) {
                double f0[SPM_TRUTH_BINS], fl[SPM_TRUTH_BINS], x0[3], xl[3];
                for (int b = 0; b < SPM_TRUTH_BINS; b++) {
                    f0[b] = exp(-s0[b] * fr[a] * dmax);
                    fl[b] = exp(-sl[b / w] * fr[a] * dmax);
                }
                xyz_of(f0, x0);
                xyz_of(fl, xl);
                want = fmax(want, spm_pretest_xyz_error(x0, xl, SPM_METRIC_DE00));
            }
            printf("pretest size %.2f level %d: %.4f (recomputed %.4f)\n", dmax, l, r.err_k[0][l],
                   want);
            CHECK(fabs(r.err_k[0][l] - want) <= 1e-9 * fmax(1.0, want), "level %d: %g vs %g", l,
                  r.err_k[0][l], want);
            at4 = r.err_k[0][l];
        }
        if (sz)
            CHECK(at4 > 2.0 * prev && at4 > 1.0, "the error does not grow with the size (%g, %g)",
                  prev, at4);
        prev = at4;
    }
}

int main(void)
{
    test_fresnel();
    test_smooth();
    test_pretest();
    test_furnace();
    TEST_END();
}
