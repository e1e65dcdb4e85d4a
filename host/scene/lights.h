/* The light kinds as descriptors, one per tag, from the one list
 * (include/spm_lights.h: an entry's name is its tag SPM_LIGHT_*, its fields
 * the descriptor): the `light` statement reads a kind's arguments from its
 * descriptor, the geometry weighs it for the selection by its power, the
 * render plan compiles in the kernel code of the kinds a scene uses.
 * docs/ADDING_A_LIGHT.md says how to add one. */
#ifndef SPM_LIGHTS_H
#define SPM_LIGHTS_H
#include <stddef.h>
#include "scene.h"

typedef struct {
    unsigned tag;          /* its index in the table */
    const char *keyword;   /* after 'light'; NULL: not made by the statement */
    const char *help;      /* the statement's form and the units */
    /* The statement's arguments in order, a letter each (scene_parse.c):
     *   P  a position, three numbers: p[SPM_LIGHT_P_POS..]
     *   D  a direction, three numbers, not zero (made unit): p[SPM_LIGHT_P_DIR..]
     *   S  a spectrum name: the light's colour (its values as given; no scale)
     *   T  a target position, three numbers: p[SPM_LIGHT_P_DIR..] the unit
     *      direction toward it from the P before it
     *   W  a radiant power in W (per unit of the spectrum), or the word
     *      `intensity` and a radiant intensity (W/sr per unit of the spectrum):
     *      p[SPM_LIGHT_P_SCALE] the intensity, a power divided by what the
     *      kind's power hook gives for intensity 1 once every argument is read
     *   E  an irradiance (W/m^2 per unit of the spectrum): p[SPM_LIGHT_P_SCALE]
     *   C  `cone DEG [falloff DEG] [shape NAME]`: the cone's half-angle in
     *      (0, 90] into p[SPM_LIGHT_P_A] (radians) and its cosine into
     *      p[SPM_LIGHT_P_C], the beam angle DEG - falloff (default 3/4 of the
     *      cone, Mitsuba 3's beam_width) into p[SPM_LIGHT_P_B], the falloff's
     *      shape (SPM_SPOT_*: linear, smoothstep, squared) into p[SPM_LIGHT_P_D] */
    const char *args;
    const char *define;    /* the kernel define that compiles it in (NULL: always) */
    /* its radiant power per unit of the spectrum (W), from its parameters p
     * and the scene (a distant light's bounding sphere) */
    double (*power)(const spm_scene *sc, const float *p);
    /* what the scene adds to its parameters p (NULL: nothing) */
    void (*place)(const spm_scene *sc, float *p);
} spm_light_desc;

extern const spm_light_desc spm_light_kinds[];
extern const int spm_nlight_kinds;

/* the kind whose keyword is kw, or NULL */
const spm_light_desc *spm_light_kind_find(const char *kw);
/* "-DNAME " for each kind the selection table em[0, n) holds that has a
 * define, into buf; returns the length written */
int spm_light_defines(const spm_emitter *em, int n, char *buf, size_t size);
/* The selection's weight of a statement's light (scene.h spm_scene_light),
 * in the area lights' unit, area x Y of radiance: its radiant power in Y
 * over pi (a point light: 4 pi I_Y / pi). */
double spm_light_power(const spm_scene *sc, const spm_scene_light *l);
/* the scene's bounding sphere: its box's centre and half diagonal (pbrt-v4's
 * Bounds3::BoundingSphere); r = 0 for a scene with no triangles. For the
 * kinds' hooks (include/spm_lights.h). */
void spm_light_bounding_sphere(const spm_scene *sc, double c[3], double *r);
/* The emitter's parameters of statement light l: its own, and what its
 * kind's place hook adds from the scene (a distant light's bounding sphere,
 * centre into p[POS], radius into p[A]). */
void spm_light_place(const spm_scene *sc, const spm_scene_light *l, float p[SPM_LIGHT_PARAMS]);
#endif
