/* The bidirectional integrator (--integrator bdpt) on the CPU reference
 * converges to the image of the path and the light integrators: per pixel
 * and channel, the mean of K independent renders (seeds of their own) of
 * each, bdpt against path and bdpt against light, within their joint
 * standard error measured from the K renders, and the image's totals too. On
 * the Cornell box (diffuse, an area light) and a glossy box lit by a point
 * light (its boxes rough conductors: importance-mode eval and pdf of a
 * lobe that is no Lambertian, a delta light that no camera vertex meets),
 * a dispersive prism throwing an area light's spectrum onto a wall (both
 * subpaths sharing the sample's committed wavelength, its pdf counted once;
 * against the light tracer only, see prism below), fluorescent scenes
 * (each connected path's re-radiation matrices in light-flow order, whichever
 * subpath a fluorescent vertex came from), and a lamp behind a slab
 * of rough glass (scenes/frosted_lamp.scene: the rough refraction's eval in
 * both modes at the joins, its reverse densities through the slab in MIS).
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

#include "bdpt_converge_lib.h"

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

/* two dyes in series (fluor_relay.scene: the floor's turns the lamp's blue
 * green, the back wall's that green red) with its spot light made an area
 * light of 0.6 x 0.6 facing down over the floor, so bdpt joins to it: the
 * wall's red exists only if each connected path applies the floor's matrix
 * before the wall's, whichever subpath either vertex came from */
static const char *const relay_area[][2] = {
    {"light spot ", "material lamp emit band 40\n"
                    "quad lamp -0.3 1 1.2  0.3 1 1.2  0.3 1 1.8  -0.3 1 1.8\n"}};

/* The frosted lamp is compared with the path tracer over the image only:
 * a camera path meets the lamp behind the slab by its sampled rays alone
 * (glass occludes light samples), rare and large (relative standard error
 * per pixel 41 % against bdpt's 3.3 %), so its K renders do not measure its
 * spread per pixel (worst |z| 36 at 48 spp); against the light tracer, per
 * pixel (worst 3.0), the image totals within 0.8 % of the path tracer's. */
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

/* the plain scenes: the Cornell box, the glossy box under a point light,
 * the area-lit prism */
static void converge_plain(const char *dir, const char *cornell)
{
    char path[1200], wall[1024];
    snprintf(path, sizeof path, "%s/glossy_point.scene", dir);
    converge(cornell, "cornell", 1);
    if (!it_write_variant(cornell, path, glossy, NSUB))
        converge(path, "glossy_point", 1);
    spm_data_path("scenes/prism_wall.scene", wall, sizeof wall);
    if (!it_write_variant(wall, path, prism, 1))
        converge(path, "prism_area", 0);
    remove(path);
}

static void converge_fluor(const char *dir, const char *cornell)
{
    char path[1200], fluor[1024], relay[1024];
    (void)cornell;
    snprintf(path, sizeof path, "%s/relay_area.scene", dir);
    spm_data_path("scenes/fluorescent.scene", fluor, sizeof fluor);
    converge_mode(fluor, "fluorescent", 1, SPM_MODE_RGB);
    spm_data_path("tests/data/scenes/fluor_relay.scene", relay, sizeof relay);
    if (!it_write_variant(relay, path, relay_area, 1))
        converge_mode(path, "relay_area", 1, SPM_MODE_RGB);
    remove(path);
}

static void converge_rough(const char *dir, const char *cornell)
{
    char frosted[1024];
    (void)dir, (void)cornell;
    spm_data_path("scenes/frosted_lamp.scene", frosted, sizeof frosted);
    converge(frosted, "frosted_lamp", 2);
}

/* argv[1] names one group of scenes (ctest runs each as a test of its own,
 * side by side); none runs them all */
int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*run)(const char *dir, const char *cornell);
    } group[] = {{"plain", converge_plain},
                 {"fluor", converge_fluor},
                 {"rough", converge_rough},
                 {"textures", converge_textures}};
    char cornell[1024], dir[] = "/tmp/specmip_bdpt_XXXXXX";
    int ran = 0;
    spm_data_path("scenes/cornell.scene", cornell, sizeof cornell);
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    for (size_t i = 0; i < sizeof group / sizeof group[0]; i++)
        if (argc < 2 || !strcmp(argv[1], group[i].name)) {
            group[i].run(dir, cornell);
            ran++;
        }
    CHECK(ran > 0, "no group of scenes named '%s'", argc > 1 ? argv[1] : "");
    rmdir(dir);
    TEST_END();
}
