/* glTF's metallicRoughnessTexture and MTL's map_Ns (mesh.h spm_mesh_mix_read,
 * spm_mesh_mix_bind): the map's name and path read through Assimp in the
 * importer's child; in the parent a glTF map's blue (metallic) and green
 * (roughness) channels bound to the mix record mesh_pbr.c gave the material,
 * an MTL exponent map converted to roughness per texel and bound to a mix
 * record of metallic 1 naming the material itself (scene.h mix_*;
 * spm_shared.h SPM_MIX_*), as one-byte maps beside the opacity's. */
#include "mesh.h"
#include "materials.h"
#include "texture.h"
#include <assimp/material.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* MTL's exponents run from 0 to 1000: a map without an Ns spans them */
#define NS_MAP_SCALE 1000.0

int spm_mesh_mix_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                      spm_error *refused)
{
    /* Assimp 5.2 gives glTF's texture as UNKNOWN; later versions as both of these too */
    static const enum aiTextureType types[] = {aiTextureType_UNKNOWN, aiTextureType_METALNESS,
                                               aiTextureType_DIFFUSE_ROUGHNESS};
    /* MTL's map_Ns (Assimp's SHININESS) */
    static const enum aiTextureType ns_types[] = {aiTextureType_SHININESS};
    struct aiString path;
    int found = 0, gltf = out->format == SPM_MESH_FMT_GLTF;
    if (!gltf && out->format != SPM_MESH_FMT_OBJ)
        return 0;
    const enum aiTextureType *ty = gltf ? types : ns_types;
    size_t nty = gltf ? sizeof types / sizeof *types : 1;
    for (size_t i = 0; i < nty && !found; i++)
        found = aiGetMaterialTextureCount(m, ty[i]) > 0 &&
                aiGetMaterialTexture(m, ty[i], 0, &path, NULL, NULL, NULL, NULL, NULL,
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

/* channel c of the map as a one-byte map: 1 + its index, or -1 with why.
 * ns > 0: the channel holds t in [0, 1] of a Phong exponent ns t, stored as
 * the roughness r whose alpha = r^2 is Walter et al.'s (2007) width for it:
 *   alpha = sqrt(2 / (ns t + 2)),  r = (2 / (ns t + 2))^(1/4). */
static int bind_channel(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                        int c, double ns, const char *mwhere, char *why, size_t whylen)
{
    spm_file f;
    spm_image_src src;
    float *a = NULL;
    int w, h;
    if (spm_mesh_map_image(d, m->mr_embed, m->mr_file, mwhere, &f, &src, why, whylen) ||
        spm_texture_read_one(&src, -1 - c, &a, &w, &h, why, whylen))
        return -1;
    for (size_t k = 0; ns > 0 && k < (size_t)w * h; k++) {
        double t = a[k] > 0 ? (a[k] < 1 ? a[k] : 1) : 0;
        a[k] = (float)pow(2.0 / (ns * t + 2.0), 0.25);
    }
    int i = spm_sb_alpha_pixels(b, a, w, h, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT);
    free(a);
    return 1 + i;
}

/* MTL's map_Ns on a coated or conductor material (mesh_pbr.c: Ks not black):
 * a mix of metallic 1 whose metal is the material itself, of roughness
 * factor 1 and the converted map (bind_channel), so each hit is the material
 * at the texel's width. The exponent's scale is the material's Ns (a map's
 * texel t is the exponent Ns t, as common converters read it), NS_MAP_SCALE
 * without one. */
static int ns_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                   int material, const char *mwhere, spm_error *err)
{
    spm_scene_material proto = b->s->materials[material];
    if (m->mr_map == SPM_MESH_MRMAP_NONE)
        return material;
    char why[300] = "";
    int rm = -1;
    double ns = m->has & SPM_MESH_HAS_SHININESS && m->shininess > 0 ? m->shininess
                                                                    : NS_MAP_SCALE;
    if (proto.type != SPM_MAT_COATED && proto.type != SPM_MAT_CONDUCTOR)
        snprintf(why, sizeof why, "only a coated or conductor material (Ks not black, no "
                                  "refraction) has a width to map");
    else if (proto.mix_metal)
        snprintf(why, sizeof why, "the material has a mix already");
    else if (!d->uvs)
        snprintf(why, sizeof why, "the mesh has no texture coordinates");
    else
        rm = bind_channel(b, d, m, 0, ns, mwhere, why, sizeof why);
    if (rm < 0) {
        spm_warnf("%s: exponent map map_Ns '%s' not applied (%s): Ns %g throughout", mwhere,
                  m->mr_name, why, m->has & SPM_MESH_HAS_SHININESS ? m->shininess : 0.0);
        return material;
    }
    proto.mix_metal = 1 + material;
    proto.mix_metallic = 1.0f;
    proto.mix_rough = 1.0f;
    proto.mix_mmap = 0;
    proto.mix_rmap = rm;
    b->s->alphas[rm - 1].uvx = m->uvx[SPM_MESH_MAP_MR];
    return spm_sb_material_typed(b, &proto, mwhere, err);
}

int spm_mesh_mix_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                      int material, const char *mwhere, spm_error *err)
{
    spm_scene_material proto = b->s->materials[material];
    if (m->format == SPM_MESH_FMT_OBJ)
        return ns_bind(b, d, m, material, mwhere, err);
    if (!proto.mix_metal || m->mr_map == SPM_MESH_MRMAP_NONE)
        return material;
    char why[300] = "";
    int mm = -1, rm = -1;
    if (!d->uvs)
        snprintf(why, sizeof why, "the mesh has no texture coordinates");
    else if ((mm = bind_channel(b, d, m, 2, 0, mwhere, why, sizeof why)) > 0)
        rm = bind_channel(b, d, m, 1, 0, mwhere, why, sizeof why);
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
