/* RGB -> spectrum after W. Jakob and J. Hanika, "A Low-Dimensional Function
 * Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2), 2019.
 *
 * What we do: the paper's model, a sigmoid of a quadratic polynomial in
 * wavelength (three coefficients, smooth, always within (0, 1)), and its
 * objective, the CIELAB difference under the colour space's white (D65 for
 * sRGB) between the target colour and the spectrum's colour. Where the paper
 * precomputes a 3D coefficient table, we fit each distinct colour when a scene
 * is imported (scenes have few colours): Levenberg-Marquardt (Gauss-Newton with
 * damping) on the three Lab residuals, Jacobian by central differences through
 * the same XYZ code the renderer's colour science uses, and - as the paper does
 * when filling its table - continuation: the target moves in steps from mid grey
 * (whose solution, coef = 0, is exact) to the colour, each step starting from
 * the previous solution, so saturated colours are reached without a poor start.
 * The spectrum is evaluated at the centre of each 1 nm truth bin; the fit is
 * made on exactly those bins, so what the renderer gets is what was fitted. */
#include "rgb2spec.h"
#include "colour.h"
#include "csv.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIT_STEPS 8          /* continuation steps from grey to the target */
#define FIT_ITERS 60         /* LM iterations per step */
#define FIT_TOL2 1e-12       /* stop when |Lab residual|^2 is below this */

/* The fit cannot report errors; D65 is bundled data, so its absence is a broken
 * installation (spm_rgb_to_* check it first and report it properly). */
static const spm_spectrum *d65_required(void)
{
    spm_error err;
    const spm_spectrum *d = spm_d65(&err);
    if (!d) {
        fprintf(stderr, "specmip: %s\n", err.msg);
        exit(SPM_EXIT_RUNTIME);
    }
    return d;
}

static double sigmoid(double z) { return 0.5 + z / (2.0 * sqrt(1.0 + z * z)); }

void spm_rgb2spec_eval(const double coef[3], spm_spectrum *out)
{
    out->kind = SPM_KIND_REFLECTANCE;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double x = (i + 0.5) / SPM_TRUTH_BINS;
        out->nm1[i] = sigmoid((coef[0] * x + coef[1]) * x + coef[2]);
    }
}

static void white_lab_ref(double white[3])
{
    spm_white_d65(white);
    for (int k = 0; k < 3; k++)
        white[k] *= 100.0;
}

static void rgb_lab(const double rgb[3], double lab[3])
{
    double xyz[3], white[3];
    spm_linear_srgb_to_xyz(rgb, xyz);
    for (int k = 0; k < 3; k++)
        xyz[k] *= 100.0;
    white_lab_ref(white);
    spm_xyz_to_lab(xyz, white, lab);
}

static void reflectance_lab(const spm_spectrum *r, double lab[3])
{
    double xyz[3], white[3];
    spm_xyz_reflectance(r, d65_required(), xyz);
    white_lab_ref(white);
    spm_xyz_to_lab(xyz, white, lab);
}

double spm_rgb2spec_delta_e(const spm_spectrum *r, const double rgb[3])
{
    double a[3], b[3];
    reflectance_lab(r, a);
    rgb_lab(rgb, b);
    return spm_delta_e_2000(a, b);
}

/* The Lab of the model's spectrum for coef: through the renderer's colour
 * code for one colour, through precomputed weights for the table. */
typedef void (*lab_fn)(const double coef[3], const void *ctx, double lab[3]);

static void model_lab(const double coef[3], const void *ctx, double lab[3])
{
    (void)ctx;
    spm_spectrum s;
    spm_rgb2spec_eval(coef, &s);
    reflectance_lab(&s, lab);
}

static void residual(lab_fn f, const void *ctx, const double coef[3], const double target[3],
                     double r[3])
{
    f(coef, ctx, r);
    for (int k = 0; k < 3; k++)
        r[k] -= target[k];
}

static double norm2(const double r[3]) { return r[0] * r[0] + r[1] * r[1] + r[2] * r[2]; }

/* Solves a x = b for a 3x3 system by Gaussian elimination with partial
 * pivoting; returns 1 if the matrix is (numerically) singular. */
