/* The light kinds: one entry each, its tag SPM_LIGHT_NAME its position in the
 * list. A kind is named here once, and everything else is derived:
 *  - spm_shared.h expands the names into the tags (host, CPU reference and
 *    kernels alike);
 *  - kernels/lights.clh and host/cpu/refcpu_lights.c expand them into one
 *    switch per call of the light contract, a case per kind calling the
 *    kind's own file (kernels/light_<name>.clh, host/cpu/refcpu_light_<name>.c);
 *  - kernels/light_kinds.clh includes each kind's kernel file, which its
 *    entry names under SPM_KERNEL_FILES (a line above the entry);
 *  - host/scene/lights.c expands the fields into the descriptors (lights.h
 *    spm_light_desc): the `light` statement's keyword and arguments, the
 *    kernel define that compiles the kind in, and how its power is found for
 *    the selection; the hooks the fields name are written above the entry
 *    under SPM_LIGHT_HOST_CODE, which lights.c alone defines.
 * The fields are host-only C initialisers; the kernels' expansion drops them.
 * docs/ADDING_A_LIGHT.md says how to add a kind.
 *
 * No include guard: the includer defines SPM_LIGHT_KIND(NAME, ...) first and
 * undefines it after. */

/* triangles of an emitting material (spm_types.h's emitter types): chosen by
 * power (area x Y of the emission), reached by rays too; p[D] = 1 when it
 * emits from both faces ('twosided'), whose emission rays leave either face
 * (each with probability 1/2, cosine-weighted about it) */
#ifdef SPM_KERNEL_FILES
#include "light_area.clh"
#endif
SPM_LIGHT_KIND(AREA,
    .keyword = NULL, /* made by materials with 'emit', not by a statement */
    .define = NULL)  /* always compiled in */

/* the background: two colours by hemisphere (MiniLight's sky above, ground
 * below), the 'background' statement; met only by escaping rays, so not in
 * the selection (sampling it would change every image that has one) */
#ifdef SPM_KERNEL_FILES
#include "light_sky.clh"
#endif
SPM_LIGHT_KIND(SKY,
    .keyword = NULL,
    .define = NULL)

/* a point light: intensity I = POWER / (4 pi) in every direction, a delta
 * (no MIS; no ray hits it). POWER as pbrt-v4's `power`: the emitted
 * power in the unit of an emission's scale (the spectrum normalised to
 * Y = 1, as every emission is) */
#ifdef SPM_KERNEL_FILES
#include "light_point.clh"
#elif defined(SPM_LIGHT_HOST_CODE)
/* 4 pi I */
static double spm_light_power_point(const spm_scene *sc, const float *p)
{
    (void)sc;
    return 4.0 * M_PI * (double)p[SPM_LIGHT_P_SCALE];
}
#endif
SPM_LIGHT_KIND(POINT,
    .keyword = "point",
    .help = "'light point X Y Z SPECTRUM POWER': a point light at (X, Y Z); POWER its total "
            "emitted power (the spectrum at luminance 1 times POWER over 4 pi steradians)",
    .args = "PSW",
    .define = "SPM_WITH_LIGHT_POINT",
    .power = spm_light_power_point)

/* a spot light: a point light whose intensity I f(theta) falls with the
 * angle theta to its axis: f = 1 inside the beam angle b, 0 beyond the cone
 * angle c, between them one of three shapes (p[D], SPM_SPOT_*): linear in
 * theta (Mitsuba 3's `spot`, the default), a smoothstep in cos theta
 * (pbrt-v4's) or the square of a ramp linear in cos theta (glTF's); a
 * delta. p[A] = c, p[B] = b (radians), p[C] = cos c. POWER: the intensity's
 * integral over the cone */
#ifdef SPM_KERNEL_FILES
#include "light_spot.clh"
#elif defined(SPM_LIGHT_HOST_CODE)
/* I times the solid angle of the falloff, 2 pi int_{cos c}^1 f(mu) dmu: 1 to
 * cos b, then over the band the mean of its shape times (cos b - cos c):
 * linear in theta 2 pi (1 - (sin c - sin b) / (c - b)) (2 pi (1 - cos c) as
 * b -> c); a smoothstep's mean 1/2 (pbrt-v4's Phi), a square's 1/3 */
