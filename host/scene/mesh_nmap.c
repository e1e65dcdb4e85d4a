/* A mesh material's normal map (mesh.h spm_mesh_nmap_read, spm_mesh_nmap_bind):
 * glTF's normalTexture with its scale, OBJ's norm, and bump / map_Bump when
 * its image has colour (Blender writes its normal maps so; a grey image is a
 * height map, which is not rendered: warned about). Found through Assimp in
 * the importer's child, bound in the parent as the scene format's 'normal'
 * clause binds a texture (scene.h spm_scene_material nmap; spm_shared.h
 * SPM_NMAP_*). */
#include "mesh.h"
#include "texture.h"
#include <assimp/GltfMaterial.h>
#include <assimp/ObjMaterial.h>
#include <assimp/material.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int spm_mesh_nmap_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                       spm_error *refused)
{
    enum aiTextureType type = aiTextureType_NORMALS;
    out->nmap_scale = 1.0f;
    if (aiGetMaterialTextureCount(m, type) == 0) {
        type = aiTextureType_HEIGHT;
        if (out->format != SPM_MESH_FMT_OBJ || aiGetMaterialTextureCount(m, type) == 0)
            return 0;
    }
    struct aiString path;
    if (aiGetMaterialTexture(m, type, 0, &path, NULL, NULL, NULL, NULL, NULL, NULL) !=
        aiReturn_SUCCESS)
        return 0;
    if (out->format == SPM_MESH_FMT_GLTF)
        aiGetMaterialFloatArray(m, AI_MATKEY_GLTF_TEXTURE_SCALE(type, 0), &out->nmap_scale, NULL);
    else
        aiGetMaterialFloatArray(m, AI_MATKEY_OBJ_BUMPMULT(type, 0), &out->nmap_scale, NULL);
    snprintf(out->nmap_name, sizeof out->nmap_name, "%.95s", path.data);
    out->nmap = type == aiTextureType_NORMALS ? SPM_MESH_NMAP_NORMAL : SPM_MESH_NMAP_BUMP;
    if (path.data[0] == '*') /* an embedded image: nmap_file stays empty */
        return 0;
    spm_file file;
    if (spm_mesh_image_check(path.data, model, &file, refused))
        return 2;
    snprintf(out->nmap_file, sizeof out->nmap_file, "%s", file.path);
    return 0;
}

/* the image's texels into the scene: 1 + its index, 0 when a bump map's
 * image is grey (a height map), -1 with why filled */
static int bind_map(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                    const char *mwhere, char *why, size_t whylen)
{
    spm_file f;
    spm_image_src src;
    float *rgb;
    int w, h;
    if (spm_mesh_map_image(d, m->nmap_embed, m->nmap_file, mwhere, &f, &src, why, whylen) ||
        spm_texture_read(&src, SPM_IMAGE_DATA, &rgb, &w, &h, why, whylen))
        return -1;
    int grey = m->nmap == SPM_MESH_NMAP_BUMP;
    for (size_t i = 0; grey && i < (size_t)w * h; i++)
        grey = rgb[3 * i] == rgb[3 * i + 1] && rgb[3 * i + 1] == rgb[3 * i + 2];
    int k = grey ? 0 : 1 + spm_sb_nmap_pixels(b, rgb, w, h, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT);
    free(rgb);
    return k;
}

int spm_mesh_nmap_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                       int material, const char *mwhere, spm_error *err)
{
    if (m->nmap == SPM_MESH_NMAP_NONE)
        return material;
    char why[300] = "the mesh has no texture coordinates";
    int k = d->uvs ? bind_map(b, d, m, mwhere, why, sizeof why) : -1;
    if (k == 0)
        spm_warnf("%s: bump map '%s' is a grey height map: not rendered (only normal maps are)",
                  mwhere, m->nmap_name);
    if (k < 0)
        spm_warnf("%s: normal map '%s' not applied (%s)", mwhere, m->nmap_name, why);
    if (k <= 0)
        return material;
    b->s->nmaps[k - 1].uvx = m->uvx[SPM_MESH_MAP_NORMAL];
    spm_scene_material proto = b->s->materials[material];
    proto.nmap = k;
    proto.nmap_scale = isfinite(m->nmap_scale) ? m->nmap_scale : 1.0f;
    return spm_sb_material_typed(b, &proto, mwhere, err);
}
