/* Closed forms per parameter, not only at the furnace settings where the
 * sampling weights cancel (host and CPU reference, no device):
 *  - GGX's normalisation: the projected microfacet area is the surface's,
 *    int D(m) (m.n) dm = 2 pi int_0^1 D(mu) mu dmu = 1, for widths from
 *    nearly smooth to 1 (the reference's D; a D with alpha in place of alpha^2
 *    integrates to 1 at alpha = 1 only);
 *  - Cauchy's index n = A + B / lambda^2 (lambda in micrometres) at the
 *    Fraunhofer F and C lines, 486.1 and 656.3 nm, from the formula and from
 *    a scene's index table (scenes/strategies.scene's 'cauchy 1.5 0.0042'
 *    glass, at the centres of the 1 nm bins holding them);
 *  - Beer-Lambert: the reference's transmittance against exp(-sigma d) at two
 *    distances, and their ratio exp(-sigma (d2 - d1));
 *  - the glowing furnace through the whole pipeline (a scene file, the
 *    materials' own fill and Russian roulette, the CPU backend, the film): a
 *    closed box whose walls emit E and reflect rho shows E / (1 - rho)
 *    everywhere, twice the box of rho 0 at rho 1/2. */
#include <stdlib.h>
#include <string.h>
#include "dispersion.h"
#include "refcpu_conductor.h"
#include "refcpu_dielectric.h"
#include "scene.h"
#include "render_testlib.h"
#include "testutil.h"
#include <unistd.h>

/* Midpoint rule in mu with N steps: D's peak at mu = 1 is about alpha^2 / 2
 * wide in mu, so N = 4e5 gives >= 500 points over it at alpha 0.05. Measured:
 * |integral - 1| <= 9e-7 over the widths below (the float D's rounding);
 * bound 1e-4. */
#define GGX_STEPS 400000
#define GGX_TOL 1e-4

static void test_ggx_normalisation(void)
{
    const float alphas[] = {0.05f, 0.1f, 0.2f, 0.35f, 0.5f, 0.75f, 1.0f};
    for (size_t a = 0; a < sizeof alphas / sizeof alphas[0]; a++) {
        double sum = 0.0, h = 1.0 / GGX_STEPS;
        for (int i = 0; i < GGX_STEPS; i++) {
            double mu = (i + 0.5) * h;
            sum += spm_ref_ggx_d(alphas[a], (float)mu) * mu * h;
        }
        double integral = 2.0 * M_PI * sum;
        printf("GGX alpha %.2f: int D(m) (m.n) dm = %.7f\n", alphas[a], integral);
        CHECK_NEAR(integral, 1.0, GGX_TOL, "GGX normalisation");
    }
}

/* Cauchy's formula in double: the table and the function must agree with it
 * to double rounding (measured 0; bound 1e-12). */
#define CAUCHY_A 1.5
#define CAUCHY_B 0.0042
static double cauchy(double nm)
{
    double um = nm / 1000.0;
    return CAUCHY_A + CAUCHY_B / (um * um);
}

static void test_cauchy(void)
{
    const double lines[2] = {486.1, 656.3}; /* Fraunhofer F and C */
    for (int i = 0; i < 2; i++)
        CHECK_NEAR(spm_disp_cauchy(CAUCHY_A, CAUCHY_B, lines[i]), cauchy(lines[i]), 1e-12,
                   "spm_disp_cauchy at a Fraunhofer line");
    /* n_F - n_C = B (1 / 0.4861^2 - 1 / 0.6563^2) = 0.00802 for B = 0.0042: dispersive */
    double dnfc = spm_disp_cauchy(CAUCHY_A, CAUCHY_B, 486.1) - spm_disp_cauchy(CAUCHY_A, CAUCHY_B, 656.3);
    printf("cauchy %g %g: n_F %.6f, n_C %.6f, n_F - n_C %.6f\n", CAUCHY_A, CAUCHY_B,
           spm_disp_cauchy(CAUCHY_A, CAUCHY_B, 486.1), spm_disp_cauchy(CAUCHY_A, CAUCHY_B, 656.3), dnfc);
    CHECK(dnfc > 0.007 && dnfc < 0.009, "n_F - n_C = %g, not about 0.0080", dnfc);

    char path[1024];
    spm_scene sc;
    spm_error err;
    if (spm_scene_load(spm_data_path("scenes/strategies.scene", path, sizeof path), &sc, &err)) {
        CHECK(0, "%s", err.msg);
        return;
    }
    int row = -1;
    for (int m = 0; m < sc.nmaterials; m++)
        if (!strcmp(sc.materials[m].name, "rough_glass"))
            row = (int)sc.materials[m].p[SPM_DIEL_P_DISP] - 1;
    CHECK(row >= 0 && row < sc.ndisp, "the Cauchy glass has no index table (row %d of %d)", row,
          sc.ndisp);
    if (row >= 0 && row < sc.ndisp)
        for (int i = 0; i < 2; i++) {
            int b = (int)(lines[i] - SPM_LAMBDA_MIN);
            double got = sc.disp[(size_t)row * SPM_TRUTH_BINS + (size_t)b];
            printf("scene table, bin %d (%.1f nm): %.9f\n", b, spm_disp_bin_nm(b), got);
            CHECK_NEAR(got, cauchy(spm_disp_bin_nm(b)), 1e-12, "the scene's Cauchy index");
        }
    spm_scene_free(&sc);
}

