/* The bidirectional integrator's light kinds beyond the area and point
 * lights, on the CPU reference: bdpt converges to the path and the light
 * tracers' image (bdpt_converge_lib.h: K renders each, per pixel and channel
 * within their joint standard error) on the Cornell box lit by
 *  - a spot light (a delta position with a cone: its emission sampled in the
 *    cone, its density 0 outside it), over glossy boxes;
 *  - a two-sided area light hanging in the room (its emission rays leave
 *    either face, the back face lighting the floor and seen by the camera:
 *    the camera vertex on it weighed by its emission sampling's density of
 *    that face);
 *  - a distant light through the open top of the box (a light at infinity:
 *    its subpaths leave a disc of the bounding sphere, the first vertex's
 *    density that disc's, the camera vertex joined along its direction).
 * bdpt against the light tracer too, whose subpaths start as bdpt's: the
 * two agreeing with the path tracer is the emission sampling's check. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "testutil.h"
#include "bdpt_converge_lib.h"

/* cornell.scene's boxes rough gold and silver */
#define GLOSSY                                                                                   \
    {"material short_box ", "material short_box conductor au_eta au_k alpha 0.25\n"},            \
        {"material tall_box ", "material tall_box conductor au_eta au_k alpha 0.4\n"},           \
    {                                                                                            \
        "spectrum equal ", "spectrum equal equal\nspectrum au_eta file metal_Au_eta.csv\n"       \
                           "spectrum au_k file metal_Au_k.csv\n"                                 \
    }

/* the area light's place a spot 0.05 below the ceiling aimed at the floor,
 * its cone 50 degrees (the boxes and the floor lit, the upper walls only by
 * bounces) */
static const char *const spot[][2] = {
    GLOSSY, {"quad light ", "light spot 0.278 0.5 0.2795 0.30 0 0.30 equal 20 cone 50\n"}};

/* the area light a two-sided panel in mid-air (0.1 below the ceiling), its
 * front facing down: the ceiling lit by its back */
static const char *const twosided[][2] = {
    {"material light ", "material light emit equal 300 twosided\n"},
    {"quad light ", "quad light  0.343 0.40 0.332  0.213 0.40 0.332  0.213 0.40 0.227  "
                    "0.343 0.40 0.227\n"}};

/* the ceiling and its light gone, a distant light coming down through the
 * opening, slanted so the walls cast shadows */
static const char *const distant[][2] = {
    GLOSSY,
    {"quad white  0.556 0.549 0.559  0.000", "\n"},
    {"quad light ", "light distant 0.2 -1 0.3 equal 2\n"}};

#define VARIANT(name, subs)                                                                    \
    do {                                                                                       \
        snprintf(path, sizeof path, "%s/%s.scene", dir, name);                                 \
        if (!it_write_variant(cornell, path, subs, (int)(sizeof subs / sizeof subs[0])))       \
            converge(path, name, 1);                                                           \
        remove(path);                                                                          \
    } while (0)

int main(void)
{
    char cornell[1024], dir[] = "/tmp/specmip_bdptl_XXXXXX", path[1200];
    spm_data_path("scenes/cornell.scene", cornell, sizeof cornell);
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    VARIANT("spot", spot);
    VARIANT("twosided", twosided);
    VARIANT("distant", distant);
    rmdir(dir);
    TEST_END();
}
