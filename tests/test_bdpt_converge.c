/* The bidirectional integrator (--integrator bdpt) on the CPU reference
 * converges to the image of the path and the light integrators: per pixel
 * and channel, the mean of K independent renders (seeds of their own) of
 * each, bdpt against path and bdpt against light, within their joint
 * standard error measured from the K renders, and the image's totals too. On
 * the Cornell box (diffuse, an area light) and a glossy box lit by a point
 * light (its boxes rough conductors: importance-mode eval and pdf of a
 * lobe that is no Lambertian, a delta light that no camera vertex meets),
 * and a dispersive prism throwing an area light's spectrum onto a wall (both
 * subpaths sharing the sample's committed wavelength, its pdf counted once;
 * against the light tracer only, see prism below).
 * Scenes with mirrors or smooth glass are not compared: a path tracer misses
 * what a point light throws through them and a light tracer what the camera
 * sees in them, which is what bdpt adds (their weights: test_bdpt_mis). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "backend_cpu.h"
#include "render_plan.h"
#include "scene.h"
#include "tables.h"
#include "testutil.h"
#include "integrator_testlib.h"

#define SIDE 16
#define K 32      /* independent renders of each integrator */
#define SPP 48    /* samples per pixel of each */
#define Z_MAX 5.5 /* per pixel and channel, Student's t with K - 1 = 31 degrees:
                     two-sided 5e-6, 0.8 % over the 2 x 768 values (measured: worst
                     4.1; 16 renders of 96 spp saw a light tracer's pixel on the
                     floor under the gold boxes at 6.4, its rare large splats
                     missing from the spread of so few renders) */

typedef it_scene scene;

enum { NP = 3 * SIDE * SIDE };

/* the mean m and its variance v per pixel channel of K renders */
static int moments(const scene *s, int integrator, double *m, double *v)
{
    static double y[NP];
    for (int i = 0; i < NP; i++)
        m[i] = v[i] = 0.0;
    for (spm_u32 k = 0; k < K; k++) {
        if (it_render_xyz(s, SPM_MODE_ML, integrator, 7919u * (spm_u32)(integrator + 1) + k, SPP, y))
            return 1;
        for (int i = 0; i < NP; i++)
            m[i] += y[i], v[i] += y[i] * y[i];
    }
    for (int i = 0; i < NP; i++) {
        m[i] /= K;
        v[i] = fmax(0.0, v[i] / K - m[i] * m[i]) / (K - 1);
    }
    return 0;
}

static void compare(const char *scene_name, const char *other, const double *mb,
                    const double *vb, const double *mo, const double *vo)
{
    double worst = 0.0, tot[3][2] = {{0}}, var[3][2] = {{0}}, se[2] = {0.0, 0.0};
    int bad = 0;
    for (int i = 0; i < NP; i++) {
        double z = (mb[i] - mo[i]) / sqrt(vb[i] + vo[i] + 1e-30);
        worst = fmax(worst, isnan(z) ? INFINITY : fabs(z));
        bad += !(fabs(z) <= Z_MAX);
        tot[i % 3][0] += mb[i], var[i % 3][0] += vb[i];
        tot[i % 3][1] += mo[i], var[i % 3][1] += vo[i];
        se[0] += mb[i] > 0.0 ? sqrt(vb[i]) / mb[i] / NP : 0.0;
        se[1] += mo[i] > 0.0 ? sqrt(vo[i]) / mo[i] / NP : 0.0;
    }
    printf("%s %dx%d, %d renders of %d spp: bdpt against %s, worst |z| %.2f; mean relative "
           "standard error bdpt %.2f %%, %s %.2f %%\n",
           scene_name, SIDE, SIDE, K, SPP, other, worst, 100.0 * se[0], other, 100.0 * se[1]);
    for (int c = 0; c < 3; c++) {
        double zt = (tot[c][0] - tot[c][1]) / sqrt(var[c][0] + var[c][1]);
        printf("  %c over the image: bdpt %.5f %s %.5f (%+.3f %%, z %.2f)\n", "XYZ"[c],
               tot[c][0] / (NP / 3), other, tot[c][1] / (NP / 3),
               100.0 * (tot[c][0] / tot[c][1] - 1.0), zt);
        CHECK(tot[c][0] > 0.0 && tot[c][1] > 0.0, "%s: nothing rendered", scene_name);
        CHECK(fabs(zt) <= 4.0, "%s: the image's %c differs from %s's by %.2f standard errors",
              scene_name, "XYZ"[c], other, zt);
    }
    CHECK(bad == 0, "%s: %d pixel channels differ from %s's beyond %.1f standard errors "
                    "(worst %.2f)", scene_name, bad, other, Z_MAX, worst);
}

