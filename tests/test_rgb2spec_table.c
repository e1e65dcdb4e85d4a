/* The RGB-to-spectrum coefficient table (rgb2spec_table.h) against the fitter
 * it is built from: its trilinear lookup against direct fits at seeded random
 * colours between the nodes, with the primaries, the secondaries and the
 * cube's edges and faces; its nodes are fits; greys are exact; the texel
 * kinds; the cache file's round trip and refusals; and the model's bin means
 * by Gauss-Legendre against the 1 nm sums and a fine integration. */
#include "colour.h"
#include "rgb2spec.h"
#include "rgb2spec_table.h"
#include "testutil.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static void lab_of(const double coef[3], double lab[3])
{
    spm_error err;
    spm_spectrum s;
    double xyz[3], white[3];
    spm_rgb2spec_eval(coef, &s);
    spm_xyz_reflectance(&s, spm_d65(&err), xyz);
    spm_white_d65(white);
    for (int k = 0; k < 3; k++)
        white[k] *= 100.0;
    spm_xyz_to_lab(xyz, white, lab);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The test colours: the corners of the cube, its edges and faces, then
 * seeded random colours (uniform, and a third of them with a component at 0
 * or near it: the gamut's faces, where the coefficients grow fastest). */
static int test_colours(double (*rgb)[3], int n)
{
    static const double fixed[][3] = {
        {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1},
        {0.5, 0, 0}, {0, 0.02, 0}, {1, 0.5, 0}, {0, 0.3, 1}, {1, 1, 0.5}, {0.9, 0.01, 0.9},
        {0.01, 0.005, 0.002}, {0.999, 0.998, 1.0},
    };
    int m = (int)(sizeof fixed / sizeof fixed[0]);
    memcpy(rgb, fixed, sizeof fixed);
    for (int i = m; i < n; i++) {
        for (int c = 0; c < 3; c++)
            rgb[i][c] = uniform();
        if (i % 3 == 0)
            rgb[i][i / 3 % 3] = (i % 2) ? 0.0 : 1e-3 * uniform();
    }
    return n;
}

typedef struct {
    const char *name;
    double de[2][600]; /* against the direct fit, against the target */
} lookup_stats;

static void percentiles(double *v, int n, double out[3])
{
    qsort(v, n, sizeof v[0], cmp_double);
    out[0] = v[n / 2], out[1] = v[(int)(0.99 * (n - 1))], out[2] = v[n - 1];
}

/* ΔE00 of the trilinear and cubic lookups and of the texel (cubic, polished)
 * against a direct fit and against the target, at each colour. */
static void lookup_vs_fits(const spm_rgb2spec_table *t)
{
    enum { N = 600 };
    static double rgb[N][3];
    static lookup_stats st[3] = {{.name = "trilinear"}, {.name = "cubic"}, {.name = "texel"}};
    test_colours(rgb, N);
    double fit_worst = 0;
    for (int i = 0; i < N; i++) {
        double c[3][3], cf[3], lf[3], scale;
        double fit_de = spm_rgb2spec_fit(rgb[i], cf);
        fit_worst = fit_de > fit_worst ? fit_de : fit_worst;
        lab_of(cf, lf);
        spm_rgb2spec_lookup(t, rgb[i], c[0]);
        spm_rgb2spec_lookup_cubic(t, rgb[i], c[1]);
        spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, rgb[i], c[2], &scale);
        for (int m = 0; m < 3; m++) {
            double lt[3];
            spm_spectrum s;
            lab_of(c[m], lt);
            spm_rgb2spec_eval(c[m], &s);
            st[m].de[0][i] = spm_delta_e_2000(lt, lf);
            st[m].de[1][i] = spm_rgb2spec_delta_e(&s, rgb[i]);
        }
    }
    double p[3][2][3];
    for (int m = 0; m < 3; m++)
        for (int v = 0; v < 2; v++) {
            percentiles(st[m].de[v], N, p[m][v]);
            printf("%-9s vs %-6s over %d colours: ΔE00 median %.3g, p99 %.3g, max %.3g\n",
                   st[m].name, v ? "target" : "fit", N, p[m][v][0], p[m][v][1], p[m][v][2]);
        }
    printf("the direct fit's own ΔE00 to the target: max %.3g\n", fit_worst);
    /* measured here (docs/METHODS.md): trilinear median 0.0065, max 0.38;
     * cubic median 1.1e-4, max 0.31; the bounds leave a factor ~1.3 */
    CHECK(p[0][1][0] <= 0.01, "trilinear lookup vs target ΔE00 median %g", p[0][1][0]);
    CHECK(p[0][1][2] <= 0.5, "trilinear lookup vs target ΔE00 max %g", p[0][1][2]);
    CHECK(p[1][1][0] <= 3e-4, "cubic lookup vs target ΔE00 median %g", p[1][1][0]);
    CHECK(p[1][1][2] <= 0.4, "cubic lookup vs target ΔE00 max %g", p[1][1][2]);
    /* the texel: the goal of issue 52, max 0.01, against the target (and the
     * fit, which is within fit_worst of it) */
    CHECK(p[2][1][2] <= SPM_TEXEL_MAX_DE00, "texel vs target ΔE00 max %g", p[2][1][2]);
    CHECK(p[2][0][2] <= SPM_TEXEL_MAX_DE00 + fit_worst, "texel vs fit ΔE00 max %g", p[2][0][2]);
}

/* At the nodes the lookup is the node: each a fit of its colour. */
static void nodes_are_fits(const spm_rgb2spec_table *t)
{
    double worst = 0;
    for (int n = 0; n < 40; n++) {
        int l = n % 3, k = 1 + (int)(uniform() * (t->res - 1)), j = (int)(uniform() * t->res),
            i = (int)(uniform() * t->res);
        k = k < t->res ? k : t->res - 1;
        double rgb[3], ct[3], cf[3], lt[3], lf[3];
        spm_rgb2spec_node_rgb(t, l, k, j, i, rgb);
        if (rgb[0] == rgb[1] && rgb[1] == rgb[2])
            continue; /* a grey is looked up exactly, not from the node */
        spm_rgb2spec_lookup(t, rgb, ct);
        spm_rgb2spec_fit(rgb, cf);
        lab_of(ct, lt);
        lab_of(cf, lf);
        double d = spm_delta_e_2000(lt, lf);
        worst = d > worst ? d : worst;
    }
    CHECK(worst < 1e-3, "a node is a fit of its colour (ΔE00 %g)", worst);
}

static void greys_and_texels(const spm_rgb2spec_table *t)
{
    const double g[] = {0.0, 0.02, 0.18, 0.5, 0.9, 1.0};
    for (int n = 0; n < 6; n++) {
        double rgb[3] = {g[n], g[n], g[n]}, c[3];
        spm_rgb2spec_lookup(t, rgb, c);
        spm_spectrum s;
        spm_rgb2spec_eval(c, &s);
        double want = g[n] < 1e-6 ? 1e-6 : (g[n] > 1 - 1e-6 ? 1 - 1e-6 : g[n]);
        CHECK(c[0] == 0 && c[1] == 0 && fabs(s.nm1[123] - want) < 1e-12,
              "grey %g is the constant %g (%g)", g[n], want, s.nm1[123]);
    }
    /* unbounded: a value above 1 keeps its chromaticity, its scale the max */
    double hdr[3] = {4.0, 2.0, 1.0}, unit[3] = {1.0, 0.5, 0.25}, c1[3], c2[3], scale;
    double one;
    spm_rgb2spec_texel(t, SPM_TEXEL_UNBOUNDED, hdr, c1, &scale);
    spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, unit, c2, &one);
    CHECK(scale == 4.0 && c1[0] == c2[0] && c1[1] == c2[1] && c1[2] == c2[2],
          "unbounded texel: scale %g and the coefficients of rgb / max", scale);
    spm_rgb2spec_texel(t, SPM_TEXEL_REFLECTANCE, hdr, c1, &scale);
    double white[3] = {1, 1, 1};
    spm_rgb2spec_lookup(t, white, c2);
    CHECK(scale == 1.0 && c1[2] == c2[2], "reflectance texel: clamped to [0, 1]");
    /* emission: value = m S(coef) D65 / Y(D65), so Y follows the texel's rgb */
    double rgb_e[3] = {2.0, 1.0, 0.5}, xyz_rgb[3], xyz_s[3];
    spm_spectrum e;
    spm_error err;
    spm_rgb2spec_texel(t, SPM_TEXEL_EMISSION, rgb_e, c1, &scale);
    CHECK(spm_rgb2spec_texel_spectrum(SPM_TEXEL_EMISSION, c1, scale, &e, &err) == 0, "%s",
          err.msg);
    spm_linear_srgb_to_xyz(rgb_e, xyz_rgb);
    spm_xyz_emission(&e, xyz_s);
    /* 1e-3 relative: the fit's ΔE (under 0.01) and the 1 nm D65's white point */
    CHECK(fabs(xyz_s[1] / xyz_rgb[1] - 1) < 3e-3, "emission texel Y %g vs rgb's %g", xyz_s[1],
          xyz_rgb[1]);
    double black[3] = {0, 0, 0};
    spm_rgb2spec_texel(t, SPM_TEXEL_EMISSION, black, c1, &scale);
    CHECK(scale == 0.0, "a black emission texel has scale 0 (%g)", scale);
}