static double spm_light_power_spot(const spm_scene *sc, const float *p)
{
    (void)sc;
    double c = p[SPM_LIGHT_P_A], b = p[SPM_LIGHT_P_B], band;
    if (p[SPM_LIGHT_P_D] == SPM_SPOT_LINEAR)
        band = 1.0 - (c - b > 1e-6 ? (sin(c) - sin(b)) / (c - b) : cos(c));
    else
        band = 1.0 - cos(b) + (cos(b) - cos(c)) * (p[SPM_LIGHT_P_D] == SPM_SPOT_SMOOTHSTEP
                                                       ? 1.0 / 2.0 : 1.0 / 3.0);
    return 2.0 * M_PI * band * (double)p[SPM_LIGHT_P_SCALE];
}
#endif
SPM_LIGHT_KIND(SPOT,
    .keyword = "spot",
    .help = "'light spot X Y Z TX TY TZ SPECTRUM POWER|intensity I cone DEG [falloff DEG] "
            "[shape linear|smoothstep|squared]': a spot light at (X, Y, Z) aimed at (TX, TY, "
            "TZ); cone the half-angle of its edge, falloff the width (degrees) inside it over "
            "which the intensity falls to 0 (default a quarter of the cone), linearly in the "
            "angle (Mitsuba 3's), as a smoothstep in its cosine (pbrt-v4's) or as the square "
            "of a ramp in its cosine (glTF's)",
    .args = "PTSWC",
    .define = "SPM_WITH_LIGHT_SPOT",
    .power = spm_light_power_spot)

/* a distant light: parallel light travelling along p[DIR], irradiance E on
 * a surface facing it; a delta. Its power is E over the disc of the scene's
 * bounding sphere (pi r^2 E), the sphere's centre in p[POS], r in p[A]
 * (spm_light_place), the disc its emission rays leave from */
#ifdef SPM_KERNEL_FILES
#include "light_distant.clh"
#elif defined(SPM_LIGHT_HOST_CODE)
/* E over the disc of the bounding sphere: pi r^2 E */
static double spm_light_power_distant(const spm_scene *sc, const float *p)
{
    double c[3], r;
    spm_light_bounding_sphere(sc, c, &r);
    return M_PI * r * r * (double)p[SPM_LIGHT_P_SCALE];
}

/* the disc its emission rays leave from: the bounding sphere's */
static void spm_light_place_distant(const spm_scene *sc, float *p)
{
    double c[3], r;
    spm_light_bounding_sphere(sc, c, &r);
    for (int k = 0; k < 3; k++)
        p[SPM_LIGHT_P_POS + k] = (float)c[k];
    p[SPM_LIGHT_P_A] = (float)r;
}
#endif
SPM_LIGHT_KIND(DISTANT,
    .keyword = "distant",
    .help = "'light distant DX DY DZ SPECTRUM IRRADIANCE': parallel light travelling along "
            "(DX, DY, DZ), IRRADIANCE on a surface facing it (the spectrum at luminance 1 times "
            "IRRADIANCE)",
    .args = "DSE",
    .define = "SPM_WITH_LIGHT_DISTANT",
    .power = spm_light_power_distant,
    .place = spm_light_place_distant)

/* an environment map: an equirectangular image around the scene (the
 * 'background map' statement), met by escaping rays and sampled by a 2-D
 * piecewise-constant distribution of its texels' luminance x sin(theta), so
 * it takes MIS. Its texels are colours of a palette and a luminance each
 * (host/scene/envmap.h); p[POS..] the scene's centre, p[DIR] cos and
 * p[DIR + 1] sin of its rotation about +y, p[DIR + 2] the scene's radius,
 * p[A] and p[B] the image's width and height. */
#ifdef SPM_KERNEL_FILES
#include "light_envmap.clh"
#endif
SPM_LIGHT_KIND(ENVMAP,
    .keyword = NULL, /* made by 'background map', not by 'light' */
    .define = "SPM_WITH_LIGHT_ENVMAP")

/* the sun of a daylight sky (`background sky`, host/scene/sky.h): a disc of
 * angular radius alpha around p[DIR] (unit, toward it) of uniform radiance
 * p[SCALE] times its colour, sampled uniformly in its cone and met by
 * escaping rays inside it, so it takes MIS; p[B] = 1 - cos alpha, p[C] =
 * sin^2 alpha; p[POS] and p[A] the scene's bounding sphere (its emission
 * rays leave a disc of it, as a distant light's). Listed after the map's
 * statement lights, before the map: the trace stage finds it there. */
#ifdef SPM_KERNEL_FILES
#include "light_sun.clh"
#elif defined(SPM_LIGHT_HOST_CODE)
/* what a disc of radiance L at normal incidence sends through the disc of
 * the bounding sphere: pi r^2 E, E = L pi sin^2 alpha */
static double spm_light_power_sun(const spm_scene *sc, const float *p)
{
    double c[3], r;
    spm_light_bounding_sphere(sc, c, &r);
    return M_PI * r * r * M_PI * (double)p[SPM_LIGHT_P_C] * (double)p[SPM_LIGHT_P_SCALE];
}
#endif
SPM_LIGHT_KIND(SUN,
    .keyword = NULL, /* made by 'background sky' */
    .define = "SPM_WITH_LIGHT_SUN",
    .power = spm_light_power_sun,
    .place = spm_light_place_distant)