static int solve3(double a[3][3], double b[3], double x[3])
{
    for (int c = 0; c < 3; c++) {
        int p = c;
        for (int r = c + 1; r < 3; r++)
            if (fabs(a[r][c]) > fabs(a[p][c]))
                p = r;
        if (!(fabs(a[p][c]) > 1e-300))
            return 1;
        for (int k = 0; k < 3; k++) {
            double t = a[c][k];
            a[c][k] = a[p][k];
            a[p][k] = t;
        }
        double t = b[c];
        b[c] = b[p];
        b[p] = t;
        for (int r = c + 1; r < 3; r++) {
            double f = a[r][c] / a[c][c];
            for (int k = c; k < 3; k++)
                a[r][k] -= f * a[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int c = 2; c >= 0; c--) {
        double s = b[c];
        for (int k = c + 1; k < 3; k++)
            s -= a[c][k] * x[k];
        x[c] = s / a[c][c];
    }
    return 0;
}

/* Levenberg-Marquardt from coef towards target Lab; coef is updated in place. */
static void lm(lab_fn f, const void *ctx, double coef[3], const double target[3])
{
    double r[3], mu = 1e-3;
    residual(f, ctx, coef, target, r);
    double cost = norm2(r);
    for (int it = 0; it < FIT_ITERS && cost > FIT_TOL2; it++) {
        double J[3][3]; /* J[i][k] = d r_i / d coef_k */
        for (int k = 0; k < 3; k++) {
            double h = 1e-4 * fmax(1.0, fabs(coef[k])), cp[3], cm[3], rp[3], rm[3];
            memcpy(cp, coef, sizeof cp);
            memcpy(cm, coef, sizeof cm);
            cp[k] += h;
            cm[k] -= h;
            residual(f, ctx, cp, target, rp);
            residual(f, ctx, cm, target, rm);
            for (int i = 0; i < 3; i++)
                J[i][k] = (rp[i] - rm[i]) / (2.0 * h);
        }
        double JtJ[3][3], Jtr[3];
        for (int a = 0; a < 3; a++) {
            Jtr[a] = 0.0;
            for (int i = 0; i < 3; i++)
                Jtr[a] += J[i][a] * r[i];
            for (int b = 0; b < 3; b++) {
                JtJ[a][b] = 0.0;
                for (int i = 0; i < 3; i++)
                    JtJ[a][b] += J[i][a] * J[i][b];
            }
        }
        int improved = 0;
        while (!improved && mu < 1e12) {
            double A[3][3], g[3], d[3], trial[3], rt[3];
            for (int a = 0; a < 3; a++) {
                for (int b = 0; b < 3; b++)
                    A[a][b] = JtJ[a][b];
                A[a][a] += mu * (JtJ[a][a] + 1e-12);
                g[a] = -Jtr[a];
            }
            if (solve3(A, g, d)) {
                mu *= 10.0;
                continue;
            }
            for (int k = 0; k < 3; k++)
                trial[k] = coef[k] + d[k];
            residual(f, ctx, trial, target, rt);
            double c2 = norm2(rt);
            if (c2 < cost) {
                memcpy(coef, trial, sizeof trial);
                memcpy(r, rt, sizeof rt);
                cost = c2;
                mu = fmax(mu / 3.0, 1e-9);
                improved = 1;
            } else {
                mu *= 4.0;
            }
        }
        if (!improved)
            break; /* at a minimum the damping cannot leave */
    }
}

static void clamp01(const double in[3], double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = in[k] > 0.0 ? (in[k] < 1.0 ? in[k] : 1.0) : 0.0; /* NaN -> 0 */
}

double spm_rgb2spec_fit(const double rgb_in[3], double coef[3])
{
    double rgb[3];
    clamp01(rgb_in, rgb);
    coef[0] = coef[1] = coef[2] = 0.0; /* S(0) = 1/2: mid grey */
    for (int s = 1; s <= FIT_STEPS; s++) {
        double t = (double)s / FIT_STEPS, step[3], target[3];
        for (int k = 0; k < 3; k++)
            step[k] = 0.5 + t * (rgb[k] - 0.5);
        rgb_lab(step, target);
        lm(model_lab, NULL, coef, target);
    }
    spm_spectrum sp;
    spm_rgb2spec_eval(coef, &sp);
    return spm_rgb2spec_delta_e(&sp, rgb);
}

/* Lab through weights w[k][i] = D65_i cmf_k,i * 100 / Y(D65): the same sums
 * as reflectance_lab without building a spectrum per call. */
static void weights_lab(const double coef[3], const void *ctx, double lab[3])
{
    const double (*w)[SPM_TRUTH_BINS] = ctx;
    double xyz[3] = {0, 0, 0}, white[3];
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double x = (i + 0.5) / SPM_TRUTH_BINS;
        double s = sigmoid((coef[0] * x + coef[1]) * x + coef[2]);
        for (int k = 0; k < 3; k++)
            xyz[k] += s * w[k][i];
    }
    white_lab_ref(white);
    spm_xyz_to_lab(xyz, white, lab);
}

void spm_rgb2spec_weights(double w[3][SPM_TRUTH_BINS])
{
    const spm_spectrum *d = d65_required();
    const double (*cmf)[SPM_TRUTH_BINS] = spm_cmf_truth();
    double white = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        white += d->nm1[i] * cmf[1][i];
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            w[k][i] = d->nm1[i] * cmf[k][i] * (100.0 / white);
}

void spm_rgb2spec_refine(const double w[3][SPM_TRUTH_BINS], const double from[3],
                         const double rgb_in[3], int steps, double coef[3])
{
    double rgb[3];
    clamp01(rgb_in, rgb);
    for (int s = 1; s <= steps; s++) {
        double t = (double)s / steps, step[3], target[3];
        for (int k = 0; k < 3; k++)
            step[k] = from[k] + t * (rgb[k] - from[k]);
        rgb_lab(step, target);
        lm(weights_lab, w, coef, target);
    }
}

double spm_rgb2spec_delta_e_w(const double w[3][SPM_TRUTH_BINS], const double coef[3],
                              const double rgb_in[3])
{
    double rgb[3], a[3], b[3];
    clamp01(rgb_in, rgb);
    weights_lab(coef, w, a);
    rgb_lab(rgb, b);
    return spm_delta_e_2000(a, b);
}

int spm_rgb_to_reflectance(const double rgb_in[3], spm_spectrum *out, double *de00,
                           spm_error *err)
{
    if (!spm_d65(err) || spm_cmf_init(err))
        return 1;
    double rgb[3];
    clamp01(rgb_in, rgb);
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
        /* A grey (black and white included) is a constant: exact, not fitted. */
        spm_spectrum_constant(rgb[0], SPM_KIND_REFLECTANCE, out);
        if (de00)
            *de00 = spm_rgb2spec_delta_e(out, rgb);
        return 0;
    }
    double coef[3];
    double de = spm_rgb2spec_fit(rgb, coef);
    spm_rgb2spec_eval(coef, out);
    if (de00)
        *de00 = de;
    return 0;
}