/* exp in float: measured relative error <= 1.2e-7; bound 1e-6. */
static void test_beer_lambert(void)
{
    const float sigma[] = {0.3f, 2.0f, 7.5f};
    const float dist[2] = {0.25f, 1.5f};
    for (int s = 0; s < 3; s++) {
        float t[2];
        for (int i = 0; i < 2; i++) {
            t[i] = spm_ref_diel_absorb(sigma[s], dist[i]);
            double want = exp(-(double)sigma[s] * dist[i]);
            CHECK(fabs(t[i] / want - 1.0) <= 1e-6, "sigma %g d %g: %.9g, exp(-sigma d) %.9g",
                  sigma[s], dist[i], t[i], want);
        }
        double ratio = (double)t[1] / t[0], want = exp(-(double)sigma[s] * (dist[1] - dist[0]));
        CHECK(fabs(ratio / want - 1.0) <= 2e-6, "sigma %g: T(%g) / T(%g) = %.9g, not %.9g",
              sigma[s], dist[1], dist[0], ratio, want);
    }
    CHECK(spm_ref_diel_absorb(2.0f, 0.0f) == 1.0f, "no length inside, no absorption");
}

/* A closed unit box whose walls glow 'emit equal 1 twosided' and reflect rho:
 * the image's mean luminance and its standard error over the pixels. */
#define FURNACE_SIZE 16
static int furnace(double rho, double *mean, double *se)
{
    char path[] = "/tmp/spm_furnaceXXXXXX";
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f)
        return 1;
    fprintf(f, "image 8 8\ncamera position 0.5 0.5 0.5  direction 0.3 0.2 1  fov 80\n"
               "spectrum rho inline 380 %g 780 %g end\nspectrum equal equal\n"
               "material glow %s emit equal 1 twosided\n", rho, rho, rho > 0 ? "reflect rho" : "");
    for (int axis = 0; axis < 3; axis++)
        for (int side = 0; side < 2; side++) {
            fprintf(f, "quad glow");
            for (int c = 0; c < 4; c++) { /* the corners of the face axis = side */
                double p[3];
                int a = (axis + 1) % 3, b = (axis + 2) % 3;
                p[axis] = side, p[a] = c == 1 || c == 2, p[b] = c >= 2;
                fprintf(f, "  %g %g %g", p[0], p[1], p[2]);
            }
            fprintf(f, "\n");
        }
    fclose(f);
    rt_render_job j = {path, SPM_MODE_RGB, 256, 3u, FURNACE_SIZE, 0.0, "cpu"};
    rt_render_out o;
    int rc = rt_render(&j, &o, NULL, NULL);
    unlink(path);
    if (rc)
        return 1;
    double s = 0.0, s2 = 0.0, n = FURNACE_SIZE * FURNACE_SIZE;
    for (int i = 0; i < FURNACE_SIZE * FURNACE_SIZE; i++) {
        const float *c = &o.img.rgb[3 * i];
        double y = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        s += y, s2 += y * y;
    }
    free(o.img.rgb);
    *mean = s / n;
    *se = sqrt(fmax(s2 / n - *mean * *mean, 0.0) / (n - 1.0));
    return 0;
}

static void test_furnace(void)
{
    double m0, se0, m1, se1;
    if (furnace(0.0, &m0, &se0) || furnace(0.5, &m1, &se1)) {
        CHECK(0, "the furnace scenes do not render");
        return;
    }
    double ratio = m1 / m0, se = ratio * sqrt(se0 * se0 / (m0 * m0) + se1 * se1 / (m1 * m1));
    printf("furnace: rho 0 %.5f +- %.5f, rho 1/2 %.5f +- %.5f, ratio %.4f +- %.4f (closed form 2)\n",
           m0, se0, m1, se1, ratio, se);
    /* a box's corners give next-event estimation an infinite variance (the
     * 1 / d^2 of a light sample next to an edge), so se understates the
     * noise: measured 1.956, 1.982, 2.009 at 64, 256 and 1024 spp; bound 0.1, where
     * Russian roulette without its 1 / mean weight gives 1.654 */
    CHECK(m0 > 0.0 && fabs(ratio - 2.0) <= 0.1, "furnace rho 1/2: %.4f +- %.4f times the "
          "emission, not 1 / (1 - rho) = 2", ratio, se);
}

int main(void)
{
    test_furnace();
    test_ggx_normalisation();
    test_cauchy();
    test_beer_lambert();
    TEST_END();
}
