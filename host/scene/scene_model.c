/* A model file rendered alone, `specmip render model.glb` (.gltf, .obj,
 * .ply, .stl): the file's triangles and materials as a `mesh` statement
 * would import them, in a scene made around them (docs/SCENE_FORMAT.md,
 * "A model alone"): the file's camera (--camera chooses among several) or
 * one framing the bounding box, a default light, a default material for
 * triangles the file gives none. */
#include "scene_parsers.h"
#include "mesh_gltf.h"
#include "lights.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MODEL_WIDTH 512
#define MODEL_HEIGHT 384
/* the framing: a vertical field of view across the shorter image side, the
 * bounding sphere inside it with a margin, seen from the front right, above
 * (+x right, +y up, +z toward the viewer: glTF's axes) */
#define MODEL_FOV 40.0
#define MODEL_MARGIN 1.08
static const double model_view[3] = {0.55, 0.45, 1.0};
/* the grey of a model whose format has no default material (glTF has one,
 * mesh_build.c) */
static const double model_grey[3] = {0.8, 0.8, 0.8};

/* The camera that frames the box: its bounding sphere (centre c, radius r)
 * fills the shorter side's field of view but for the margin, at distance
 * r / sin(fov / 2). */
static int frame_box(spm_scene_builder *b, const double c[3], double r, const char *where,
                     spm_error *err)
{
    double n = 0.0;
    for (int k = 0; k < 3; k++)
        n += model_view[k] * model_view[k];
    double dist = MODEL_MARGIN * r / sin(0.5 * MODEL_FOV * M_PI / 180.0);
    double eye[3], dir[3];
    for (int k = 0; k < 3; k++) {
        eye[k] = c[k] + dist * model_view[k] / sqrt(n);
        dir[k] = c[k] - eye[k];
    }
    return spm_sb_camera_view(b, eye, dir, NULL, 0, MODEL_FOV, SPM_FOV_SHORTER, where, err);
}

static const char *model_camera; /* --camera NAME|INDEX, or NULL */

int spm_scene_model_camera(const char *name_or_index)
{
    model_camera = name_or_index;
    return 0;
}

int spm_scene_model_camera_unused(const char *path, spm_error *err)
{
    if (!model_camera)
        return 0;
    spm_errorf(err, "%s: --camera %s chooses among a model file's own cameras (.glb, .gltf): "
                    "this is a scene file (--look-from, --look-at and --fov move its camera)",
               path, model_camera);
    return 1;
}

/* The camera --camera names among the file's n: by name first, then as an
 * index from 0; without --camera the first. -1 with err when none matches. */
static int pick_camera(const spm_gltf_camera *c, int n, const char *where, spm_error *err)
{
    if (!model_camera)
        return 0;
    for (int i = 0; i < n; i++)
        if (!strcmp(c[i].name, model_camera))
            return i;
    char *end;
    long k = strtol(model_camera, &end, 10);
    if (*model_camera && !*end && k >= 0 && k < n)
        return (int)k;
    char list[600] = "";
    size_t len = 0;
    for (int i = 0; i < n && len < sizeof list - 100; i++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%d '%s'", i ? ", " : "", i,
                                c[i].name);
    spm_errorf(err, "%s: --camera %s: %s", where, model_camera,
               n ? "no camera of that name or index; the file's cameras are " : "the file has no "
               "camera (a glTF's cameras can be chosen; without one the view frames the model)");
    if (n)
        snprintf(err->msg + strlen(err->msg), sizeof err->msg - strlen(err->msg), "%s", list);
    return -1;
}

/* The file's camera k of n as the scene's: glTF's yfov is vertical; an
 * aspect ratio the camera gives sets the image's height (the width kept). */
static int file_camera(spm_scene_builder *b, const spm_gltf_camera *cams, int n, int k,
                       const char *where, spm_error *err)
{
    const spm_gltf_camera *c = &cams[k];
    spm_scene *s = b->s;
    if (c->aspect > 0) {
        double h = round(s->width / c->aspect);
        s->height = h < 1 ? 1 : h > SPM_SCENE_MAX_SIDE ? SPM_SCENE_MAX_SIDE : (int)h;
    }
    if (spm_sb_camera_view(b, c->eye, c->dir, c->up, 0, c->ortho ? 40.0 : c->yfov,
                           SPM_FOV_VERTICAL, where, err))
        return 1;
    if (c->ortho) {
        s->projection = SPM_PROJ_ORTHOGRAPHIC;
        s->ortho_size = (float)(2.0 * c->ymag);
    }
    spm_notef("%s: the file's camera '%s' (%d of %d%s)", where, c->name, k + 1, n,
              n > 1 ? "; --camera NAME|INDEX chooses another" : "");
    return 0;
}

/* The key light: a square lamp of side 2r at 4r from the centre, up and to
 * the left in front, facing the centre; its radiance 8 pi times the
 * background's gives the centre twice the background's irradiance (pi):
 * E = L A / d^2 = L (2r)^2 / (4r)^2 = L / 4. Out of the framing's view. */