int spm_rgb_to_emission(const double rgb[3], spm_spectrum *out, double *de00, spm_error *err)
{
    double m = fmax(rgb[0], fmax(rgb[1], rgb[2]));
    if (!(m > 0.0) || !isfinite(m) || rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) {
        spm_errorf(err, "RGB emission (%g %g %g) must be finite, non-negative and not black",
                   rgb[0], rgb[1], rgb[2]);
        return 1;
    }
    double shape_rgb[3] = {rgb[0] / m, rgb[1] / m, rgb[2] / m}, xyz[3];
    if (spm_rgb_to_reflectance(shape_rgb, out, de00, err))
        return 1;
    spm_spectrum_multiply(out, spm_d65(err));
    out->kind = SPM_KIND_EMISSION;
    double Y_rgb, Y_spec;
    spm_linear_srgb_to_xyz(rgb, xyz);
    Y_rgb = xyz[1];
    spm_xyz_emission(out, xyz);
    Y_spec = xyz[1];
    if (!(Y_spec > 0.0) || !(Y_rgb > 0.0)) {
        spm_errorf(err, "RGB emission (%g %g %g) has no luminance", rgb[0], rgb[1], rgb[2]);
        return 1;
    }
    spm_spectrum_scale(out, Y_rgb / Y_spec);
    return 0;
}
