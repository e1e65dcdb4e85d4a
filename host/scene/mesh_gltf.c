/* What specmip reads from a glTF's JSON itself, where Assimp 5.2 does not
 * hand it on: KHR_materials_dispersion and _emissive_strength, and the cameras (Assimp's aiCamera
 * gives a horizontal field of view scaled linearly from yfov); the walk of
 * the default scene's nodes that places cameras and lights
 * (mesh_gltf_lights.c). */
#include "mesh_gltf.h"
#include "json.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

static int is_gltf(const char *name)
{
    size_t n = strlen(name);
    return (n > 4 && !strcasecmp(name + n - 4, ".glb")) ||
           (n > 5 && !strcasecmp(name + n - 5, ".gltf"));
}

void spm_mesh_gltf_materials(const spm_file *model, spm_mesh_data *d)
{
    if (!is_gltf(model->shown))
        return;
    spm_error err;
    spm_json *doc = spm_mesh_gltf_doc(model, &err);
    const spm_json *mats = doc ? spm_json_get(doc, "materials") : NULL;
    if (doc) /* Assimp's flag, replaced by what the JSON says (mesh_gltf_uvx.c) */
        d->ignored &= ~(uint32_t)SPM_MESH_IGN_TEX_TRANSFORM;
    for (size_t i = 0; mats && mats->type == SPM_JSON_ARRAY && i < mats->n && i < d->nmats; i++) {
        const spm_json *ext = spm_json_get(&mats->items[i], "extensions");
        const spm_json *disp = spm_json_get(spm_json_get(ext, "KHR_materials_dispersion"),
                                            "dispersion");
        if (disp && disp->type == SPM_JSON_NUMBER && isfinite(disp->number)) {
            d->mats[i].dispersion = (float)disp->number;
            d->mats[i].has |= SPM_MESH_HAS_DISPERSION;
        }
        spm_mesh_gltf_uvx(&mats->items[i], &d->mats[i], &d->ignored);
        /* emission = emissiveTexture x emissiveFactor x emissiveStrength */
        const spm_json *es = spm_json_get(spm_json_get(ext, "KHR_materials_emissive_strength"),
                                          "emissiveStrength");
        if (es && !(es->type == SPM_JSON_NUMBER && isfinite(es->number) && es->number >= 0.0))
            d->ignored |= SPM_MESH_IGN_EMISSIVE_STRENGTH;
        else if (es)
            for (int c = 0; c < 3; c++)
                d->mats[i].emission[c] = (float)(d->mats[i].emission[c] * es->number);
    }
    spm_json_free(doc);
}

/* a member's number, or def when absent or not a number */
double spm_mesh_gltf_num(const spm_json *v, const char *key, double def)
{
    const spm_json *m = spm_json_get(v, key);
    return m && m->type == SPM_JSON_NUMBER ? m->number : def;
}

/* a member's array of n numbers into out; 0 when absent (out untouched) */
static int nums(const spm_json *v, const char *key, double *out, size_t n)
{
    const spm_json *a = spm_json_get(v, key);
    if (!a || a->type != SPM_JSON_ARRAY || a->n != n)
        return 0;
    for (size_t i = 0; i < n; i++)
        if (a->items[i].type == SPM_JSON_NUMBER)
            out[i] = a->items[i].number;
    return 1;
}

/* A node's local transform, column-major 4x4 as glTF writes `matrix`: the
 * matrix, or T R S from translation, rotation (a unit quaternion x y z w)
 * and scale. */
static void local_matrix(const spm_json *node, double m[16])
{
    static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    memcpy(m, id, sizeof id);
    if (nums(node, "matrix", m, 16))
        return;
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    nums(node, "translation", t, 3);
    nums(node, "rotation", q, 4);
    nums(node, "scale", s, 3);
    double x = q[0], y = q[1], z = q[2], w = q[3];
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < 3; i++)
            m[4 * c + i] = r[i][c] * s[c];
    for (int i = 0; i < 3; i++)
        m[12 + i] = t[i];
}

void spm_mesh_gltf_name(const spm_json *obj, const spm_json *node, const char *what, size_t i,
                        char *out, size_t size)
{
    const char *name = spm_json_string(obj, "name");
    if (!name || !name[0])
        name = spm_json_string(node, "name");
    if (name && name[0])
        snprintf(out, size, "%s", name);
    else
        snprintf(out, size, "%s %zu", what, i);
}

typedef struct {
    const spm_json *doc, *nodes, *cams;
    spm_gltf_camera *out;
    int n;
    spm_error *err;
    const char *file;
} cam_walk;

