/* Loading a scene file: the format is told by the file's first line, and
 * the parser of that format (scene_parsers.h) builds the scene through the
 * builder (scene_build.h). Nothing here is called back. */
#include "scene_parsers.h"
#include "paths.h"
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#define MINILIGHT_ID "#MiniLight"

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

int spm_scene_load(const char *path, spm_scene *out, spm_error *err)
{
    memset(out, 0, sizeof *out); /* a failed load leaves an empty scene to free */
    out->bg_up = out->bg_down = -1;
    static const char *const models[] = {".glb", ".gltf", ".obj", ".ply", ".stl"};
    int model = 0;
    for (size_t i = 0; i < sizeof models / sizeof *models; i++) {
        size_t n = strlen(path), m = strlen(models[i]);
        model |= n > m && strcasecmp(path + n - m, models[i]) == 0;
    }
    if (!model && spm_scene_model_camera_unused(path, err))
        return 1;
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        spm_errorf(err, "%s: is a directory, not a scene file", path);
        return 1;
    }
    spm_file top; /* the file named on the command line: its folder is the root */
    if (spm_paths_set_root(path, &top, err))
        return 1;
    FILE *f = spm_path_fopen(&top, "rb");
    if (!f) {
        spm_errorf(err, "%s: cannot open: %s", path, strerror(errno));
        return 1;
    }
    char head[sizeof MINILIGHT_ID] = {0};
    size_t got = fread(head, 1, sizeof head - 1, f);
    fclose(f);
    if (got == sizeof head - 1 && memcmp(head, MINILIGHT_ID, got) == 0)
        return spm_scene_parse_minilight(&top, out, err);
    if (ends_with(path, ".ml.txt")) {
        spm_errorf(err, "%s:1:1: expected '%s' at the start of a MiniLight file", path,
                   MINILIGHT_ID);
        return 1;
    }
    if (ends_with(path, ".pbrt"))
        return spm_scene_parse_pbrt(&top, out, err);
    if (ends_with(path, ".xml"))
        return spm_scene_parse_mitsuba(&top, out, err);
    /* a model file alone, by its extension (any case) */
    return model ? spm_scene_parse_model(&top, out, err) : spm_scene_parse_text(&top, out, err);
}
