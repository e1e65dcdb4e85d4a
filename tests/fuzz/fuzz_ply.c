/* libFuzzer harness: the project's own PLY reader (mesh_ply.c, every PLY
 * file but one of polygons) on any bytes, written to a file as the loader
 * reads files. A success must hold triangles of in-range material indices;
 * anything else is an error or the answer that sends polygons to Assimp. */
#include "fuzz_input.h"
#include "mesh_ply.h"
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = spm_fuzz_write("in.ply", data, size);
    if (!path)
        return 0;
    spm_mesh_data d;
    spm_error err;
    spm_file file;
    if (spm_paths_set_root(path, &file, &err))
        abort();
    int rc = spm_ply_read(&file, &d, &err);
    if (rc != 0 && rc != 1 && rc != SPM_PLY_POLYGONS)
        abort();
    if (rc == 0) {
        if (d.ntris == 0 || d.nmats != 1)
            abort();
        for (uint64_t t = 0; t < d.ntris; t++)
            if (d.tris[t].mat != 0)
                abort();
        spm_mesh_free(&d);
    }
    return 0;
}
