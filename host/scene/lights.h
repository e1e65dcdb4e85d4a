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
     *   W  a radiant power in W (per unit of the spectrum): p[SPM_LIGHT_P_SCALE]
     *      = W / solid, the intensity
     *   I  a radiant intensity (W/sr per unit of the spectrum): p[SPM_LIGHT_P_SCALE]
     *   E  an irradiance (W/m^2 per unit of the spectrum): p[SPM_LIGHT_P_SCALE]
     *   A  an angle in degrees in (0, 90]: its cosine into p[SPM_LIGHT_P_A], the
     *      next A's into p[SPM_LIGHT_P_B] */
    const char *args;
    const char *define;    /* the kernel define that compiles it in (NULL: always) */
    double solid;          /* the solid angle (sr) its intensity fills, for its power */
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
#endif
