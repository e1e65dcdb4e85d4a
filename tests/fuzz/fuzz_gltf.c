/* libFuzzer harness: a model's references checked before its importer runs
 * (mesh_refs.c) on any bytes, as a .gltf (JSON), a .glb (binary) or an .obj
 * with its MTL files (by the first byte), and the JSON reader itself. The
 * input's folder is the root; a success must not name a file outside it. */
#include "fuzz_input.h"
#include "json.h"
#include "mesh.h"
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    spm_quiet_warnings = 1;
    char why[200];
    spm_json *v = spm_json_parse((const char *)data, size, why, sizeof why);
    if (!v && !why[0])
        abort(); /* a refusal says why */
    spm_json_free(v);
    if (size < 1)
        return 0;
    static const char *const names[] = {"in.gltf", "in.glb", "in.obj", "in.mtl"};
    const char *path = spm_fuzz_write(names[data[0] & 3], data + 1, size - 1);
    if (!path)
        return 0;
    spm_file file;
    spm_error err;
    if (spm_paths_set_root(path, &file, &err))
        abort();
    char unrendered[64];
    if (spm_mesh_refs_check(&file, unrendered, sizeof unrendered, &err) && !strstr(err.msg, "in."))
        abort(); /* every error names the file */
    if (strlen(unrendered) >= sizeof unrendered)
        abort();
    return 0;
}
