/* The OpenCL backend's program (cl_renderer.h): the trace, accumulate and
 * shade kernels, the last compiled only for the slots the plan uses, each
 * with the define its mode's descriptor gives (modes.h), and the code of the
 * material and emitter types the scene uses (materials.h, the plan's
 * type_defines). */
#include "cl_renderer.h"

int spm_clr_build(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err)
{
    char defs[512];
    int n = 0;
    defs[0] = '\0';
    for (int s = 0; s < plan->nslots; s++)
        if (plan->used[s]) {
            char define[96];
            spm_mode_kernel(r->mode, plan->tables, s, r->kname[s], sizeof r->kname[s], define,
                            sizeof define);
            n += snprintf(defs + n, sizeof defs - (size_t)n, "-D%s ", define);
        }
    n += snprintf(defs + n, sizeof defs - (size_t)n, "%s", plan->type_defines);
    if (plan->nspec)
        n += snprintf(defs + n, sizeof defs - (size_t)n, "-DSPM_SPEC_BINS=%d -DSPM_PATH_CH=%d ",
                      plan->nspec, plan->pix_ch);
    /* The device's index makes each device's program text distinct: PoCL
     * otherwise shares one compiled kernel between same-kind devices, and two
     * devices launching it at once can break its reference counts (an
     * assertion in pocl_release_dlhandle_cache). */
    n += snprintf(defs + n, sizeof defs - (size_t)n, "-DSPM_DEVICE_INDEX=%d", r->cl.dev.index);
    const char *files[] = {"kernels/trace.cl", "kernels/shade.cl"};
    if (spm_cl_build(&r->cl, files, 2, defs, &r->prog, err))
        return 1;
    cl_int rc;
    r->k_trace = clCreateKernel(r->prog, "spm_trace", &rc);
    CK(rc, "clCreateKernel(spm_trace)");
    r->k_accum = clCreateKernel(r->prog, "spm_accumulate", &rc);
    CK(rc, "clCreateKernel(spm_accumulate)");
    for (int s = 0; s < plan->nslots; s++)
        if (plan->used[s]) {
            char what[96];
            snprintf(what, sizeof what, "clCreateKernel(%s)", r->kname[s]);
            r->k_shade[s] = clCreateKernel(r->prog, r->kname[s], &rc);
            CK(rc, what);
        }
    return 0;
}

/* PoCL compiles a kernel for the shape of its launches (local size, zero
 * offset, a grid under 2^32 items) at the first launch, not in clBuildProgram:
 * on a cold cache that is most of the build, and it would land in the first
 * pass. So every kernel is launched once here, in the shape every pass uses,
 * with nothing to do (no path, no pixel: each work-item returns at once). */
int spm_clr_warm_up(spm_cl_renderer *r, spm_error *err)
{
    batch b = {0, 1, 0, 0, 0, LOCAL_SIZE};
    cl_event ev[NSLOTS + 2] = {NULL};
    size_t off[NSLOTS + 1] = {0};
    int rc = spm_clr_run_trace(r, &b, &ev[NSLOTS], err) ||
             spm_clr_run_shade(r, &b, off, r->ident, 1, ev, err) ||
             spm_clr_run_accumulate(r, &b, &ev[NSLOTS + 1], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(warm-up)", err);
    spm_clr_release_events(ev, NSLOTS + 2, NULL);
    return rc;
}
