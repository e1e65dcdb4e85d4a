/* RGB -> spectrum (Jakob & Hanika model fitted per colour): accuracy of the fit,
 * exact greys, bounds, and RGB emissions that keep white lights D65-white. */
#include "colour.h"
#include "rgb2spec.h"
#include "testutil.h"
#include <stdlib.h>
#include <string.h>

/* Linear sRGB of a reflectance under D65 (white Y = 100). */
static void back_to_rgb(const spm_spectrum *r, double rgb[3])
{
    spm_error err;
    double xyz[3];
    spm_xyz_reflectance(r, spm_d65(&err), xyz);
    for (int k = 0; k < 3; k++)
        xyz[k] /= 100.0;
    spm_xyz_to_linear_srgb(xyz, rgb);
}

static void check_bounded(const spm_spectrum *s, const char *what)
{
    double lo = 1, hi = 0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        lo = s->nm1[i] < lo ? s->nm1[i] : lo;
        hi = s->nm1[i] > hi ? s->nm1[i] : hi;
    }
    CHECK(lo >= 0.0 && hi <= 1.0, "%s: reflectance within [0, 1] (%g..%g)", what, lo, hi);
}

int main(void)
{
    spm_error err;
    CHECK(spm_d65(&err) != NULL, "D65 loads: %s", err.msg);

    /* MiniLight's red wall. 0.1 is the brief's bar: a tenth of a just-noticeable
     * difference. Mapping back through XYZ -> sRGB, ΔE00 0.1 is ~1e-3 in rgb. */
    const double red[3] = {0.7, 0.2, 0.2};
    spm_spectrum s;
    double de;
    CHECK(spm_rgb_to_reflectance(red, &s, &de, &err) == 0, "red: %s", err.msg);
    CHECK(de < 0.1, "red wall fit ΔE00 %g", de);
    CHECK_NEAR(spm_rgb2spec_delta_e(&s, red), de, 1e-12, "reported ΔE is the spectrum's");
    double back[3];
    back_to_rgb(&s, back);
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(back[k], red[k], 3e-3, "red maps back to its rgb");
    check_bounded(&s, "red");

    /* Black and white and greys are exact constants. */
    const double greys[] = {0.0, 0.18, 0.7, 1.0};
    for (int g = 0; g < 4; g++) {
        double rgb[3] = {greys[g], greys[g], greys[g]};
        CHECK(spm_rgb_to_reflectance(rgb, &s, &de, &err) == 0, "grey: %s", err.msg);
        for (int i = 0; i < SPM_TRUTH_BINS; i += 37)
            CHECK(s.nm1[i] == greys[g], "grey %g is constant (%g at bin %d)", greys[g],
                  s.nm1[i], i);
        /* Only the white points of the sRGB matrix and of the 1 nm D65 table differ. */
        CHECK(de < 0.05, "grey %g ΔE00 %g", greys[g], de);
    }

    /* Out-of-range input is clamped: (1.5, -1, NaN) is (1, 0, 0). */
    double wild[3] = {1.5, -1.0, NAN}, clamped[3] = {1.0, 0.0, 0.0};
    spm_spectrum s2;
    CHECK(spm_rgb_to_reflectance(wild, &s, NULL, &err) == 0, "wild: %s", err.msg);
    CHECK(spm_rgb_to_reflectance(clamped, &s2, NULL, &err) == 0, "clamped: %s", err.msg);
    CHECK(memcmp(s.nm1, s2.nm1, sizeof s.nm1) == 0, "clamping");
    check_bounded(&s, "sRGB red primary");

    /* In-gamut colours over the cube (components 0.05..0.95, fixed grid): each
     * reaches the brief's ΔE00 < 0.1 and stays bounded. */
    double worst = 0;
    int n = 0;
    for (double r = 0.05; r < 1.0; r += 0.3)
        for (double g = 0.05; g < 1.0; g += 0.3)
            for (double b = 0.05; b < 1.0; b += 0.3) {
                double rgb[3] = {r, g, b};
                CHECK(spm_rgb_to_reflectance(rgb, &s, &de, &err) == 0, "%s", err.msg);
                check_bounded(&s, "grid");
                CHECK(de < 0.1, "rgb (%g %g %g): ΔE00 %g", r, g, b, de);
                worst = de > worst ? de : worst;
                n++;
            }
    printf("grid of %d colours: worst ΔE00 %.3g\n", n, worst);

    /* Emission: MiniLight's white light is D65 with Y = 1000. */
    double white_light[3] = {1000, 1000, 1000}, xyz[3], d65[3];
    CHECK(spm_rgb_to_emission(white_light, &s, NULL, &err) == 0, "emission: %s", err.msg);
    CHECK(s.kind == SPM_KIND_EMISSION, "emission kind");
    spm_xyz_emission(&s, xyz);
    double want_white[3];
    spm_linear_srgb_to_xyz(white_light, want_white); /* Y = 1000 to the matrix' 7 digits */
    CHECK_NEAR(xyz[1], want_white[1], 1e-12 * 1000.0, "white light luminance");
    CHECK_NEAR(xyz[1], 1000.0, 1e-3, "white light luminance is 1000");
    spm_white_d65(d65);
    double sum = xyz[0] + xyz[1] + xyz[2], dsum = d65[0] + d65[1] + d65[2];
    /* data/README.md gives D65's chromaticity as 0.31273, 0.32902 over the CMF's
     * full 360-830 nm; cutting to 380-780 nm moves it by about 4e-5. */
    CHECK_NEAR(xyz[0] / sum, d65[0] / dsum, 1e-12, "white light x is D65's");
    CHECK_NEAR(xyz[1] / sum, d65[1] / dsum, 1e-12, "white light y is D65's");
    CHECK_NEAR(xyz[0] / sum, 0.31273, 1e-4, "white light x");
    CHECK_NEAR(xyz[1] / sum, 0.32902, 1e-4, "white light y");

    /* A coloured emission keeps its luminance (Y of the linear sRGB triple) and
     * its chromaticity within the fit's accuracy. */
    double warm[3] = {10, 6, 2}, want[3];
    CHECK(spm_rgb_to_emission(warm, &s, &de, &err) == 0, "warm: %s", err.msg);
    spm_xyz_emission(&s, xyz);
    spm_linear_srgb_to_xyz(warm, want);
    CHECK_NEAR(xyz[1], want[1], 1e-9 * want[1], "warm light luminance");
    CHECK_NEAR(xyz[0] / xyz[1], want[0] / want[1], 0.01, "warm light X/Y");
    CHECK_NEAR(xyz[2] / xyz[1], want[2] / want[1], 0.01, "warm light Z/Y");

    double black[3] = {0, 0, 0}, neg[3] = {1, -1, 1};
    CHECK(spm_rgb_to_emission(black, &s, NULL, &err) != 0, "black emission refused");
    CHECK(spm_rgb_to_emission(neg, &s, NULL, &err) != 0, "negative emission refused");
    TEST_END();
}
