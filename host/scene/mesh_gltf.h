/* What specmip reads from a glTF's JSON itself, where Assimp 5.2 does not
 * hand it on (mesh_gltf.c): materials' KHR_materials_dispersion, cameras. */
#ifndef SPM_MESH_GLTF_H
#define SPM_MESH_GLTF_H
#include "mesh.h"

/* Each material's KHR_materials_dispersion into d's materials (Assimp keeps
 * the file's order); nothing for a file that is not glTF (by its name). */
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
#endif
