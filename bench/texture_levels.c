/* Levels for textured factors (docs/METHODS.md, "Textures: levels"): for sets
 * of texel colours lifted through the coefficient table, the binning error
 * of each level against the 1 nm truth (ΔE00 as the pretest measures it:
 * one and two bounces under D65 and under F11), the level each texel needs
 * under the pretest's threshold, and the level two cheap rules pick:
 *   V  the within-bin variation of the sigmoid, exact from the three
 *      coefficients (S is monotone in z, z quadratic in x), against a bound
 *      per level calibrated on one set and tried on the others;
 *   T  one level per texture: the finest any of its texels needs, over the
 *      texels' colours quantised to a 16^3 grid (the set the pretest sees).
 * Usage: texture_levels [COUNT]   (SPECMIP_DATA: the project's data) */
#include "colour.h"
#include "csv.h"
#include "pretest.h"
#include "rgb2spec.h"
#include "rgb2spec_table.h"
#include "texture.h"
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAXL (SPM_NUM_LEVELS - 1)

static uint64_t rng;
static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* The sets: 0 uniform in the cube (calibration, seed 1), 1 uniform (seed 2),
 * 2 saturated (a component under 0.05, the largest over 0.6), 3 muted
 * (each component within 0.15 of a mid grey's). */
static void draw(int set, double rgb[3])
{
    for (int c = 0; c < 3; c++)
        rgb[c] = uniform();
    if (set == 2) {
        int lo = (int)(uniform() * 3) % 3, hi = (lo + 1 + (int)(uniform() * 2) % 2) % 3;
        rgb[lo] *= 0.05;
        rgb[hi] = 0.6 + 0.4 * rgb[hi];
    } else if (set == 3) {
        double g = 0.2 + 0.5 * uniform();
        for (int c = 0; c < 3; c++)
            rgb[c] = g + 0.3 * (rgb[c] - 0.5);
    }
}

static double sig(double z) { return 0.5 + z / (2.0 * sqrt(1.0 + z * z)); }

/* max over the bins of level l of (max - min) of S(z(x)) within the bin */
static double variation(const double c[3], int l)
{
    int bins = SPM_LEVEL_BINS(l);
    double worst = 0.0;
    for (int b = 0; b < bins; b++) {
        double a = (double)b / bins, e = (b + 1.0) / bins;
        double za = (c[0] * a + c[1]) * a + c[2], ze = (c[0] * e + c[1]) * e + c[2];
        double lo = fmin(za, ze), hi = fmax(za, ze);
        if (c[0] != 0.0) {
            double xv = -c[1] / (2.0 * c[0]);
            if (xv > a && xv < e) {
                double zv = (c[0] * xv + c[1]) * xv + c[2];
                lo = fmin(lo, zv), hi = fmax(hi, zv);
            }
        }
        worst = fmax(worst, sig(hi) - sig(lo));
    }
    return worst;
}

static void xyz_of(const double *p, double xyz[3])
{
    const double (*w)[SPM_TRUTH_BINS] = spm_cmf_truth();
    for (int k = 0; k < 3; k++) {
        xyz[k] = 0;
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            xyz[k] += p[i] * w[k][i];
    }
}

/* err[l]: worst over the lights and one or two bounces of the level-l
 * reflectance (held over its bins) against the 1 nm one. */
static void level_errors(const spm_spectrum *s, const spm_spectrum *lights[2], double err[])
{
    for (int l = 1; l <= MAXL; l++) {
        double bins[SPM_TRUTH_BINS], held[SPM_TRUTH_BINS];
        int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
        spm_spectrum_level(s, l, bins);
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            held[i] = bins[i / w];
        err[l] = 0;
        for (int li = 0; li < 2; li++)
            for (int k = 1; k <= 2; k++) {
                double p0[SPM_TRUTH_BINS], pl[SPM_TRUTH_BINS], x0[3], xl[3];
                for (int i = 0; i < SPM_TRUTH_BINS; i++) {
                    p0[i] = lights[li]->nm1[i] * pow(s->nm1[i], k);
                    pl[i] = lights[li]->nm1[i] * pow(held[i], k);
                }
                xyz_of(p0, x0);
                xyz_of(pl, xl);
                err[l] = fmax(err[l], spm_pretest_xyz_error(x0, xl, SPM_METRIC_DE00));
            }
    }
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ns per texel spectrum at each level: the 1 nm sums against Gauss-Legendre
 * of the order that reaches 1e-4 (test_rgb2spec_table) */
static void timing(const spm_rgb2spec_table *t)
{
    enum { N = 20000 };
    static double coef[N][3], out[SPM_TRUTH_BINS];
    static const int order[SPM_NUM_LEVELS] = {0, 2, 3, 4, 6};
    double sink = 0;
    for (int i = 0; i < N; i++) {
        double rgb[3] = {uniform(), uniform(), uniform()}, scale;
        spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, rgb, coef[i], &scale);
    }
    printf("\nbin means per texel (host, scalar C, one core): ns for the 1 nm sums / Gauss\n");
    for (int l = 1; l <= MAXL; l++) {
        double t0 = now();
        for (int i = 0; i < N; i++)
            spm_sigmoid_level_sum(coef[i], l, out), sink += out[0];
        double t1 = now();
        for (int i = 0; i < N; i++)
            spm_sigmoid_level_gauss(coef[i], l, order[l], out), sink += out[0];
        double t2 = now();
        printf("  level %d (%2d bins): sums %.0f ns, %d-point Gauss %.0f ns (%.1fx)\n", l,
               SPM_LEVEL_BINS(l), 1e9 * (t1 - t0) / N, order[l], 1e9 * (t2 - t1) / N,
               (t1 - t0) / (t2 - t1));
    }
    double t0 = now();
    for (int i = 0; i < N; i++) {
        double rgb[3] = {uniform(), uniform(), uniform()}, c[3], scale;
        spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, rgb, c, &scale);
        sink += c[0];
    }
    double t1 = now();
    for (int i = 0; i < N; i++) {
        double rgb[3] = {uniform(), uniform(), uniform()}, c[3];
        spm_rgb2spec_lookup(t, rgb, c);
        sink += c[0];
    }
    double t2 = now();
    printf("texel lift: cubic lookup and polish %.0f ns, trilinear lookup %.0f ns (sink %g)\n",
           1e9 * (t1 - t0) / N, 1e9 * (t2 - t1) / N, sink);
    /* a 256 x 256 level lifted: 8-bit noise (nearly every texel distinct) and
     * an 8 x 8 checker of two colours */
    enum { S = 256 };
    static float px[S * S * 3], lifted[S * S * 4];
    for (int i = 0; i < S * S * 3; i++)
        px[i] = (float)spm_srgb_decode((int)(uniform() * 255.999) / 255.0);
    spm_texmap m = {S, S, px};
    t0 = now();
    long d = spm_texture_lift(t, SPM_TEXEL_REFLECTANCE, &m, lifted);
    t1 = now();
    printf("lift of a %dx%d level: 8-bit noise (%ld distinct) %.2f s", S, S, d, t1 - t0);
    for (int y = 0; y < S; y++)
        for (int x = 0; x < S; x++)
            for (int c = 0; c < 3; c++)
                px[3 * (y * S + x) + c] = ((x / 32 + y / 32) % 2) ? 0.8f : 0.1f * (c + 1);
    t0 = now();
    d = spm_texture_lift(t, SPM_TEXEL_REFLECTANCE, &m, lifted);
    t1 = now();
    printf(", checker (%ld distinct) %.4f s\n", d, t1 - t0);
}

