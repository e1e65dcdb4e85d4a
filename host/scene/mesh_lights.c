/* A model's lights (a glTF's KHR_lights_punctual, mesh_gltf_lights.c) made
 * scene lights: a point light, a spot of the squared shape, a distant light.
 * Units: an emission's spectrum is lifted at Y = the luminance of its RGB,
 * and Y of radiance reads as cd/m^2, so a light's candela are its intensity
 * I (Y of I x its colour) and lux its irradiance E as given
 * (docs/SCENE_FORMAT.md). */
#include "mesh.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

static double det3(const double m[3][4])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* the scene light of file light f under x' = M x + t; its colour c */
static void place_light(const spm_mesh_light *f, const double m[3][4], int c, spm_scene_light *l)
{
    static const int kinds[] = {[SPM_MESH_LIGHT_POINT] = SPM_LIGHT_POINT,
                                [SPM_MESH_LIGHT_SPOT] = SPM_LIGHT_SPOT,
                                [SPM_MESH_LIGHT_DIRECTIONAL] = SPM_LIGHT_DISTANT};
    memset(l, 0, sizeof *l);
    l->kind = kinds[f->type];
    l->colour = c;
    double d[3], len = 0.0;
    for (int i = 0; i < 3; i++) {
        l->p[SPM_LIGHT_P_POS + i] =
            (float)(m[i][0] * f->pos[0] + m[i][1] * f->pos[1] + m[i][2] * f->pos[2] + m[i][3]);
        d[i] = m[i][0] * f->dir[0] + m[i][1] * f->dir[1] + m[i][2] * f->dir[2];
        len += d[i] * d[i];
    }
    for (int i = 0; i < 3; i++)
        l->p[SPM_LIGHT_P_DIR + i] = (float)(d[i] / sqrt(len));
    /* glTF's cone: full intensity to the inner angle, to 0 at the outer */
    l->p[SPM_LIGHT_P_A] = f->outer;
    l->p[SPM_LIGHT_P_B] = f->inner;
    l->p[SPM_LIGHT_P_C] = (float)cos(f->outer);
    l->p[SPM_LIGHT_P_D] = SPM_SPOT_SQUARED;
    l->p[SPM_LIGHT_P_SCALE] = 1.0f;
}

int spm_mesh_add_lights(spm_scene_builder *b, spm_mesh_cache *cache, const spm_mesh_data *d,
                        const spm_mesh_opts *o, const char *file, const char *where,
                        spm_error *err)
{
    /* the statement's length scale: a model scaled s times keeps its image
     * when its intensities grow by s^2 (irradiance I / d^2) */
    double s = cbrt(fabs(det3(o->m)));
    int made = 0;
    for (uint32_t i = 0; i < d->nlights; i++) {
        const spm_mesh_light *f = &d->lights[i];
        char lwhere[700];
        snprintf(lwhere, sizeof lwhere, "%s: %s: light '%s'", where, file, f->name);
        double rgb[3], k = f->intensity * (f->type == SPM_MESH_LIGHT_DIRECTIONAL ? 1.0 : s * s);
        int ok = isfinite(k) && k >= 0.0 && f->inner >= 0.0f && f->inner < f->outer &&
                 f->outer <= (float)(M_PI / 2.0) && s > 0.0 && isfinite(s);
        for (int c = 0; c < 3; c++) {
            rgb[c] = f->colour[c] * k;
            ok &= isfinite(rgb[c]) && rgb[c] >= 0.0 && isfinite(f->pos[c]) && isfinite(f->dir[c]);
        }
        if (!ok) {
            spm_errorf(err, "%s: its values are not usable (the importer's answer is damaged, "
                            "or the transform is)", lwhere);
            return 1;
        }
        int c = spm_sb_rgb_colour(b, &cache->rgb, rgb, SPM_KIND_EMISSION, lwhere, err);
        if (c < -1)
            return 1;
        if (c == -1)
            continue; /* black: no light */
        spm_scene_light l;
        place_light(f, o->m, c, &l);
        snprintf(l.where, sizeof l.where, "%.127s", where);
        spm_scene *sc = b->s;
        sc->lights = spm_xrealloc(sc->lights, ((size_t)sc->nlights + 1) * sizeof *sc->lights);
        sc->lights[sc->nlights++] = l;
        made++;
    }
    if (made)
        spm_notef("%s: %s: %d light%s (KHR_lights_punctual)", where, file, made,
                  made == 1 ? "" : "s");
    return 0;
}
