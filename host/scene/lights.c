/* The light kinds' descriptors (lights.h), from include/spm_lights.h. */
#include "lights.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "colour.h"

/* the scene's bounding sphere: its box's centre and half diagonal (pbrt-v4's
 * Bounds3::BoundingSphere); r = 0 for a scene with no triangles */
void spm_light_bounding_sphere(const spm_scene *sc, double c[3], double *r)
{
    if (sc->have_sphere) { /* its triangles were consumed (geometry.h) */
        for (int k = 0; k < 3; k++)
            c[k] = sc->sphere[k];
        *r = sc->sphere[3];
        return;
    }
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int i = 0; i < sc->ntris; i++)
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++) {
                lo[k] = fmin(lo[k], sc->tris[i].p[v][k]);
                hi[k] = fmax(hi[k], sc->tris[i].p[v][k]);
            }
    double r2 = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = sc->ntris ? 0.5 * (lo[k] + hi[k]) : 0.0;
        r2 += sc->ntris ? 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]) : 0.0;
    }
    *r = sqrt(r2);
}

/* The kinds' own host code, written in their entries (SPM_LIGHT_HOST_CODE):
 * the hooks their descriptors name, which may use the helpers above. */
#define SPM_LIGHT_HOST_CODE
#define SPM_LIGHT_KIND(name, ...)
#include "spm_lights.h"
#undef SPM_LIGHT_KIND
#undef SPM_LIGHT_HOST_CODE

#define SPM_LIGHT_KIND(name, ...) [SPM_LIGHT_##name] = {.tag = SPM_LIGHT_##name, __VA_ARGS__},
const spm_light_desc spm_light_kinds[] = {
#include "spm_lights.h"
};
#undef SPM_LIGHT_KIND
const int spm_nlight_kinds = (int)(sizeof spm_light_kinds / sizeof spm_light_kinds[0]);

const spm_light_desc *spm_light_kind_find(const char *kw)
{
    for (int i = 0; i < spm_nlight_kinds; i++)
        if (spm_light_kinds[i].keyword && !strcmp(spm_light_kinds[i].keyword, kw))
            return &spm_light_kinds[i];
    return NULL;
}

int spm_light_defines(const spm_emitter *em, int n, char *buf, size_t size)
{
    int used[SPM_LIGHT_NKINDS] = {0}, len = 0;
    for (int i = 0; i < n; i++)
        if (em[i].kind < SPM_LIGHT_NKINDS)
            used[em[i].kind] = 1;
    buf[0] = '\0';
    for (int k = 0; k < spm_nlight_kinds; k++)
        if (used[k] && spm_light_kinds[k].define && len < (int)size)
            len += snprintf(buf + len, size - (size_t)len, "-D%s ", spm_light_kinds[k].define);
    return len;
}

double spm_light_power(const spm_scene *sc, const spm_scene_light *l)
{
    double xyz[3];
    spm_xyz_emission(&sc->colours[l->colour].s, xyz);
    double y = xyz[1] > 0.0 ? xyz[1] : 0.0;
    return y * spm_light_kinds[l->kind].power(sc, l->p) / M_PI;
}






void spm_light_place(const spm_scene *sc, const spm_scene_light *l, float p[SPM_LIGHT_PARAMS])
{
    memcpy(p, l->p, SPM_LIGHT_PARAMS * sizeof *p);
    if (spm_light_kinds[l->kind].place)
        spm_light_kinds[l->kind].place(sc, p);
}
