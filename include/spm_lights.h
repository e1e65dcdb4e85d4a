/* The light kinds: one entry each, its tag SPM_LIGHT_NAME its position in the
 * list. A kind is named here once, and everything else is derived:
 *  - spm_shared.h expands the names into the tags (host, CPU reference and
 *    kernels alike);
 *  - kernels/lights.clh and host/cpu/refcpu_lights.c expand them into one
 *    switch per call of the light contract, a case per kind calling the
 *    kind's own file (kernels/light_<name>.clh, host/cpu/refcpu_light_<name>.c);
 *  - host/scene/lights.c expands the fields into the descriptors (lights.h
 *    spm_light_desc): the `light` statement's keyword and arguments, the
 *    kernel define that compiles the kind in, and how its power is found for
 *    the selection.
 * The fields are host-only C initialisers; the kernels' expansion drops them.
 * docs/ADDING_A_LIGHT.md says how to add a kind.
 *
 * No include guard: the includer defines SPM_LIGHT_KIND(NAME, ...) first and
 * undefines it after. */

/* triangles of an emitting material (spm_types.h's emitter types): chosen by
 * power (area x Y of the emission), reached by rays too */
SPM_LIGHT_KIND(AREA,
    .keyword = NULL, /* made by materials with 'emit', not by a statement */
    .define = NULL)  /* always compiled in */

/* the background: two colours by hemisphere (MiniLight's sky above, ground
 * below), the 'background' statement; met only by escaping rays, so not in
 * the selection (sampling it would change every image that has one) */
SPM_LIGHT_KIND(SKY,
    .keyword = NULL,
    .define = NULL)

/* a point light: intensity I = POWER / (4 pi) in every direction, a delta
 * (no MIS; no ray hits it). POWER as pbrt-v4's `power`: the emitted
 * power in the unit of an emission's scale (the spectrum normalised to
 * Y = 1, as every emission is) */
SPM_LIGHT_KIND(POINT,
    .keyword = "point",
    .help = "'light point X Y Z SPECTRUM POWER': a point light at (X, Y Z); POWER its total "
            "emitted power (the spectrum at luminance 1 times POWER over 4 pi steradians)",
    .args = "PSW",
    .define = "SPM_WITH_LIGHT_POINT",
    .solid = 12.566370614359172) /* 4 pi */

/* an environment map: an equirectangular image around the scene (the
 * 'background map' statement), met by escaping rays and sampled by a 2-D
 * piecewise-constant distribution of its texels' luminance x sin(theta), so
 * it takes MIS. Its texels are colours of a palette and a luminance each
 * (host/scene/envmap.h); p[POS..] the scene's centre, p[DIR] cos and
 * p[DIR + 1] sin of its rotation about +y, p[DIR + 2] the scene's radius,
 * p[A] and p[B] the image's width and height. */
SPM_LIGHT_KIND(ENVMAP,
    .keyword = NULL, /* made by 'background map', not by 'light' */
    .define = "SPM_WITH_LIGHT_ENVMAP")
