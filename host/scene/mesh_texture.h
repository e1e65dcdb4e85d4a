/* A mesh material's base-colour texture (glTF baseColorTexture, an OBJ's
 * map_Kd; a file beside the model or an image embedded in it): an image file
 * on a material that maps to a textured type (Lambertian, coated) textures it per point
 * (times the colour factor); any other is replaced by its mean linear colour,
 * which multiplies the material's colour factor, and a warning says so when
 * the colour is used. */
#ifndef SPM_MESH_TEXTURE_H
#define SPM_MESH_TEXTURE_H
#include <stddef.h>
#include "paths.h"
#ifndef __cplusplus
#include "mesh.h"
#endif
#ifdef __cplusplus
extern "C" {
#endif

/* A texture of more pixels is not read (8192 x 8192: its float pixels,
 * 768 MiB, fit under the importer child's address-space limit beside Assimp). */
#define SPM_TEXTURE_MAX_PIXELS (1LL << 26)

/* The mean linear RGB of the image file `file` (checked by the path rule),
 * or of the size bytes at data (an embedded image; the extension of `hint`
 * says its format). Integer-coded pixels are sRGB-decoded before averaging;
 * one or two channels are grey. Returns 0, or 1 with why filled.
 * (mesh_texture_io.cpp) */
int spm_texture_mean_file(const spm_file *file, float mean[3], char *why, size_t whylen);
int spm_texture_mean_data(const char *hint, const void *data, size_t size, float mean[3],
                          char *why, size_t whylen);

#ifndef __cplusplus
struct aiScene;
struct aiMaterial;
/* In the importer's child: the material's base-colour texture, if it has
 * one, read and its mean multiplied into out->diffuse (out->texture* say
 * what happened). `model` is the file's path (textures are found beside it).
 * Returns 1 if the material has a base-colour texture, 2 with *refused
 * filled when its file is outside where the scene may read (paths.h). */
int spm_mesh_texture_apply(const struct aiScene *sc, const struct aiMaterial *m,
                           const char *model, spm_mesh_material *out, spm_error *refused);
/* In the importer's child: the material's emissive texture (glTF
 * emissiveTexture, MTL map_Ke), if it has one, found and its mean taken
 * (out->etexture* say what happened; out->emission stays the factor).
 * Returns 1 if it has one, 2 with *refused filled as above. */
int spm_mesh_etexture_apply(const struct aiScene *sc, const struct aiMaterial *m,
                            const char *model, spm_mesh_material *out, spm_error *refused);
/* In the importer's child: 1 + the index of the embedded image (an image
 * file's bytes: PNG, JPEG...) that a texture path names ("*N", or an image's
 * file name), else 0. */
int spm_mesh_embedded(const struct aiScene *sc, const char *path);
/* In the parent, when a file material's colour is used: the warning that its
 * texture was replaced by its mean for the reason `why` (or could not be
 * read). `mwhere` names the statement, file and material. */
void spm_mesh_texture_warn(const spm_mesh_material *m, const char *mwhere, const char *why);
/* In the parent: m's base-colour texture (an image file or an image
 * embedded in d; texels times the colour factor) on the scene material `material` it maps to, when its type
 * takes a textured reflectance and the mesh d has texture coordinates: the textured
 * material's index. Else the warning above and `material`. -1 with err. */
int spm_mesh_texture_bind(spm_scene_builder *b, const spm_mesh_data *d,
                          const spm_mesh_material *m, int material, const char *mwhere,
                          spm_error *err);
/* In the parent: m's emissive texture on the scene material `material`: an
 * image (a file or embedded) on a mesh with texture coordinates textures its emission per
 * point (texels times the emissive factor; the material's emission the
 * mean's, for the light pick), else the emission is the factor times the
 * texture's mean, with a warning; unreadable: the factor alone, warned.
 * The material's index, -1 with err. */
int spm_mesh_etexture_bind(spm_scene_builder *b, const spm_mesh_data *d,
                           const spm_mesh_material *m, int material, const char *mwhere,
                           spm_error *err);
#endif
#ifdef __cplusplus
}
#endif
#endif
