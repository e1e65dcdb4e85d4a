/* glTF's KHR_texture_transform (mesh_gltf.h spm_mesh_gltf_uvx): each
 * textureInfo's offset, rotation and scale as a transform of its map's
 * texture coordinates (texture.h spm_uvx), applied where the map is looked
 * up, not to the mesh's coordinates: two maps of a material may each have
 * their own. */
#include "mesh_gltf.h"
#include "json.h"
#include <math.h>

/* a member's number, or def when absent or not a number */
static double num(const spm_json *v, const char *key, double def)
{
    const spm_json *m = spm_json_get(v, key);
    return m && m->type == SPM_JSON_NUMBER ? m->number : def;
}

/* a member that must be an array of n finite numbers: 1 read (or absent:
 * out untouched), 0 when it is something else */
static int finite_nums(const spm_json *v, const char *key, double *out, size_t n)
{
    const spm_json *a = spm_json_get(v, key);
    if (!a)
        return 1;
    if (a->type != SPM_JSON_ARRAY || a->n != n)
        return 0;
    for (size_t i = 0; i < n; i++) {
        if (a->items[i].type != SPM_JSON_NUMBER || !isfinite(a->items[i].number))
            return 0;
        out[i] = a->items[i].number;
    }
    return 1;
}

/* textureInfo `info`'s transform into *out; 0 when the map cannot be read as
 * given (another coordinate set, values that are not numbers) */
static int info_uvx(const spm_json *info, spm_uvx *out)
{
    const spm_json *x = spm_json_get(spm_json_get(info, "extensions"), "KHR_texture_transform");
    double set = num(info, "texCoord", 0);
    double offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = num(x, "rotation", 0);
    set = num(x, "texCoord", set); /* the extension's overrides the map's */
    if (set != 0)
        return 0;
    if (!x)
        return 1;
    if (!finite_nums(x, "offset", offset, 2) || !finite_nums(x, "scale", scale, 2) ||
        !isfinite(rotation))
        return 0;
    spm_uvx_gltf(offset, rotation, scale, out);
    return 1;
}

void spm_mesh_gltf_uvx(const spm_json *mat, spm_mesh_material *out, uint32_t *ignored)
{
    const spm_json *pbr = spm_json_get(mat, "pbrMetallicRoughness");
    const spm_json *info[4] = {spm_json_get(pbr, "baseColorTexture"),
                               spm_json_get(mat, "emissiveTexture"),
                               spm_json_get(pbr, "metallicRoughnessTexture"),
                               spm_json_get(mat, "normalTexture")};
    for (int k = 0; k < 4; k++) {
        out->uvx[k].on = 0;
        if (info[k] && !info_uvx(info[k], &out->uvx[k])) {
            out->uvx[k].on = 0;
            *ignored |= SPM_MESH_IGN_TEX_TRANSFORM;
        }
    }
    const spm_json *occ = spm_json_get(mat, "occlusionTexture");
    spm_uvx unused;
    if (occ && !info_uvx(occ, &unused)) /* not rendered, but named all the same */
        *ignored |= SPM_MESH_IGN_TEX_TRANSFORM;
}
