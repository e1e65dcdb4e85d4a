/* Quick speed check of the OpenCL backend (not a test): a scene at WxH with SPP
 * samples, the modes round-robin for ROUNDS rounds in one process (a busy
 * moment of the shared machine slows a round, not a mode); per mode the
 * median [min-max] of wall time, process CPU time (getrusage: every thread,
 * PoCL's included), paths/s and stage times, then within-round ratios.
 * Build: gcc -O2 -std=gnu11 -DCL_TARGET_OPENCL_VERSION=120 -Iinclude -Ihost \
 *   tools/cl_bench.c build-X/libspm_core.a $(pkg-config --libs OpenImageIO) -lOpenCL -lstdc++ -lm -lpthread
 * Run:   SPECMIP_DATA=. ./cl_bench [W H SPP [modes...]]
 * env:   SCENE=file (default: the built-in Cornell box), ROUNDS (3), PER (samples per pass) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include "render_cl.h"
#include "render_run.h"
#include "render_setup.h"

#define MAX_MODES 8
#define MAX_ROUNDS 32
enum { F_WALL, F_CPU, F_MPS, F_TRACE, F_SHADE, NFIG };
static const char *fig_name[NFIG] = {"wall s", "cpu s", "Mpaths/s", "trace s", "shade s"};

static double cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_utime.tv_sec + (double)u.ru_stime.tv_sec +
           1e-6 * (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* "median [min-max]" of n values */
static void print_stat(const double *v, int n)
{
    double s[MAX_ROUNDS];
    memcpy(s, v, (size_t)n * sizeof *s);
    qsort(s, (size_t)n, sizeof *s, cmp_double);
    double med = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    printf("  %8.4f [%.4f-%.4f]", med, s[0], s[n - 1]);
}

/* One render of `spp` samples in passes of `per`; figures into fig[]. */
static int render(const spm_geometry *g, const spm_tables *t, int mode, int spp, spm_u32 per,
                  float *img, double fig[NFIG])
{
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, g, t, mode, 1, &r, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    spm_pass_stats st;
    memset(&st, 0, sizeof st);
    double t0 = spm_now(), c0 = cpu_seconds();
    for (int s = 0; s < spp; s += (int)per) {
        spm_u32 n = (spm_u32)(spp - s) < per ? (spm_u32)(spp - s) : per;
        if (spm_cl_pass(r, (spm_u32)s, n, img, &st, &err)) {
            spm_cl_destroy(r);
            return fprintf(stderr, "%s\n", err.msg), 1;
        }
    }
    fig[F_WALL] = spm_now() - t0;
    fig[F_CPU] = cpu_seconds() - c0;
    fig[F_MPS] = (double)st.paths / fig[F_WALL] * 1e-6;
    fig[F_TRACE] = st.trace_s;
    fig[F_SHADE] = st.shade_s;
    spm_cl_destroy(r);
    return 0;
}

static int find_mode(char **names, int nm, const char *m)
{
    for (int i = 0; i < nm; i++)
        if (!strcmp(names[i], m))
            return i;
    return -1;
}

int main(int argc, char **argv)
{
    int w = argc > 3 ? atoi(argv[1]) : 256, h = argc > 3 ? atoi(argv[2]) : 256;
    int spp = argc > 3 ? atoi(argv[3]) : 64;
    int rounds = getenv("ROUNDS") ? atoi(getenv("ROUNDS")) : 3;
    const char *scene = getenv("SCENE");
    char *def[] = {"ref", "ml", "rgb"};
    char **names = argc > 4 ? argv + 4 : def;
    int nm = argc > 4 ? argc - 4 : 3;
    if (nm > MAX_MODES || rounds < 1 || rounds > MAX_ROUNDS || w < 1 || h < 1 || spp < 1)
        return fprintf(stderr, "cl_bench: at most %d modes and %d rounds\n", MAX_MODES, MAX_ROUNDS),
               2;
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
    spm_error err;
    spm_pretest_opts po;
    spm_quiet_warnings = 1;
    spm_pretest_defaults(&po);
    if (scene ? spm_scene_load(scene, &sc, &err) : spm_scene_default(&sc, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    sc.width = w;
    sc.height = h;
    if (spm_geometry_build(&sc, &g, &err) || spm_tables_build(&sc, &po, &t, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    int modes[MAX_MODES];
    for (int i = 0; i < nm; i++)
        if ((modes[i] = spm_mode_parse(names[i])) < 0)
            return fprintf(stderr, "cl_bench: unknown mode '%s'\n", names[i]), 2;
    size_t npix = (size_t)w * h;
    spm_u32 per = getenv("PER") ? (spm_u32)atoi(getenv("PER")) : spm_spp_per_pass(npix, spp);
    float *img = malloc(npix * 3 * sizeof *img);
    printf("%s %dx%d, %d spp, %u spp per pass, %d triangles, %d rounds\n",
           scene ? scene : "default scene", w, h, spp, per, g.ntris, rounds);
    static double fig[MAX_ROUNDS][MAX_MODES][NFIG];
    for (int i = 0; i < nm; i++) /* kernel builds land in PoCL's cache first */
        if (render(&g, &t, modes[i], 1, 1, img, fig[0][i]))
            return 1;
    for (int r = 0; r < rounds; r++)
        for (int i = 0; i < nm; i++)
            if (render(&g, &t, modes[i], spp, per, img, fig[r][i]))
                return 1;
    printf("%-6s", "mode");
    for (int f = 0; f < NFIG; f++)
        printf("  %-24s", fig_name[f]);
    printf("\n");
    for (int i = 0; i < nm; i++) {
        printf("%-6s", names[i]);
        for (int f = 0; f < NFIG; f++) {
            double v[MAX_ROUNDS];
            for (int r = 0; r < rounds; r++)
                v[r] = fig[r][i][f];
            print_stat(v, rounds);
        }
        printf("\n");
    }
    /* the issues' ratios, where both modes ran */
    const struct { const char *a, *b; int f; } ratios[] = {
        {"ref", "ml", F_SHADE}, {"mlc", "ml", F_SHADE}, {"ml", "rgb", F_WALL}, {"ml", "rgb", F_CPU}};
    for (size_t k = 0; k < sizeof ratios / sizeof *ratios; k++) {
        int a = find_mode(names, nm, ratios[k].a), b = find_mode(names, nm, ratios[k].b);
        if (a < 0 || b < 0)
            continue;
        double v[MAX_ROUNDS];
        for (int r = 0; r < rounds; r++)
            v[r] = fig[r][a][ratios[k].f] / fig[r][b][ratios[k].f];
        printf("%s/%s %-8s", ratios[k].a, ratios[k].b, fig_name[ratios[k].f]);
        print_stat(v, rounds);
        printf("\n");
    }
    free(img);
    return 0;
}