/* the camera of node `node` under world transform m, into w->out */
static int add_camera(cam_walk *w, const spm_json *node, size_t ci, const double m[16])
{
    const spm_json *cam = &w->cams->items[ci];
    spm_gltf_camera *c = &w->out[w->n];
    memset(c, 0, sizeof *c);
    spm_mesh_gltf_name(cam, node, "camera", (size_t)w->n, c->name, sizeof c->name);
    const char *type = spm_json_string(cam, "type");
    c->ortho = type && !strcmp(type, "orthographic");
    const spm_json *p = spm_json_get(cam, c->ortho ? "orthographic" : "perspective");
    double len_d = 0, len_u = 0;
    for (int i = 0; i < 3; i++) {
        c->eye[i] = m[12 + i];
        c->dir[i] = -m[8 + i];
        c->up[i] = m[4 + i];
        len_d += c->dir[i] * c->dir[i];
        len_u += c->up[i] * c->up[i];
    }
    if (c->ortho) {
        double xmag = spm_mesh_gltf_num(p, "xmag", 0), ymag = spm_mesh_gltf_num(p, "ymag", 0);
        c->ymag = fabs(ymag);
        c->aspect = ymag != 0 ? fabs(xmag / ymag) : 0;
        if (!(c->ymag > 0 && isfinite(c->ymag) && c->aspect > 0 && isfinite(c->aspect))) {
            spm_errorf(w->err, "%s: camera '%s': orthographic xmag %g, ymag %g: both must be "
                               "non-zero", w->file, c->name, xmag, ymag);
            return 1;
        }
    } else {
        double yfov = spm_mesh_gltf_num(p, "yfov", -1);
        c->yfov = yfov * (180.0 / M_PI);
        c->aspect = spm_mesh_gltf_num(p, "aspectRatio", 0);
        if (!(yfov > 0 && yfov < M_PI) || !(c->aspect >= 0) || !isfinite(c->aspect)) {
            spm_errorf(w->err, "%s: camera '%s': yfov %g radians (must lie in (0, pi)), "
                               "aspectRatio %g", w->file, c->name, yfov, c->aspect);
            return 1;
        }
    }
    if (!(len_d > 1e-24 && len_u > 1e-24 && isfinite(len_d + len_u))) {
        spm_errorf(w->err, "%s: camera '%s': its node's transform leaves it no direction",
                   w->file, c->name);
        return 1;
    }
    w->n++;
    return 0;
}

typedef struct {
    const spm_json *nodes;
    spm_gltf_visit visit;
    void *ctx;
    long visits;
} node_walk;

static int walk_node(node_walk *w, size_t k, const double parent[16], int depth)
{
    if (k >= w->nodes->n || depth > SPM_MESH_MAX_DEPTH || ++w->visits > (1L << 20))
        return 0;
    const spm_json *node = &w->nodes->items[k];
    double l[16], m[16];
    local_matrix(node, l);
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < 4; i++)
            m[4 * c + i] = parent[i] * l[4 * c] + parent[4 + i] * l[4 * c + 1] +
                           parent[8 + i] * l[4 * c + 2] + parent[12 + i] * l[4 * c + 3];
    int rc = w->visit(w->ctx, node, k, m);
    if (rc)
        return rc;
    const spm_json *kids = spm_json_get(node, "children");
    for (size_t i = 0; kids && kids->type == SPM_JSON_ARRAY && i < kids->n; i++)
        if (kids->items[i].type == SPM_JSON_NUMBER && kids->items[i].number >= 0 &&
            kids->items[i].number < (double)w->nodes->n &&
            (rc = walk_node(w, (size_t)kids->items[i].number, m, depth + 1)))
            return rc;
    return 0;
}

int spm_mesh_gltf_walk(const spm_json *doc, spm_gltf_visit visit, void *ctx)
{
    node_walk w = {spm_json_get(doc, "nodes"), visit, ctx, 0};
    const spm_json *scenes = spm_json_get(doc, "scenes");
    double si = spm_mesh_gltf_num(doc, "scene", 0);
    const spm_json *roots = scenes && scenes->type == SPM_JSON_ARRAY && si >= 0 &&
                                    si < (double)scenes->n
                                ? spm_json_get(&scenes->items[(size_t)si], "nodes")
                                : NULL;
    static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int rc = 0;
    for (size_t i = 0; !rc && w.nodes && w.nodes->type == SPM_JSON_ARRAY && roots &&
                       roots->type == SPM_JSON_ARRAY && i < roots->n; i++)
        if (roots->items[i].type == SPM_JSON_NUMBER && roots->items[i].number >= 0 &&
            roots->items[i].number < (double)w.nodes->n)
            rc = walk_node(&w, (size_t)roots->items[i].number, id, 0);
    return rc;
}

/* a node's camera, if it has one (at most SPM_GLTF_MAX_CAMERAS) */
static int visit_camera(void *ctx, const spm_json *node, size_t k, const double m[16])
{
    (void)k;
    cam_walk *w = ctx;
    double ci = spm_mesh_gltf_num(node, "camera", -1);
    if (w->n < SPM_GLTF_MAX_CAMERAS && ci >= 0 && w->cams && ci < (double)w->cams->n &&
        add_camera(w, node, (size_t)ci, m))
        return 1;
    return 0;
}

int spm_mesh_gltf_is(const char *name)
{
    return is_gltf(name);
}

int spm_mesh_gltf_cameras(const spm_file *model, spm_gltf_camera *out, spm_error *err)
{
    if (!is_gltf(model->shown))
        return 0;
    err->msg[0] = '\0';
    spm_json *doc = spm_mesh_gltf_doc(model, err);
    if (!doc)
        return err->msg[0] ? -1 : 0;
    cam_walk w = {doc, spm_json_get(doc, "nodes"), spm_json_get(doc, "cameras"), out, 0, err,
                  model->shown};
    if (w.cams && w.cams->type != SPM_JSON_ARRAY)
        w.cams = NULL;
    int rc = spm_mesh_gltf_walk(doc, visit_camera, &w);
    spm_json_free(doc);
    return rc ? -1 : w.n;
}
