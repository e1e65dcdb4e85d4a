/* libFuzzer harness: Mitsuba 3 XML scenes (host/scene/mitsuba_*.c) from any
 * bytes: a refusal names the file; nothing crashes, leaks or hangs. */
#include "fuzz_input.h"
#include "scene.h"
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    spm_quiet_warnings = 1;
    const char *path = spm_fuzz_write("input.xml", data, size);
    if (!path)
        return 0;
    spm_scene s;
    spm_error err;
    if (spm_scene_load(path, &s, &err) && !strstr(err.msg, ".xml"))
        abort(); /* every error names the scene file where it arose */
    spm_scene_free(&s);
    return 0;
}
