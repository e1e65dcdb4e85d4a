/* What specmip reads from a glTF's JSON itself, where Assimp 5.2 does not
 * hand it on: KHR_materials_dispersion. */
#include "mesh.h"
#include "json.h"
#include <math.h>
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
    for (size_t i = 0; mats && mats->type == SPM_JSON_ARRAY && i < mats->n && i < d->nmats; i++) {
        const spm_json *ext = spm_json_get(&mats->items[i], "extensions");
        const spm_json *disp = spm_json_get(spm_json_get(ext, "KHR_materials_dispersion"),
                                            "dispersion");
        if (disp && disp->type == SPM_JSON_NUMBER && isfinite(disp->number)) {
            d->mats[i].dispersion = (float)disp->number;
            d->mats[i].has |= SPM_MESH_HAS_DISPERSION;
        }
    }
    spm_json_free(doc);
}
