#include "render_hints.h"
#include <stdlib.h>
#include "geometry_vec3.h"
#include "materials.h"

/* Emitter triangle e lights nothing and is seen by no camera ray, as far as
 * one ray tells: the eye is behind (or in) its plane, (eye - v0) . n <= 0, and
 * the ray centroid + t n, t > 0, hits nothing. The centroid lies on the
 * triangle itself (skipped) and a ray along n never hits a coplanar
 * neighbour, so no offset, and nothing here depends on the scene's unit. */
static int emitter_idle(const spm_geometry *g, const spm_tri *t, spm_u32 e)
{
    float rel[3];
    v3_sub(rel, g->cam.eye, t->v0);
    if (v3_dot(rel, t->n) > 0.0f)
        return 0;
    float c[3], tmax;
    for (int i = 0; i < 3; i++)
        c[i] = (t->v0[i] + t->v1[i] + t->v2[i]) / 3.0f;
    return spm_bvh_intersect(g, c, t->n, e, &tmax) < 0;
}

int spm_render_hint_emitters(const spm_scene *sc, const spm_geometry *g)
{
    /* per material: its emitting triangles, and how many of them are idle */
    int *count = spm_xcalloc((size_t)sc->nmaterials * 2 + 1, sizeof *count);
    for (int k = 0; k < g->nemitters; k++) {
        if (g->emitters[k].kind != SPM_LIGHT_AREA)
            continue; /* a light of the `light` statement has no face */
        spm_u32 e = g->emitters[k].tri;
        const spm_tri *t = &g->tris[e];
        int m = (int)t->material;
        if (m < 0 || m >= sc->nmaterials || spm_material_faces(&sc->materials[m]) != 1)
            continue; /* a twosided light is checked by neither face */
        count[2 * m]++;
        count[2 * m + 1] += emitter_idle(g, t, e);
    }
    int warned = 0;
    for (int m = 0; m < sc->nmaterials; m++)
        if (count[2 * m] && count[2 * m + 1] == count[2 * m]) {
            spm_warnf("emitter material '%s' lights nothing the camera can see: none of its %d "
                      "triangles has the camera or any geometry in front of it (a ray along "
                      "each one's normal from its centre hits nothing); is the light facing "
                      "away? (its front is (b - a) x (c - a); 'emit ... twosided' lights both "
                      "faces)", sc->materials[m].name, count[2 * m]);
            warned++;
        }
    free(count);
    return warned;
}

int spm_render_hint_black(const spm_film *f)
{
    size_t n = 3 * (size_t)f->width * (size_t)f->height;
    for (size_t i = 0; i < n; i++)
        if (f->sum[i] != 0.0)
            return 0;
    spm_warnf("the image is black (every pixel zero): no light reaches the camera; are the "
              "lights facing away, or the camera inside a closed mesh?");
    return 1;
}
