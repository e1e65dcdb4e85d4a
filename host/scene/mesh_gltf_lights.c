/* glTF's KHR_lights_punctual, read from the JSON by the importer's child
 * (mesh_import.c), which sends the lights to the parent on its pipe. Assimp
 * 5.2 keeps one aiLight per glTF light, placed by whichever node named it
 * last; here every node of the default scene that names a light places one,
 * at its world transform's origin, shining along its -z (the extension's
 * convention, as a camera's). */
#include "mesh_gltf.h"
#include "json.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const spm_json *lights; /* the extension's `lights`, or NULL */
    spm_mesh_light *out;
    long n, cap;
    int range_set;
    spm_error *err;
} light_walk;

/* `color` (default 1 1 1) and `intensity` (default 1) of light src into l:
 * 0, or 1 with err when not numbers at least 0 */
static int light_values(light_walk *w, const spm_json *src, const char *who, spm_mesh_light *l)
{
    const spm_json *c = spm_json_get(src, "color");
    double rgb[3] = {1, 1, 1}, in = spm_mesh_gltf_num(src, "intensity", 1.0);
    int ok = !c || (c->type == SPM_JSON_ARRAY && c->n == 3);
    for (size_t i = 0; ok && c && i < 3; i++) {
        ok = c->items[i].type == SPM_JSON_NUMBER;
        rgb[i] = ok ? c->items[i].number : 0.0;
    }
    for (int i = 0; i < 3; i++) {
        ok &= rgb[i] >= 0.0 && isfinite(rgb[i]);
        l->colour[i] = (float)rgb[i];
    }
    const spm_json *iv = spm_json_get(src, "intensity");
    if (!ok || (iv && iv->type != SPM_JSON_NUMBER) || !(in >= 0.0 && isfinite(in) && in < 1e30)) {
        spm_errorf(w->err, "%s: `color` must be three numbers and `intensity` a number, none "
                           "negative (color %g %g %g, intensity %g)", who, rgb[0], rgb[1], rgb[2],
                   in);
        return 1;
    }
    l->intensity = (float)in;
    return 0;
}

/* the light src that node `node` places, under world transform m, into l */
static int read_light(light_walk *w, const spm_json *node, size_t k, size_t li,
                      const double m[16], spm_mesh_light *l)
{
    static const char *const types[] = {[SPM_MESH_LIGHT_POINT] = "point",
                                        [SPM_MESH_LIGHT_SPOT] = "spot",
                                        [SPM_MESH_LIGHT_DIRECTIONAL] = "directional"};
    const spm_json *src = &w->lights->items[li];
    memset(l, 0, sizeof *l);
    spm_mesh_gltf_name(src, node, "light", li, l->name, sizeof l->name);
    char who[200];
    snprintf(who, sizeof who, "KHR_lights_punctual light %zu ('%s') of node %zu", li, l->name, k);
    const char *type = spm_json_string(src, "type");
    l->type = -1;
    for (int t = 0; t < 3 && type; t++)
        if (!strcmp(type, types[t]))
            l->type = t;
    if (l->type < 0) {
        spm_errorf(w->err, "%s: type '%.40s' (point, spot or directional)", who,
                   type ? type : "(none)");
        return 1;
    }
    if (light_values(w, src, who, l))
        return 1;
    w->range_set |= spm_json_get(src, "range") != NULL && l->type != SPM_MESH_LIGHT_DIRECTIONAL;
    const spm_json *spot = spm_json_get(src, "spot");
    double inner = spm_mesh_gltf_num(spot, "innerConeAngle", 0.0);
    double outer = spm_mesh_gltf_num(spot, "outerConeAngle", M_PI / 4.0);
    if (l->type == SPM_MESH_LIGHT_SPOT &&
        !(inner >= 0.0 && inner < outer && outer <= M_PI / 2.0 + 1e-6 && outer > 0.0)) {
        spm_errorf(w->err, "%s: cone angles inner %g, outer %g radians: glTF needs 0 <= inner "
                           "< outer <= pi/2", who, inner, outer);
        return 1;
    }
    l->inner = (float)inner;
    l->outer = (float)fmin(outer, M_PI / 2.0);
    double len = 0.0;
    for (int i = 0; i < 3; i++) {
        l->pos[i] = (float)m[12 + i];
        len += m[8 + i] * m[8 + i];
    }
    len = sqrt(len);
    for (int i = 0; i < 3; i++)
        l->dir[i] = (float)(-m[8 + i] / len);
    if (!(len > 1e-12 && isfinite(len)) && l->type != SPM_MESH_LIGHT_POINT) {
        spm_errorf(w->err, "%s: its node's transform leaves it no direction", who);
        return 1;
    }
    if (!(isfinite(l->pos[0]) && isfinite(l->pos[1]) && isfinite(l->pos[2]))) {
        spm_errorf(w->err, "%s: its node's transform is not finite", who);
        return 1;
    }
    return 0;
}

/* a node's light, if it names one: its index must be one of the file's */
static int visit_light(void *ctx, const spm_json *node, size_t k, const double m[16])
{
    light_walk *w = ctx;
    const spm_json *ext = spm_json_get(spm_json_get(node, "extensions"), "KHR_lights_punctual");
    if (!ext)
        return 0;
    const spm_json *li = spm_json_get(ext, "light");
    size_t n = w->lights ? w->lights->n : 0;
    if (!li || li->type != SPM_JSON_NUMBER || !(li->number >= 0) || li->number != floor(li->number) ||
        li->number >= (double)n) {
        const char *name = spm_json_string(node, "name");
        char v[48];
        snprintf(v, sizeof v, li && li->type == SPM_JSON_NUMBER ? "%g" : "(not a number)",
                 li && li->type == SPM_JSON_NUMBER ? li->number : 0.0);
        spm_errorf(w->err, "node %zu ('%.64s'): KHR_lights_punctual light %s is out of range "
                           "(the file defines %zu light%s)", k, name ? name : "", v, n,
                   n == 1 ? "" : "s");
        return 1;
    }
    if (w->n == SPM_MESH_MAX_LIGHTS) {
        spm_errorf(w->err, "more than %d lights placed by nodes", SPM_MESH_MAX_LIGHTS);
        return 1;
    }
    if (w->n == w->cap) {
        w->cap = w->cap ? 2 * w->cap : 8;
        w->out = spm_xrealloc(w->out, (size_t)w->cap * sizeof *w->out);
    }
    if (read_light(w, node, k, (size_t)li->number, m, &w->out[w->n]))
        return 1;
    w->n++;
    return 0;
}

long spm_mesh_gltf_lights(const spm_file *model, spm_mesh_light **out, int *range_set,
                          spm_error *err)
{
    *out = NULL;
    *range_set = 0;
    if (!spm_mesh_gltf_is(model->shown))
        return 0;
    err->msg[0] = '\0';
    spm_json *doc = spm_mesh_gltf_doc(model, err);
    if (!doc)
        return err->msg[0] ? -1 : 0;
    const spm_json *ext = spm_json_get(spm_json_get(doc, "extensions"), "KHR_lights_punctual");
    light_walk w = {spm_json_get(ext, "lights"), NULL, 0, 0, 0, err};
    int rc = 0;
    if (w.lights && w.lights->type != SPM_JSON_ARRAY) {
        spm_errorf(err, "KHR_lights_punctual: `lights` is not an array");
        rc = 1;
    }
    rc = rc || spm_mesh_gltf_walk(doc, visit_light, &w);
    spm_json_free(doc);
    if (rc) {
        free(w.out);
        return -1;
    }
    *out = w.out;
    *range_set = w.range_set;
    return w.n;
}