/* bdpt against the light tracer, and (vs_path) against the path tracer */
static void converge(const char *path, const char *name, int vs_path)
{
    static double m[3][NP], v[3][NP];
    scene s;
    if (it_load(&s, path, SIDE))
        return;
    for (int i = vs_path ? 0 : 1; i < 3; i++)
        if (moments(&s, i, m[i], v[i]))
            return;
    if (vs_path)
        compare(name, "path", m[SPM_INTEGRATOR_BDPT], v[SPM_INTEGRATOR_BDPT],
                m[SPM_INTEGRATOR_PATH], v[SPM_INTEGRATOR_PATH]);
    compare(name, "light", m[SPM_INTEGRATOR_BDPT], v[SPM_INTEGRATOR_BDPT],
            m[SPM_INTEGRATOR_LIGHT], v[SPM_INTEGRATOR_LIGHT]);
    it_free(&s);
}

/* the glossy box under a point light: cornell.scene with each line starting
 * with sub[k][0] replaced by sub[k][1]; the point light the area light's
 * flux (1000 pi 0.0137 W), 0.2 below the ceiling */
static const char *const glossy[][2] = {
    {"material short_box ", "material short_box conductor au_eta au_k alpha 0.25\n"},
    {"material tall_box ", "material tall_box conductor au_eta au_k alpha 0.4\n"},
    {"spectrum equal ", "spectrum equal equal\nspectrum au_eta file metal_Au_eta.csv\n"
                        "spectrum au_k file metal_Au_k.csv\n"},
    {"quad light ", "light point 0.278 0.35 0.2795 equal 43\n"}};
#define NSUB 4

/* the prism on a wall with its spot light made an area light of 0.6 x 0.6
 * where the spot stands, facing the prism (its direction the spot's): large
 * enough that a path tracer's rays through the prism meet it often enough
 * for K renders to measure its spread. Compared with the light tracer only:
 * the path tracer finds the caustic by its BSDF rays meeting the lamp
 * through the prism, rare and large (its relative standard error 16.8 %
 * against bdpt's 8.3 %), and its K renders underestimate its spread (9 pixel
 * channels beyond Z_MAX, worst 8.0, at 0.2 x 0.2 85). The camera side of a
 * committed path against the path tracer is tests/cli_bdpt.sh's prism, bit
 * for bit. */
static const char *const prism[][2] = {
    {"light spot ", "material lamp emit equal 600\n"
                    "quad lamp -3.211547 -0.3 1.688169  -3.211547 0.3 1.688169  "
                    "-3.157737 0.3 2.285751  -3.157737 -0.3 2.285751\n"}};

/* textured.scene's floor and back wall in squares of a few pixels at SIDE
 * (a vertex of either subpath records the texel's colour: its mean colour
 * would wash the squares out) */
static const char *const textured[][2] = {
    {"texture floor ", "texture floor   checker 2   0.80 0.80 0.78  0.12 0.12 0.12\n"},
    {"texture wall ", "texture wall    checker 2   0.60 0.05 0.04  0.05 0.12 0.55\n"}};

/* the Cornell box's white floor, back wall and ceiling normal-mapped in
 * squares leaning 22 degrees to +x and to -x: a light subpath's vertices
 * need the adjoint of their shading normal (Veach) */
static const char *const bumpy[][2] = {
    {"material white ", "texture bump checker 2  0.68 0.5 0.9  0.32 0.5 0.9\n"
                        "material white reflect white normal texture bump\n"}};

/* textures, opacity and normal maps on both subpaths, against both */
static void converge_textures(const char *dir, const char *cornell)
{
    char src[1024], path[1200];
    snprintf(path, sizeof path, "%s/textured.scene", dir);
    spm_data_path("scenes/textured.scene", src, sizeof src);
    if (!it_write_variant(src, path, textured, 2))
        converge(path, "textured", 1);
    spm_data_path("scenes/cutout.scene", src, sizeof src);
    converge(src, "cutout", 0);
    snprintf(path, sizeof path, "%s/bumpy.scene", dir);
    if (!it_write_variant(cornell, path, bumpy, 1))
        converge(path, "bumpy", 1);
    remove(path);
    snprintf(path, sizeof path, "%s/textured.scene", dir);
    remove(path);
}

int main(void)
{
    char cornell[1024], dir[] = "/tmp/specmip_bdpt_XXXXXX", path[1200];
    spm_data_path("scenes/cornell.scene", cornell, sizeof cornell);
    converge(cornell, "cornell", 1);
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/glossy_point.scene", dir);
    if (!it_write_variant(cornell, path, glossy, NSUB))
        converge(path, "glossy_point", 1);
    remove(path);
    char wall[1024];
    spm_data_path("scenes/prism_wall.scene", wall, sizeof wall);
    if (!it_write_variant(wall, path, prism, 1))
        converge(path, "prism_area", 0);
    remove(path);
    converge_textures(dir, cornell);
    rmdir(dir);
    TEST_END();
}