typedef struct {
    double err[SPM_NUM_LEVELS], var[SPM_NUM_LEVELS];
    int need, cell;
} texel;

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 4000;
    spm_error err;
    spm_spectrum f11;
    char path[4096];
    const spm_rgb2spec_table *t = spm_rgb2spec_srgb(&err);
    if (!t || spm_spectrum_load(spm_data_path("spectra/illuminant_F11.csv", path, sizeof path),
                                NULL, SPM_KIND_EMISSION, &f11, &err)) {
        fprintf(stderr, "texture_levels: %s\n", err.msg);
        return 2;
    }
    const spm_spectrum *lights[2] = {spm_d65(&err), &f11};
    spm_pretest_opts o;
    spm_pretest_defaults(&o);
    double T = o.threshold, tau[SPM_NUM_LEVELS] = {0};
    static const char *names[] = {"uniform (calibration)", "uniform", "saturated", "muted"};
    texel *tx = malloc(sizeof(texel) * (size_t)n);
    printf("threshold ΔE00 %.2g (the pretest's), lights D65 and F11, 1 and 2 bounces, %d texels "
           "a set\n", T, n);
    for (int set = 0; set < 4; set++) {
        rng = 0x9e3779b97f4a7c15ull * (uint64_t)(set + 1);
        static unsigned char seen[16 * 16 * 16];
        memset(seen, 0, sizeof seen);
        int per_texture = 1, cells = 0, cell_level = MAXL;
        for (int i = 0; i < n; i++) {
            double rgb[3], c[3], scale;
            draw(set, rgb);
            spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, rgb, c, &scale);
            spm_spectrum s;
            spm_rgb2spec_eval(c, &s);
            level_errors(&s, lights, tx[i].err);
            tx[i].need = 0;
            while (tx[i].need < MAXL && tx[i].err[tx[i].need + 1] <= T)
                tx[i].need++;
            for (int l = 1; l <= MAXL; l++)
                tx[i].var[l] = variation(c, l);
            per_texture = i == 0 ? tx[i].need : (tx[i].need < per_texture ? tx[i].need : per_texture);
            int q = (int)(rgb[0] * 15.999) * 256 + (int)(rgb[1] * 15.999) * 16 + (int)(rgb[2] * 15.999);
            if (!seen[q]) { /* the cell's centre, judged once */
                seen[q] = 1;
                cells++;
                double cc[3] = {((q >> 8) + 0.5) / 16, (((q >> 4) & 15) + 0.5) / 16,
                                ((q & 15) + 0.5) / 16}, e[SPM_NUM_LEVELS];
                spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, cc, c, &scale);
                spm_rgb2spec_eval(c, &s);
                level_errors(&s, lights, e);
                int need = 0;
                while (need < MAXL && e[need + 1] <= T)
                    need++;
                cell_level = need < cell_level ? need : cell_level;
            }
        }
        if (set == 0) /* tau[l]: the least variation among texels that fail level l */
            for (int l = 1; l <= MAXL; l++) {
                tau[l] = 1.0;
                for (int i = 0; i < n; i++)
                    if (tx[i].err[l] > T && tx[i].var[l] < tau[l])
                        tau[l] = tx[i].var[l];
            }
        int hist_need[SPM_NUM_LEVELS] = {0}, hist_v[SPM_NUM_LEVELS] = {0}, unsafe = 0;
        double *picked = malloc(sizeof(double) * (size_t)n), *pmax = malloc(sizeof(double) * (size_t)n);
        for (int i = 0; i < n; i++) {
            int v = 0;
            while (v < MAXL && tx[i].var[v + 1] < tau[v + 1])
                v++;
            hist_need[tx[i].need]++;
            hist_v[v]++;
            unsafe += v > tx[i].need;
            picked[i] = tx[i].err[v > 0 ? v : 1] * (v > 0);
            pmax[i] = tx[i].err[per_texture > 0 ? per_texture : 1] * (per_texture > 0);
        }
        qsort(picked, n, sizeof(double), cmpd);
        qsort(pmax, n, sizeof(double), cmpd);
        printf("\n%s:\n  level needed per texel (0 = 1 nm .. 4 = 10 bins):", names[set]);
        for (int l = 0; l <= MAXL; l++)
            printf(" %d:%.1f%%", l, 100.0 * hist_need[l] / n);
        printf("\n  rule V picks:                                    ");
        for (int l = 0; l <= MAXL; l++)
            printf(" %d:%.1f%%", l, 100.0 * hist_v[l] / n);
        printf("\n  rule V: coarser than needed %.2f%%; error at its pick p99 %.3g max %.3g\n",
               100.0 * unsafe / n, picked[(int)(0.99 * (n - 1))], picked[n - 1]);
        printf("  rule T: level %d (texels %d, quantised cells %d give %d); error p99 %.3g max "
               "%.3g\n", per_texture, n, cells, cell_level, pmax[(int)(0.99 * (n - 1))],
               pmax[n - 1]);
        double e4[4000];
        int m = n < 4000 ? n : 4000;
        for (int l = 1; l <= MAXL; l++) {
            for (int i = 0; i < m; i++)
                e4[i] = tx[i].err[l];
            qsort(e4, m, sizeof(double), cmpd);
            printf("  level %d (%2d bins) binning ΔE00: median %.3g p99 %.3g max %.3g\n", l,
                   SPM_LEVEL_BINS(l), e4[m / 2], e4[(int)(0.99 * (m - 1))], e4[m - 1]);
        }
        free(picked);
        free(pmax);
    }
    printf("\nrule V bounds (calibrated on the first set):");
    for (int l = 1; l <= MAXL; l++)
        printf(" level %d: %.4g", l, tau[l]);
    printf("\n");
    free(tx);
    timing(t);
    return 0;
}
