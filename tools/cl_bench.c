/* Quick speed check of the OpenCL backend (not a test): the default Cornell
 * box at WxH with SPP samples, per mode wall time, paths/s and stage times.
 * Build: gcc -O2 -std=gnu11 -DCL_TARGET_OPENCL_VERSION=120 -Iinclude -Ihost \
 *   tools/cl_bench.c build-X/libspm_core.a $(pkg-config --libs OpenImageIO) -lOpenCL -lstdc++ -lm -lpthread
 * Run:   SPECMIP_DATA=. ./cl_bench [W H SPP [modes...]]   (PER=n: samples per pass) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "render_cl.h"
#include "render_run.h"
#include "render_setup.h"

int main(int argc, char **argv)
{
    int w = argc > 3 ? atoi(argv[1]) : 256, h = argc > 3 ? atoi(argv[2]) : 256;
    int spp = argc > 3 ? atoi(argv[3]) : 64;
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_error err;
    spm_pretest_opts po;
    spm_quiet_warnings = 1;
    spm_pretest_defaults(&po);
    if (spm_scene_default(&sc, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    sc.width = w;
    sc.height = h;
    if (spm_geometry_build(&sc, &g, &err) || spm_tables_build(&sc, &po, &t, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    const char *def[] = {"ref", "ml", "rgb"};
    int nm = argc > 4 ? argc - 4 : 3;
    size_t npix = (size_t)w * h;
    spm_u32 per = getenv("PER") ? (spm_u32)atoi(getenv("PER")) : spm_spp_per_pass(npix, spp);
    float *img = malloc(npix * 3 * sizeof *img);
    printf("%dx%d, %d spp, %u spp per pass, %d triangles\n", w, h, spp, per, g.ntris);
    for (int i = 0; i < nm; i++) {
        const char *name = argc > 4 ? argv[4 + i] : def[i];
        int mode = spm_mode_parse(name);
        spm_cl_renderer *r;
        if (spm_cl_create(0, &g, &t, mode, 1, &r, &err))
            return fprintf(stderr, "%s\n", err.msg), 1;
        spm_pass_stats st;
        memset(&st, 0, sizeof st);
        double t0 = spm_now();
        for (int s = 0; s < spp; s += (int)per) {
            spm_u32 n = (spm_u32)(spp - s) < per ? (spm_u32)(spp - s) : per;
            if (spm_cl_pass(r, (spm_u32)s, n, img, &st, &err))
                return fprintf(stderr, "%s\n", err.msg), 1;
        }
        double wall = spm_now() - t0;
        printf("%-5s wall %6.2f s  %5.2f Mpaths/s  trace %6.2f s  shade %6.3f s  accum %5.3f s  "
               "levels 0-3: %llu %llu %llu %llu\n",
               name, wall, (double)st.paths / wall * 1e-6, st.trace_s, st.shade_s, st.accum_s,
               (unsigned long long)(st.level_paths[0][0] + st.level_paths[0][1] + st.level_paths[0][2]),
               (unsigned long long)(st.level_paths[1][0] + st.level_paths[1][1] + st.level_paths[1][2]),
               (unsigned long long)(st.level_paths[2][0] + st.level_paths[2][1] + st.level_paths[2][2]),
               (unsigned long long)(st.level_paths[3][0] + st.level_paths[3][1] + st.level_paths[3][2]));
        spm_cl_destroy(r);
    }
    free(img);
    return 0;
}
