/* The built-in default scene is scenes/cornell.scene, read from the data
 * directory (spm_data_path), so the file and the default cannot drift apart
 * and the default works from any working directory. */
#include "scene.h"
#include <stdio.h>

int spm_scene_default(spm_scene *out, spm_error *err)
{
    char path[4096];
    spm_data_path("scenes/cornell.scene", path, sizeof path);
    if (spm_scene_load(path, out, err))
        return 1;
    snprintf(out->path, sizeof out->path, "<default>");
    return 0;
}
