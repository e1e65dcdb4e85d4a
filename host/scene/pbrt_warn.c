/* What a pbrt-v4 file holds that specmip does not render: one warning per
 * kind of thing, at its first place, and a count of its repeats at the end,
 * so a scene of a thousand textured shapes says "texture" once, not a
 * thousand times. Under --strict the first one stops the load. */
#include "pbrt.h"
#include <stdlib.h>
#include <string.h>

int spm_scene_strict = 0;

typedef struct {
    char what[256];
    char first[600];
    int count;
} seen_t;

static seen_t *seen;
static int nseen;

int pbrt_warn(const char *where, const char *what, const char *why, spm_error *err)
{
    for (int i = 0; i < nseen; i++)
        if (!strcmp(seen[i].what, what)) {
            seen[i].count++;
            return 0;
        }
    if (spm_scene_strict) {
        spm_errorf(err, "%s: %s: %s (--strict makes this an error)", where, what, why);
        return 1;
    }
    spm_warnf("%s: %s ignored: %s", where, what, why);
    seen = spm_xrealloc(seen, (size_t)(nseen + 1) * sizeof *seen);
    snprintf(seen[nseen].what, sizeof seen[nseen].what, "%s", what);
    snprintf(seen[nseen].first, sizeof seen[nseen].first, "%s", where);
    seen[nseen++].count = 1;
    return 0;
}

void pbrt_warn_summary(void)
{
    for (int i = 0; i < nseen; i++)
        if (seen[i].count > 1)
            spm_warnf("%s: %s: ignored %d times in all (the first here)", seen[i].first,
                      seen[i].what, seen[i].count);
}

void pbrt_warn_reset(void)
{
    free(seen);
    seen = NULL;
    nseen = 0;
}
