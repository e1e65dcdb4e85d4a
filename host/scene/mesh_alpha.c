/* A mesh material's opacity (mesh.h spm_mesh_alpha_read, spm_mesh_alpha_bind):
 * read through Assimp in the importer's child, its map bound in the parent
 * as the scene format's 'opacity' clause binds a texture's (scene.h
 * spm_scene_material alpha_*; spm_shared.h SPM_ALPHA_*). */
#include "mesh.h"
#include "texture.h"
#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* glTF: alphaMode, alphaCutoff (default 0.5) and baseColorFactor's alpha
 * (default 1); the base colour image's alpha channel when it is a file. */
static void gltf_alpha(const struct aiMaterial *m, spm_mesh_material *out)
{
    struct aiString mode;
    if (aiGetMaterialString(m, AI_MATKEY_GLTF_ALPHAMODE, &mode) != aiReturn_SUCCESS)
        return;
    out->alpha_mode = !strcmp(mode.data, "MASK")    ? SPM_MESH_ALPHA_MASK
                      : !strcmp(mode.data, "BLEND") ? SPM_MESH_ALPHA_BLEND
                                                    : SPM_MESH_ALPHA_OPAQUE;
    if (!out->alpha_mode)
        return;
    out->alpha_cutoff = 0.5f;
    aiGetMaterialFloatArray(m, AI_MATKEY_GLTF_ALPHACUTOFF, &out->alpha_cutoff, NULL);
    struct aiColor4D base;
    if (aiGetMaterialColor(m, AI_MATKEY_BASE_COLOR, &base) == aiReturn_SUCCESS)
        out->alpha_factor = base.a;
    if (out->texture != SPM_MESH_TEX_NONE) {
        out->alpha_map = SPM_MESH_AMAP_BASE;
        snprintf(out->alpha_name, sizeof out->alpha_name, "%s", out->texture_name);
    }
}

int spm_mesh_image_check(const char *ref, const char *model, spm_file *file, spm_error *refused)
{
    char rel[1024], dir[SPM_PATH_MAX], where[SPM_PATH_MAX + 32];
    snprintf(rel, sizeof rel, "%s", ref);
    for (char *c = rel; *c; c++) /* Windows separators as '/' */
        if (*c == '\\')
            *c = '/';
    snprintf(where, sizeof where, "%s: image", model);
    return spm_path_check(spm_path_dir(model, dir, sizeof dir), rel, where, file, refused);
}

/* Any other format: its opacity (OBJ d, 1 - Tr) and opacity map (OBJ map_d,
 * a file beside the model) as stochastic opacity. 2 when the map is refused. */
static int other_alpha(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                       spm_error *refused)
{
    struct aiString path;
    int has_map = aiGetMaterialTextureCount(m, aiTextureType_OPACITY) > 0 &&
                  aiGetMaterialTexture(m, aiTextureType_OPACITY, 0, &path, NULL, NULL, NULL, NULL,
                                       NULL, NULL) == aiReturn_SUCCESS;
    if (out->has & SPM_MESH_HAS_OPACITY && out->opacity < 1)
        out->alpha_factor = out->opacity > 0 ? out->opacity : 0;
    else if (!has_map)
        return 0;
    out->alpha_mode = SPM_MESH_ALPHA_BLEND;
    if (!has_map)
        return 0;
    snprintf(out->alpha_name, sizeof out->alpha_name, "%.95s", path.data);
    spm_file file;
    if (spm_mesh_image_check(path.data, model, &file, refused))
        return 2;
    out->alpha_map = SPM_MESH_AMAP_FILE;
    snprintf(out->alpha_file, sizeof out->alpha_file, "%s", file.path);
    return 0;
}

int spm_mesh_alpha_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                        spm_error *refused)
{
    out->alpha_factor = 1.0f;
    if (out->format == SPM_MESH_FMT_GLTF) {
        gltf_alpha(m, out);
        return 0;
    }
    return other_alpha(m, model, out, refused) ? 2 : 0;
}

/* The map's values into the scene: 1 + its index, 0 when the image has no
 * alpha channel (a base colour image: opaque), -1 with why filled. */
static int bind_map(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                    const char *mwhere, char *why, size_t whylen)
{
    int base = m->alpha_map == SPM_MESH_AMAP_BASE;
    spm_file f;
    spm_image_src src;
    float *a = NULL;
    int w, h;
    if (spm_mesh_map_image(d, base ? m->texture_embed : 0, base ? m->texture_file : m->alpha_file,
                           mwhere, &f, &src, why, whylen) ||
        spm_texture_read_one(&src, base, &a, &w, &h, why, whylen))
        return -1;
    if (!a)
        return 0;
    int i = spm_sb_alpha_pixels(b, a, w, h, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT);
    free(a);
    return 1 + i;
}

int spm_mesh_alpha_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                        int material, const char *mwhere, spm_error *err)
{
    if (!m->alpha_mode || !(m->alpha_factor >= 0.0f && m->alpha_factor <= 1.0f) ||
        !(m->alpha_cutoff >= 0.0f && m->alpha_cutoff <= 1.0f))
        return material;
    spm_scene_material proto = b->s->materials[material];
    proto.alpha_mode = m->alpha_mode == SPM_MESH_ALPHA_MASK ? (int)SPM_ALPHA_MASK
                                                            : (int)SPM_ALPHA_BLEND;
    proto.alpha_cutoff = m->alpha_mode == SPM_MESH_ALPHA_MASK ? m->alpha_cutoff : 0.0f;
    proto.alpha_factor = m->alpha_factor;
    char why[300] = "";
    if (m->alpha_map != SPM_MESH_AMAP_NONE) {
        int a = d->uvs ? bind_map(b, d, m, mwhere, why, sizeof why) : -1;
        if (a > 0 && m->alpha_map == SPM_MESH_AMAP_BASE) /* the base colour image's binding */
            b->s->alphas[a - 1].uvx = m->uvx[SPM_MESH_MAP_BASE];
        if (!d->uvs)
            snprintf(why, sizeof why, "the mesh has no texture coordinates");
        if (a < 0)
            spm_warnf("%s: opacity map '%s' not applied (%s): the opacity is %g throughout",
                      mwhere, m->alpha_name, why, m->alpha_factor);
        proto.alpha_map = a > 0 ? a : 0;
    }
    if (!proto.alpha_map && proto.alpha_mode == (int)SPM_ALPHA_MASK &&
        proto.alpha_factor >= proto.alpha_cutoff)
        return material; /* a cut-out that keeps everything */
    return spm_sb_material_typed(b, &proto, mwhere, err);
}