/* The cache file: a small table written and read back bit for bit; a file
 * for another resolution or other inputs, or cut short, is refused. */
static void cache_file(void)
{
    spm_error err;
    spm_rgb2spec_table a, b;
    CHECK(spm_rgb2spec_table_build(6, 1, &a, &err) == 0, "small table: %s", err.msg);
    char path[] = "rgb2spec_cache_test.bin";
    uint64_t h = spm_rgb2spec_inputs_hash(6);
    CHECK(h != spm_rgb2spec_inputs_hash(7), "the hash includes the resolution");
    CHECK(spm_rgb2spec_cache_write(path, h, &a) == 0, "cache written");
    CHECK(spm_rgb2spec_cache_read(path, 6, h, &b) == 0, "cache read back");
    if (b.coef) {
        CHECK(!memcmp(a.coef, b.coef, sizeof(float) * 3 * 6 * 6 * 6 * 3) &&
                  !memcmp(a.z, b.z, sizeof(float) * 6), "cache round trip is exact");
        spm_rgb2spec_table_free(&b);
    }
    /* what was written is what the fitter gives at a node */
    double rgb[3], cf[3], lt[3], lf[3];
    spm_rgb2spec_node_rgb(&a, 1, 4, 2, 3, rgb);
    const float *n = a.coef + (((size_t)1 * 6 + 4) * 6 * 6 + 2 * 6 + 3) * 3;
    double ct[3] = {n[0], n[1], n[2]};
    spm_rgb2spec_fit(rgb, cf);
    lab_of(ct, lt);
    lab_of(cf, lf);
    CHECK(spm_delta_e_2000(lt, lf) < 1e-3, "a small table's node is its colour's fit (%g)",
          spm_delta_e_2000(lt, lf));
    CHECK(spm_rgb2spec_cache_read(path, 7, h, &b) == 1, "another resolution is refused");
    CHECK(spm_rgb2spec_cache_read(path, 6, h ^ 1, &b) == 1, "other inputs are refused");
    CHECK(truncate(path, 100) == 0 && spm_rgb2spec_cache_read(path, 6, h, &b) == 1,
          "a file cut short is refused");
    unlink(path);
    spm_rgb2spec_table_free(&a);
}

