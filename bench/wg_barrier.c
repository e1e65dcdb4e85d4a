/* The cost of a work-group barrier on an OpenCL device (docs/PERFORMANCE.md,
 * "A work-group traversing together"): kernels/wg_barrier.cl's three kernels,
 * the same chain with no barrier (plain), two a step (dense) and one a step
 * (sparse). Per work-group size, the kernel time of each (OpenCL profiling,
 * the fastest of R launches after a warm-up) and the cost of one barrier:
 * dense minus sparse, per barrier met.
 *
 * usage: wg_barrier [DEVICE [N [R [GROUP]]]]   (defaults 0, 2000, 5; GROUP:
 * that work-group size alone, else 1, 4, 8, 16 and 64; R 0: one launch, its
 * time printed, for an instruction count under a profiler) */
#include <stdio.h>
#include <stdlib.h>
#include "cl_core.h"

/* the fastest of r launches after a warm-up (r 0: the one launch), in seconds */
static int run(spm_cl_ctx *c, cl_kernel k, size_t global, size_t local, int r, double *best,
               spm_error *err)
{
    *best = 1e30;
    for (int i = 0; i <= r; i++) {
        double s;
        if (spm_cl_launch(c, k, global, local, &s, "wg_barrier", err))
            return 1;
        if ((i > 0 || r == 0) && s < *best)
            *best = s;
    }
    return 0;
}

static int study(spm_cl_ctx *c, cl_kernel ks[3], int n, int r, int only, spm_error *err)
{
    size_t global = 16384, sizes[] = {1, 4, 8, 16, 64};
    printf("%s: %zu work-items, %d steps each, fastest of %d launches\n", c->dev.name, global, n,
           r);
    printf("%6s %10s %10s %10s %18s %18s\n", "group", "plain ms", "dense ms", "sparse ms",
           "ns/barrier/group", "ns/barrier/item");
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        size_t w = sizes[i];
        double t[3];
        if (only > 0 && (size_t)only != w)
            continue;
        for (int k = 0; k < 3; k++)
            if (run(c, ks[k], global, w, r, &t[k], err))
                return 1;
        /* dense meets n more barriers per work-group than sparse, the same arithmetic */
        double per_group = (t[1] - t[2]) / ((double)n * (double)(global / w)) * 1e9;
        printf("%6zu %10.3f %10.3f %10.3f %18.2f %18.3f\n", w, t[0] * 1e3, t[1] * 1e3,
               t[2] * 1e3, per_group, per_group / (double)w);
    }
    return 0;
}

int main(int argc, char **argv)
{
    int dev = argc > 1 ? atoi(argv[1]) : 0, n = argc > 2 ? atoi(argv[2]) : 2000;
    int r = argc > 3 ? atoi(argv[3]) : 5, only = argc > 4 ? atoi(argv[4]) : 0;
    if (n < 2 || r < 0) {
        fprintf(stderr, "wg_barrier: N >= 2 steps and R >= 0 launches\n");
        return 2;
    }
    spm_error err;
    spm_cl_ctx c;
    if (spm_cl_ctx_create(dev, &c, &err)) {
        fprintf(stderr, "wg_barrier: %s\n", err.msg);
        return 2;
    }
    const char *files[] = {"kernels/wg_barrier.cl"}, *names[3] = {"plain", "dense", "sparse"};
    cl_program p = NULL;
    cl_kernel ks[3] = {NULL, NULL, NULL};
    cl_mem out = NULL;
    int bad = spm_cl_build(&c, files, 1, "", &p, &err) ||
              spm_cl_buffer(&c, CL_MEM_WRITE_ONLY, 16384 * sizeof(float), NULL, "out", &out, &err);
    for (int k = 0; k < 3 && !bad; k++)
        bad = spm_cl_kernel(p, names[k], &ks[k], &err) ||
              spm_cl_arg(ks[k], 0, sizeof out, &out, names[k], &err) ||
              spm_cl_arg(ks[k], 1, sizeof n, &n, names[k], &err);
    bad = bad || study(&c, ks, n, r, only, &err);
    if (bad)
        fprintf(stderr, "wg_barrier: %s\n", err.msg);
    for (int k = 0; k < 3; k++)
        spm_cl_release_kernel(ks[k]);
    spm_cl_release_mem(out);
    spm_cl_release_program(p);
    spm_cl_ctx_release(&c);
    return bad;
}
