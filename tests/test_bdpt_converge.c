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
    char fluor[1024], relay[1024];
    spm_data_path("scenes/fluorescent.scene", fluor, sizeof fluor);
    converge_mode(fluor, "fluorescent", 1, SPM_MODE_RGB);
    spm_data_path("tests/data/scenes/fluor_relay.scene", relay, sizeof relay);
    if (!it_write_variant(relay, path, relay_area, 1))
        converge_mode(path, "relay_area", 1, SPM_MODE_RGB);
    remove(path);
    char frosted[1024];
    spm_data_path("scenes/frosted_lamp.scene", frosted, sizeof frosted);
    converge(frosted, "frosted_lamp", 2);
    rmdir(dir);
    TEST_END();
}
