/* What specmip reads from a glTF's JSON itself, where Assimp 5.2 does not
 * hand it on (mesh_gltf.c): materials' KHR_materials_dispersion and
 * _emissive_strength, cameras. */
#ifndef SPM_MESH_GLTF_H
#define SPM_MESH_GLTF_H
#include "mesh.h"

/* Each material's KHR_materials_dispersion into d's materials (Assimp keeps
 * the file's order), and its KHR_materials_emissive_strength multiplied
 * into its emission (one that is not a non-negative number is ignored:
 * d->ignored); nothing for a file that is not glTF (by its name). */
void spm_mesh_gltf_materials(const spm_file *model, spm_mesh_data *d);

/* A camera of the file's default scene, placed by its node's transform
 * (composed with its parents'): glTF's camera looks along its node's -z with
 * +y up. */
typedef struct {
    char name[64];             /* the camera's name, else its node's, else "camera N" */
    double eye[3], dir[3], up[3];
    int ortho;                 /* 1: orthographic (xmag, ymag), 0: perspective (yfov) */
    double yfov;               /* the vertical field of view, in degrees */
    double aspect;             /* width / height: aspectRatio, or xmag / ymag; 0: none */
    double ymag;               /* orthographic: half the view's height */
} spm_gltf_camera;
#define SPM_GLTF_MAX_CAMERAS 64

/* The cameras of a glTF's default scene in the order of a depth-first walk
 * of its nodes (at most SPM_GLTF_MAX_CAMERAS); their number, 0 for a file
 * that is not glTF or has none, -1 with err when the file cannot be read or
 * a camera's values are not usable (yfov not in (0, pi), a zero magnification,
 * a node transform without a direction). */
int spm_mesh_gltf_cameras(const spm_file *model, spm_gltf_camera *out, spm_error *err);

struct spm_json;
/* 1 when the name ends in .gltf or .glb (any case) */
int spm_mesh_gltf_is(const char *name);
/* obj's `name`, else its node's, else "WHAT I", into out[size] */
void spm_mesh_gltf_name(const struct spm_json *obj, const struct spm_json *node, const char *what,
                        size_t i, char *out, size_t size);
/* a member's number, or def when absent or not a number */
double spm_mesh_gltf_num(const struct spm_json *v, const char *key, double def);
/* Called for each node of the default scene, parents first (depth-first, in
 * the order of `children`), with its index k and its world transform m
 * (column-major 4x4, its parents' composed with its own); not 0 ends the
 * walk with that value. */
typedef int (*spm_gltf_visit)(void *ctx, const struct spm_json *node, size_t k,
                              const double m[16]);
/* The walk of doc's default scene (`scene`, else scenes[0]); at most
 * SPM_MESH_MAX_DEPTH levels and 2^20 visits. Returns what ended it, else 0. */
int spm_mesh_gltf_walk(const struct spm_json *doc, spm_gltf_visit visit, void *ctx);

/* A material's KHR_texture_transform on each map it renders (base colour,
 * emissive, metallic-roughness, normal) into out->uvx (mesh_gltf_uvx.c); a
 * map read from another texture coordinate set than TEXCOORD_0, or whose
 * transform holds something other than numbers, sets
 * SPM_MESH_IGN_TEX_TRANSFORM in *ignored (that map untransformed). */
void spm_mesh_gltf_uvx(const struct spm_json *mat, spm_mesh_material *out, uint32_t *ignored);

/* The KHR_lights_punctual lights its default scene's nodes place (a light
 * that two nodes name is two lights), into *out (malloc'd, NULL for none);
 * *range_set when one gives a `range` (not rendered). Their number, 0 for a
 * file that is not glTF, -1 with err naming the node or light: an index out
 * of range, an unknown type, a colour or intensity that is negative or not
 * a number, cone angles outside 0 <= inner < outer <= pi/2, a transform
 * without a direction. mesh_gltf_lights.c */
long spm_mesh_gltf_lights(const spm_file *model, spm_mesh_light **out, int *range_set,
                          spm_error *err);
#endif
