/* libFuzzer harness: the MiniLight importer (host/scene/scene_minilight.c), called
 * directly so that inputs need not start with the "#MiniLight" line. */
#include "fuzz_input.h"
#include "scene_build.h"
#include "scene_parsers.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = spm_fuzz_write("input.ml.txt", data, size);
    if (!path)
        return 0;
    spm_scene s;
    spm_error err;
    spm_file file;
    if (spm_paths_set_root(path, &file, &err) == 0 && spm_scene_parse_minilight(&file, &s, &err) == 0)
        spm_scene_free(&s);
    return 0;
}