/* mean of the model over [a, b] by composite Simpson, 2000 intervals */
static double fine_mean(const double c[3], double a, double b)
{
    int n = 2000;
    double h = (b - a) / n, s = 0;
    for (int i = 0; i <= n; i++) {
        double x = a + i * h, z = (c[0] * x + c[1]) * x + c[2];
        s += (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2)) * (0.5 + z / (2 * sqrt(1 + z * z)));
    }
    return s * h / 3 / (b - a);
}

/* Bin means: Gauss-Legendre (the shade stage's candidate) and the 1 nm sums
 * (the reference) against a fine integration, over the table's texels. */
static void bin_means(const spm_rgb2spec_table *t)
{
    double worst_sum = 0, worst_gl[5][9] = {{0}};
    for (int n = 0; n < 200; n++) {
        double rgb[3] = {uniform(), uniform(), uniform()}, c[3];
        if (n % 4 == 0)
            rgb[n % 3] = 0.0;
        spm_rgb2spec_lookup(t, rgb, c);
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            int bins = SPM_LEVEL_BINS(l);
            double sum[SPM_TRUTH_BINS], gl[SPM_TRUTH_BINS];
            spm_sigmoid_level_sum(c, l, sum);
            for (int b = 0; b < bins; b++) {
                double f = fine_mean(c, (double)b / bins, (b + 1.0) / bins);
                worst_sum = fmax(worst_sum, fabs(sum[b] - f));
            }
            for (int q = 1; q <= 8; q++) {
                spm_sigmoid_level_gauss(c, l, q, gl);
                for (int b = 0; b < bins; b++)
                    worst_gl[l][q] = fmax(worst_gl[l][q],
                                          fabs(gl[b] - fine_mean(c, (double)b / bins,
                                                                 (b + 1.0) / bins)));
            }
        }
    }
    printf("1 nm sums vs fine integration: max |error| %.3g\n", worst_sum);
    for (int l = 1; l < SPM_NUM_LEVELS; l++) {
        printf("level %d (%d bins): Gauss-Legendre vs fine integration, max |error| by points:", l,
               SPM_LEVEL_BINS(l));
        for (int q = 1; q <= 8; q++)
            printf(" %d:%.2g", q, worst_gl[l][q]);
        printf("\n");
    }
    /* the midpoint rule's error, h^2/24 max|S''| with h = 1/400, measured 8.7e-5
     * for the steepest texels: the 1 nm truth's own distance from the integral */
    CHECK(worst_sum < 2e-4, "1 nm sums are bin means (%g)", worst_sum);
    /* per level, the Gauss order that comes within that same 1e-4 (measured) */
    static const int order[SPM_NUM_LEVELS] = {0, 2, 3, 4, 6};
    for (int l = 1; l < SPM_NUM_LEVELS; l++)
        CHECK(worst_gl[l][order[l]] < 2e-4, "level %d: %d-point Gauss within 2e-4 (%g)", l,
              order[l], worst_gl[l][order[l]]);
}

int main(void)
{
    spm_error err;
    const spm_rgb2spec_table *t = spm_rgb2spec_srgb(&err);
    CHECK(t != NULL, "the sRGB table: %s", err.msg);
    if (!t)
        TEST_END();
    CHECK(t->res == SPM_RGB2SPEC_RES, "resolution %d", t->res);
    nodes_are_fits(t);
    lookup_vs_fits(t);
    greys_and_texels(t);
    cache_file();
    bin_means(t);
    TEST_END();
}
