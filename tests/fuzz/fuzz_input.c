#include "fuzz_input.h"
#include "util.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[256];

const char *spm_fuzz_write(const char *name, const uint8_t *data, size_t size)
{
    static char path[512];
    if (!dir[0]) {
        /* SPM_FUZZ_DIR: a directory that may hold CSV files a scene refers to. */
        const char *fixed = getenv("SPM_FUZZ_DIR");
        if (fixed)
            snprintf(dir, sizeof dir, "%s", fixed);
        else
            snprintf(dir, sizeof dir, "%s/specmip-fuzz-%d",
                     getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());
        if (mkdir(dir, 0700) != 0 && errno != EEXIST)
            return NULL;
        spm_quiet_warnings = 1; /* warnings are not findings */
    }
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f)
        return NULL;
    size_t n = fwrite(data, 1, size, f);
    fclose(f);
    return n == size ? path : NULL;
}
