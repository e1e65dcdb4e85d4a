/* The environment map's palette (host/scene/envmap.h, docs/METHODS.md
 * "Environment maps"): for each map named and each grid of q steps, the
 * palette's colours, the chromaticity error of the texels' spectra (the
 * distance in CIE 1976 u'v' of each texel's own linear sRGB from its cell's
 * lifted spectrum: the largest, and the mean weighted by luminance), the
 * time the palette takes, and the memory of the two designs: the palette's
 * (two words a texel, a shade-table row per colour and level) against a
 * factor carrying each texel's lift (four floats a texel).
 * Usage: envmap_palette MAP.exr...   (SPECMIP_DATA: the project's data) */
#include "envmap.h"
#include "paths.h"
#include "scene.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const int grids[] = {8, 16, 32, 64};

/* floats a colour takes in the shade tables: every level's bins */
static int row_floats(void)
{
    int n = 0;
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        n += SPM_LEVEL_BINS(l);
    return n;
}

int main(int argc, char **argv)
{
    spm_error err;
    printf("| map | texels | q | colours | u'v' max | u'v' mean (Y-weighted) | palette s | "
           "palette MB | per-texel lift MB |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int a = 1; a < argc; a++) {
        spm_file f, top;
        if (spm_paths_set_root(argv[a], &top, &err) ||
            spm_path_check(".", argv[a], argv[a], &f, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            return 2;
        }
        for (size_t g = 0; g < sizeof grids / sizeof grids[0]; g++) {
            spm_scene s;
            memset(&s, 0, sizeof s);
            if (spm_envmap_load(&s, &f, 1.0, 0.0, argv[a], &err)) {
                fprintf(stderr, "%s\n", err.msg);
                return 2;
            }
            struct timespec t0, t1;
            clock_gettime(CLOCK_MONOTONIC, &t0);
            if (spm_envmap_palette_grid(&s, grids[g], &err)) {
                fprintf(stderr, "%s\n", err.msg);
                return 2;
            }
            clock_gettime(CLOCK_MONOTONIC, &t1);
            const spm_scene_envmap *e = s.env;
            double texels = (double)e->w * e->h, secs = (double)(t1.tv_sec - t0.tv_sec) +
                                                       1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
            const char *name = strrchr(argv[a], '/') ? strrchr(argv[a], '/') + 1 : argv[a];
            printf("| %s | %dx%d | %d | %d | %.4f | %.5f | %.3f | %.2f | %.2f |\n", name, e->w, e->h,
                   grids[g], e->ncolours, e->duv_max, e->duv_mean, secs,
                   (12.0 * texels + 4.0 * row_floats() * e->ncolours) / 1e6, 16.0 * texels / 1e6);
            spm_envmap_free(s.env);
            free(s.colours);
        }
    }
    return 0;
}
