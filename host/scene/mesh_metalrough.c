/* glTF's metallicRoughnessTexture (mesh.h spm_mesh_mix_read, spm_mesh_mix_bind):
 * its name and path read through Assimp in the importer's child, its blue
 * (metallic) and green (roughness) channels bound in the parent to the mix
 * record mesh_pbr.c gave the material (scene.h mix_*; spm_shared.h
 * SPM_MIX_*), as one-byte maps beside the opacity's. */
#include "mesh.h"
#include "texture.h"
#include <assimp/material.h>
#include <stdio.h>
#include <stdlib.h>

int spm_mesh_mix_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                      spm_error *refused)
{
    /* Assimp 5.2 gives glTF's texture as UNKNOWN; later versions as both of these too */
    static const enum aiTextureType types[] = {aiTextureType_UNKNOWN, aiTextureType_METALNESS,
                                               aiTextureType_DIFFUSE_ROUGHNESS};
    struct aiString path;
    int found = 0;
    if (out->format != SPM_MESH_FMT_GLTF)
        return 0;
    for (size_t i = 0; i < sizeof types / sizeof *types && !found; i++)
        found = aiGetMaterialTextureCount(m, types[i]) > 0 &&
                aiGetMaterialTexture(m, types[i], 0, &path, NULL, NULL, NULL, NULL, NULL,
                                     NULL) == aiReturn_SUCCESS;
    if (!found)
        return 0;
    snprintf(out->mr_name, sizeof out->mr_name, "%.95s", path.data);
    if (path.data[0] == '*') { /* an image inside the file (GLB, data URI) */
        out->mr_map = SPM_MESH_MRMAP_EMBEDDED;
        return 0;
    }
    spm_file file;
    if (spm_mesh_image_check(path.data, model, &file, refused))
        return 2;
    out->mr_map = SPM_MESH_MRMAP_FILE;
    snprintf(out->mr_file, sizeof out->mr_file, "%s", file.path);
    return 0;
}

/* channel c of the map as a one-byte map: 1 + its index, or -1 with why */
static int bind_channel(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                        int c, const char *mwhere, char *why, size_t whylen)
{
    spm_file f;
    spm_image_src src;
    float *a = NULL;
    int w, h;
    if (spm_mesh_map_image(d, m->mr_embed, m->mr_file, mwhere, &f, &src, why, whylen) ||
        spm_texture_read_one(&src, -1 - c, &a, &w, &h, why, whylen))
        return -1;
    int i = spm_sb_alpha_pixels(b, a, w, h, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT);
    free(a);
    return 1 + i;
}

int spm_mesh_mix_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                      int material, const char *mwhere, spm_error *err)
{
    spm_scene_material proto = b->s->materials[material];
    if (!proto.mix_metal || m->mr_map == SPM_MESH_MRMAP_NONE)
        return material;
    char why[300] = "";
    int mm = -1, rm = -1;
    if (!d->uvs)
        snprintf(why, sizeof why, "the mesh has no texture coordinates");
    else if ((mm = bind_channel(b, d, m, 2, mwhere, why, sizeof why)) > 0)
        rm = bind_channel(b, d, m, 1, mwhere, why, sizeof why);
    if (rm < 0) {
        spm_warnf("%s: metallic-roughness map '%s' not applied (%s): metallic %g and "
                  "roughness %g throughout",
                  mwhere, m->mr_name, why, proto.mix_metallic, proto.mix_rough);
        return material;
    }
    proto.mix_mmap = mm;
    proto.mix_rmap = rm;
    b->s->alphas[mm - 1].uvx = b->s->alphas[rm - 1].uvx = m->uvx[SPM_MESH_MAP_MR];
    return spm_sb_material_typed(b, &proto, mwhere, err);
}