static int key_light(spm_scene_builder *b, spm_names *fits, const double c[3], double r,
                     const char *where, spm_error *err)
{
    const double k0[3] = {-0.6, 1.0, 0.8}, y[3] = {0.0, 1.0, 0.0};
    double rgb[3] = {8.0 * M_PI, 8.0 * M_PI, 8.0 * M_PI}, k[3], u[3], v[3], p[4][3];
    double nk = sqrt(k0[0] * k0[0] + k0[1] * k0[1] + k0[2] * k0[2]);
    for (int i = 0; i < 3; i++)
        k[i] = k0[i] / nk;
    /* u = unit(y x k), v = k x u: with the corners in the order below, the
     * front face (b - a) x (c - a) = v x u points along -k, at the centre */
    u[0] = y[1] * k[2] - y[2] * k[1], u[1] = y[2] * k[0] - y[0] * k[2],
    u[2] = y[0] * k[1] - y[1] * k[0];
    double nu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 0; i < 3; i++)
        u[i] /= nu;
    v[0] = k[1] * u[2] - k[2] * u[1], v[1] = k[2] * u[0] - k[0] * u[2],
    v[2] = k[0] * u[1] - k[1] * u[0];
    const double su[4] = {-1, -1, 1, 1}, sv[4] = {-1, 1, 1, -1};
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 3; i++)
            p[j][i] = c[i] + 4.0 * r * k[i] + r * (su[j] * u[i] + sv[j] * v[i]);
    int e = spm_sb_rgb_colour(b, fits, rgb, SPM_KIND_EMISSION, where, err);
    int m = e < 0 ? -1 : spm_sb_material(b, "key light", -1, e, where, err);
    if (m < 0)
        return 1;
    double t0[3][3], t1[3][3];
    memcpy(t0[0], p[0], sizeof t0[0]), memcpy(t0[1], p[1], sizeof t0[0]);
    memcpy(t0[2], p[2], sizeof t0[0]);
    memcpy(t1[0], p[0], sizeof t1[0]), memcpy(t1[1], p[2], sizeof t1[0]);
    memcpy(t1[2], p[3], sizeof t1[0]);
    return spm_sb_tri(b, t0, m, 1, where, err) || spm_sb_tri(b, t1, m, 1, where, err);
}

/* The default light: a uniform white background, the same radiance from
 * every direction (RGB 1 1 1 lifted as an emission), and the key light; said
 * in a note. */
static int default_light(spm_scene_builder *b, spm_names *fits, const double c[3], double r,
                         int framed, const char *where, spm_error *err)
{
    const double white[3] = {1.0, 1.0, 1.0};
    int bg = spm_sb_rgb_colour(b, fits, white, SPM_KIND_EMISSION, where, err);
    if (bg < 0 || key_light(b, fits, c, r, where, err))
        return 1;
    b->s->bg_up = b->s->bg_down = bg;
    if (!spm_quiet_warnings)
        fprintf(stderr, "specmip: %s: a model alone: lit by the default light, a uniform white "
                        "background (RGB 1 1 1 from every direction) and a square key light "
                        "above left, beside any light the model emits%s (docs/SCENE_FORMAT.md, "
                        "\"A model alone\")\n", where,
                framed ? "; the camera frames its bounding box" : "");
    return 0;
}

int spm_scene_parse_model(const spm_file *file, spm_scene *out, spm_error *err)
{
    const char *where = file->shown;
    spm_scene_builder b;
    spm_mesh_cache cache;
    spm_mesh_cache_init(&cache);
    spm_sb_init(&b, out, where);
    out->width = MODEL_WIDTH;
    out->height = MODEL_HEIGHT;
    spm_mesh_opts o = {.material = -1, .line = 1};
    spm_mesh_identity(o.m);
    int grey = spm_sb_rgb_colour(&b, &cache.rgb, model_grey, SPM_KIND_REFLECTANCE, where, err);
    int rc = grey < 0;
    if (!rc)
        rc = (o.fallback = 1 + spm_sb_material(&b, "default", grey, -1, where, err)) < 1;
    static spm_gltf_camera cams[SPM_GLTF_MAX_CAMERAS];
    int ncams = rc ? 0 : spm_mesh_gltf_cameras(file, cams, err), pick = 0;
    rc = rc || ncams < 0 || (pick = pick_camera(cams, ncams, where, err)) < 0;
    spm_mesh_data d;
    if (!rc && !(rc = spm_mesh_import(file, &d, err))) {
        spm_mesh_obj_mtl_check(file, where, &d);
        if (ncams)
            d.ignored &= ~(uint32_t)SPM_MESH_IGN_CAMERAS;
        rc = spm_mesh_add(&b, &cache, &d, &o, file->shown, where, err);
        spm_mesh_free(&d);
    }
    double c[3], r = 0.0;
    if (!rc && out->ntris > 0)
        spm_light_bounding_sphere(out, c, &r);
    if (!rc && out->ntris < 1) {
        spm_errorf(err, "%s: the model has no triangle to render", where);
        rc = 1;
    }
    rc = rc || (ncams ? file_camera(&b, cams, ncams, pick, where, err)
                      : frame_box(&b, c, r, where, err)) ||
         default_light(&b, &cache.rgb, c, r, !ncams, where, err) ||
         (out->ntextures && /* a textured mesh's colours: of what is left, before derived ones */
          (spm_sb_prune(&b, where, err) || spm_sb_texture_palette(&b, where, err))) ||
         spm_sb_finish(&b, where, err);
    spm_mesh_cache_free(&cache);
    spm_sb_done(&b, !rc);
    return rc;
}
