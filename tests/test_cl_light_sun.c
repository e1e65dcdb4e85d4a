/* The sun of a daylight sky (include/spm_lights.h SUN, kernels/light_sun.clh,
 * host/cpu/refcpu_light_sun.c) on both backends:
 *  - irradiance: a white Lambertian plane (rho = 0.5) seen from above under
 *    the sun alone ('sky 0'): every path's light sample at its first vertex
 *    is the whole of its radiance, a direction uniform in the disc's cone
 *    weighed by its solid angle, so per path
 *      Y = rho L cos(theta_i) Omega / pi,  Omega = 2 pi (1 - cos alpha),
 *    theta_i within alpha of the sun's zenith angle theta_s, and the mean
 *    over the paths rho L Omega cos(theta_s) / pi, the model's E = L Omega
 *    cos(theta_s) (L the sun's luminance the scene gives it; its value
 *    against the model is tests/test_sky.c's);
 *  - the kernel's trace against the reference's, path by path, under the
 *    sky and the sun: a floor, a block casting the sun's shadow and a
 *    polished copper patch of the floor where the camera sees the sun's
 *    reflection, its BSDF-sampled rays escaping into the disc (the escape's
 *    MIS with the disc's density). */
#include "cl_testlib.h"
#include "spm_rng.h"
#include "testutil.h"

#define SEED 5u
#define RHO 0.5
#define ELEV 40.0
#define HALF_DEG 0.2665 /* host/scene/sky.h SPM_SUN_HALF_DEG, written here */
/* per path: cos(theta_i) / cos(theta_s) - 1 is within tan(theta_s) sin(alpha)
 * (5.5e-3 at 40 degrees) plus float error (1e-5: the delta lights' 1.4e-6
 * measured, cos theta_i's rounding near the cone); the mean of 1728 paths
 * within 5e-4 (their spread's standard error 7e-5; measured 2e-5) */
#define MEAN_REL 5e-4

static void check_plane(const spm_trace_params *p, const float *xyz, size_t n, double L,
                        const char *who)
{
    double a = HALF_DEG * M_PI / 180.0, omega = 2.0 * M_PI * (1.0 - cos(a));
    double ts = (90.0 - ELEV) * M_PI / 180.0, want = RHO * L * omega * cos(ts) / M_PI;
    double band = tan(ts) * sin(a) + 1e-5, worst = 0.0, sum = 0.0;
    size_t bad = 0, lit = 0;
    (void)p;
    for (size_t i = 0; i < n; i++) {
        double e = fabs(xyz[3 * i + 1] / want - 1.0);
        worst = fmax(worst, e);
        bad += !(e <= band);
        lit += xyz[3 * i + 1] > 0.0f;
        sum += xyz[3 * i + 1];
    }
    double mean = sum / (double)n / want - 1.0;
    printf("sun plane (%s): %zu paths, %zu lit, worst %.3g of the model's E (band %.3g), mean "
           "%+.3g\n", who, n, lit, worst, band, mean);
    CHECK(lit == n, "%s: %zu of %zu paths unlit", who, n - lit, n);
    CHECK(bad == 0, "%s: %zu paths outside the disc's band (worst %.3g)", who, bad, worst);
    CHECK(fabs(mean) <= MEAN_REL, "%s: the mean is %+.3g of rho E / pi", who, mean);
}

static int write_scene(const char *path, const char *body)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fputs(body, f);
    return fclose(f) != 0;
}

