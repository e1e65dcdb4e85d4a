#include "bench_ops.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cl_core.h"

#define ROWS 4     /* spectra per work-item (opbench.cl): a power of two */
#define REPEATS 15 /* the fastest of these counts: the machine is shared */

typedef struct {
    const char *suffix, *label;
    int width, nvec, bins;
} layout;

static const layout layouts[] = {
    {"l0", "5 nm: 5 x float16", 16, 5, 80},       {"l1", "10 nm: 5 x float8", 8, 5, 40},
    {"l2", "20 nm: 5 x float4", 4, 5, 20},        {"l3", "40 nm: 5 x float2", 2, 5, 10},
    {"truth", "1 nm: 25 x float16", 16, 25, 400}, {"rgb", "rgb: 1 x float4", 4, 1, 3},
};
#define NLAYOUTS (int)(sizeof layouts / sizeof layouts[0])
static const char *const ops[] = {"mul", "fma", "set", "clear"};
static const char *const op_names[] = {"multiply", "scaled add", "set", "clear"};
#define NOPS 4

/* The fastest of REPEATS runs after one warm-up, in seconds. */
static int time_kernel(spm_cl_ctx *c, cl_kernel k, size_t items, double *best, spm_error *err)
{
    *best = 1e30;
    for (int r = 0; r <= REPEATS; r++) {
        double s;
        if (spm_cl_launch(c, k, items, 0, &s, "opbench", err))
            return 1;
        if (s < 0) {
            spm_errorf(err, "device '%s' gives no kernel times (profiling)", c->dev.name);
            return 1;
        }
        if (r > 0 && s < *best)
            *best = s;
    }
    return 0;
}

static int run_all(spm_cl_ctx *c, cl_program prog, cl_mem buf, int items, int iters,
                   double ns[NLAYOUTS][NOPS], spm_error *err)
{
    cl_uint mask = ROWS - 1, it = (cl_uint)iters;
    cl_float scale = 0.5f; /* d += a * 0.5 stays finite over any run: no overflow, no denormals */
    for (int l = 0; l < NLAYOUTS; l++)
        for (int o = 0; o < NOPS; o++) {
            char name[64];
            snprintf(name, sizeof name, "op_%s_%s", ops[o], layouts[l].suffix);
            cl_kernel k;
            if (spm_cl_kernel(prog, name, &k, err))
                return 1;
            double s = 0;
            int bad = spm_cl_arg(k, 0, sizeof buf, &buf, name, err) ||
                      spm_cl_arg(k, 1, sizeof mask, &mask, name, err) ||
                      spm_cl_arg(k, 2, sizeof it, &it, name, err) ||
                      spm_cl_arg(k, 3, sizeof scale, &scale, name, err) ||
                      time_kernel(c, k, (size_t)items, &s, err);
            spm_cl_release_kernel(k);
            if (bad)
                return 1;
            ns[l][o] = s * 1e9 / ((double)items * iters);
        }
    return 0;
}

static void print_table(FILE *f, double ns[NLAYOUTS][NOPS])
{
    fprintf(f, "%-22s %5s", "layout", "bins");
    for (int o = 0; o < NOPS; o++)
        fprintf(f, "  %10s ns %5s", op_names[o], "x l0");
    fprintf(f, "\n");
    for (int l = 0; l < NLAYOUTS; l++) {
        fprintf(f, "%-22s %5d", layouts[l].label, layouts[l].bins);
        for (int o = 0; o < NOPS; o++)
            fprintf(f, "  %13.2f %5.2f", ns[l][o], ns[l][o] / ns[0][o]);
        fprintf(f, "\n");
    }
}

static int write_csv(const char *dir, double ns[NLAYOUTS][NOPS], spm_error *err)
{
    char path[4096], part[4200];
    snprintf(path, sizeof path, "%s/ops.csv", dir);
    snprintf(part, sizeof part, "%s.part", path);
    FILE *f = fopen(part, "w");
    if (!f) {
        spm_errorf(err, "%s: %s", part, strerror(errno));
        return 1;
    }
    fprintf(f, "layout,bins,width,vectors,op,ns_per_op,ratio_to_l0\n");
    for (int l = 0; l < NLAYOUTS; l++)
        for (int o = 0; o < NOPS; o++)
            fprintf(f, "%s,%d,%d,%d,%s,%.4f,%.4f\n", layouts[l].suffix, layouts[l].bins, layouts[l].width,
                    layouts[l].nvec, ops[o], ns[l][o], ns[l][o] / ns[0][o]);
    if (fclose(f) || rename(part, path)) {
        spm_errorf(err, "%s: %s", path, strerror(errno));
        return 1;
    }
    return 0;
}

const char spm_ops_program_file[] = "kernels/opbench.cl";

int spm_bench_ops(int device, int items, int iters, const char *dir, spm_error *err)
{
    spm_cl_ctx c;
    if (spm_cl_ctx_create(device, &c, err))
        return SPM_EXIT_RUNTIME;
    const char *files[] = {spm_ops_program_file};
    cl_program prog = NULL;
    cl_mem buf = NULL;
    int rc = spm_cl_build(&c, files, 1, "", &prog, err) ? SPM_EXIT_RUNTIME : 0;
    size_t nfloat = (size_t)items * ROWS * 16 * 25; /* the largest layout: truth */
    if (!rc) {
        float *init = spm_xmalloc(nfloat * sizeof *init);
        for (size_t i = 0; i < nfloat; i++)
            init[i] = 1.0f; /* products of ones stay one: no denormal slow paths */
        if (spm_cl_buffer(&c, CL_MEM_READ_WRITE, nfloat * sizeof *init, init, "opbench", &buf,
                          err))
            rc = SPM_EXIT_RUNTIME;
        free(init);
    }
    double ns[NLAYOUTS][NOPS];
    if (!rc && run_all(&c, prog, buf, items, iters, ns, err))
        rc = SPM_EXIT_RUNTIME;
    if (!rc) {
        printf("spectral operations on %s, %d work-items x %d operations, fastest of %d runs\n"
               "(ns per operation on a whole spectrum; 'x l0' = time / level 0's time)\n",
               c.dev.name, items, iters, REPEATS);
        print_table(stdout, ns);
        printf("reproduce: specmip bench --ops --device %d --ops-items %d --ops-iters %d --out %s\n",
               device, items, iters, dir);
        rc = write_csv(dir, ns, err) ? SPM_EXIT_RUNTIME : 0;
    }
    spm_cl_release_mem(buf);
    spm_cl_release_program(prog);
    spm_cl_ctx_release(&c);
    return rc;
}
