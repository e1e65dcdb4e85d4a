#include "cl_contract.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Whether the file at path holds exactly size bytes equal to want. */
static int same_bytes(const char *path, const unsigned char *want, size_t size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return 0;
    unsigned char buf[1 << 14];
    size_t at = 0, got;
    int same = 1;
    while (same && (got = fread(buf, 1, sizeof buf, f)) > 0) {
        same = at + got <= size && memcmp(buf, want + at, got) == 0;
        at += got;
    }
    same = same && !ferror(f) && at == size;
    fclose(f);
    return same;
}

int spm_cl_contract_check(spm_error *err)
{
    char path[4096];
    for (const spm_contract_file *c = spm_contract; c->path; c++)
        if (!same_bytes(spm_data_path(c->path, path, sizeof path), c->bytes, c->size)) {
            spm_errorf(err, "%s: %s the one this specmip was built with (%s/%s): the kernels "
                            "compiled from that tree would not match the host's structs and "
                            "arguments (rebuild specmip there, or set SPECMIP_DATA to the "
                            "tree it was built from)",
                       path, access(path, F_OK) == 0 ? "differs from" : "missing, unlike",
                       SPM_SOURCE_DIR, c->path);
            return 1;
        }
    return 0;
}