static void test_plane(void)
{
    const char *path = "sun_plane.scene";
    char body[1024];
    snprintf(body, sizeof body, "image 24 18\ncamera position 0 3 0 direction 0 -1 0 fov 70\n"
             "spectrum equal equal\nmaterial floor reflect equal 0.5\n"
             "quad floor -100 0 -100  -100 0 100  100 0 100  100 0 -100\n"
             "background sky elevation %g turbidity 3 azimuth 30 sky 0\n", ELEV);
    if (write_scene(path, body)) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, 24, 18)) {
        CHECK(0, "the plane scene loads");
        return;
    }
    CHECK(s.geom.nemitters == 1 && s.geom.emitters[0].kind == SPM_LIGHT_SUN,
          "the sun alone in the selection (%u entries)", s.geom.nemitters);
    double L = s.geom.emitters[0].p[SPM_LIGHT_P_SCALE];
    const int spp = 4;
    size_t n = (size_t)24 * 18 * spp;
    spm_trace_params p = cl_test_params(&s, SEED, 0, (spm_u32)spp);
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    for (int cl = 0; cl < 2; cl++) {
        memset(xyz, 0, 3 * n * sizeof *xyz);
        int rc = cl_test_render_truth(&s, cl, SEED, 24, 18, spp, paths, xyz);
        CHECK(rc == 0, "%s: the render failed", cl ? "opencl" : "cpu");
        if (!rc)
            check_plane(&p, xyz, n, L, cl ? "opencl" : "cpu");
    }
    free(paths);
    free(xyz);
    cl_test_scene_close(&s);
}

/* as test_cl_trace: a path may diverge only where a few ulps of cos/sin move
 * a ray across an edge; 1 in 1000 is a generous ceiling */
#define MAX_DIVERGENT_FRACTION 1e-3
#define W 32
#define H 24
#define SPP 16

static void test_sky_scene(void)
{
    const char *path = "sun_sky.scene";
    if (write_scene(path, "image 32 24\ncamera position 0 1.2 -3.5 direction 0.321 -0.342 0.883 "
                          "fov 8\nspectrum equal equal\nspectrum cu_eta file metal_Cu_eta.csv\n"
                          "spectrum cu_k file metal_Cu_k.csv\n"
                          "material floor reflect equal 0.6\nmaterial block reflect equal 0.3\n"
                          "material copper conductor cu_eta cu_k alpha 0.05\n"
                          "quad floor -20 0 -20  -20 0 20  20 0 20  20 0 -20\n"
                          "quad block 1.6 0.4 0.3  2.2 0.4 0.3  2.2 0.4 0.8  1.6 0.4 0.8\n"
                          "quad block 1.6 0 0.3  1.6 0.4 0.3  2.2 0.4 0.3  2.2 0 0.3\n"
                          "quad block 1.6 0 0.8  1.6 0.4 0.8  1.6 0.4 0.3  1.6 0 0.3\n"
                          "quad copper 0.4 0.001 -1.2  0.4 0.001 0.2  1.3 0.001 0.2  1.3 0.001 -1.2\n"
                          "background sky elevation 20 turbidity 4 azimuth 160\n")) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "the sky scene loads");
        return;
    }
    CHECK(s.geom.nemitters == 2 && s.geom.emitters[0].kind == SPM_LIGHT_SUN &&
          s.geom.emitters[1].kind == SPM_LIGHT_ENVMAP, "the selection: the sun, then the map");
    size_t n = (size_t)W * H * SPP, diverged, level_diff, sunlit = 0, sunhit = 0, shadowed = 0;
    spm_path *cp = spm_xcalloc(n, sizeof *cp);
    int rc = cl_test_trace_diff(&s, SEED, SPP, cp, &diverged, &level_diff);
    CHECK(rc == 0, "the kernels ran");
    spm_u32 sun = s.geom.emitters[0].colour;
    for (size_t i = 0; !rc && i < n; i++) {
        for (spm_u32 j = 0; j < cp[i].h.nvert; j++)
            sunlit += (cp[i].v[j].ids >> 16) == sun;
        sunhit += cp[i].h.bg == sun;
        shadowed += cp[i].h.nvert > 0 && (cp[i].v[0].ids >> 16) == SPM_NONE;
    }
    printf("sky scene: %zu paths, %zu vertices lit by the sun, %zu escapes into it, %zu first "
           "vertices unlit, %zu diverged, %zu level bytes differ\n", n, sunlit, sunhit, shadowed,
           diverged, level_diff);
    CHECK(!rc && sunlit > n / 16 && sunhit >= 5 && shadowed > n / 50,
          "too little sun, reflected sun or shadow (%zu, %zu, %zu)", sunlit, sunhit, shadowed);
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu of %zu paths diverged",
          diverged, n);
    CHECK(level_diff == 0, "%zu paths with equal records have different level bytes", level_diff);
    free(cp);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_plane();
    test_sky_scene();
    TEST_END();
}
