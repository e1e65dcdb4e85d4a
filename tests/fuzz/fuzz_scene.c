/* libFuzzer harness: the project's own scene format (host/scene/scene_parse.c). */
#include "fuzz_input.h"
#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = spm_fuzz_write("input.scene", data, size);
    if (!path)
        return 0;
    spm_scene s;
    spm_error err;
    spm_scene_load(path, &s, &err);
    spm_scene_free(&s);
    return 0;
}
