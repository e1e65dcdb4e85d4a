/* The OpenCL backend's program (cl_renderer.h): the trace, accumulate and
 * shade kernels, the last compiled only for the slots the plan uses, each
 * with the define its mode's descriptor gives (modes.h), and the code of the
 * material and emitter types the scene uses (materials.h, the plan's
 * type_defines). */
#include <string.h>
#include "cl_renderer.h"

const char *const spm_cl_program_files[SPM_CL_PROGRAM_NFILES] = {"kernels/trace.cl",
                                                                 "kernels/shade.cl"};

void spm_cl_program_defines(const spm_render_plan *plan, int device_index, char *defs, size_t size,
                            char (*kname)[64])
{
    size_t n = 0;
    defs[0] = '\0';
    for (int s = 0; s < plan->nslots; s++)
        if (plan->used[s]) {
            char define[96], name[64];
            spm_mode_kernel(plan->mode, plan->tables, s, name, sizeof name, define, sizeof define);
            if (kname)
                snprintf(kname[s], sizeof kname[s], "%s", name);
            n += (size_t)snprintf(defs + n, size - n, "-D%s ", define);
        }
    n += (size_t)snprintf(defs + n, size - n, "%s", plan->type_defines);
    if (plan->integrator == SPM_INTEGRATOR_LIGHT) /* kernels/lighttrace.cl's program */
        n += (size_t)snprintf(defs + n, size - n, "-DSPM_LIGHT_TRACE ");
    if (plan->integrator == SPM_INTEGRATOR_BDPT) /* kernels/bdpt.cl's program */
        n += (size_t)snprintf(defs + n, size - n, "-DSPM_BDPT ");
    if (plan->nspec)
        n += (size_t)snprintf(defs + n, size - n, "-DSPM_SPEC_BINS=%d -DSPM_PATH_CH=%d ",
                              plan->nspec, plan->pix_ch);
    /* The device's index makes each device's program text distinct: PoCL
     * otherwise shares one compiled kernel between same-kind devices, and two
     * devices launching it at once can break its reference counts (an
     * assertion in pocl_release_dlhandle_cache). */
    snprintf(defs + n, size - n, "-DSPM_DEVICE_INDEX=%d", device_index);
}

int spm_clr_build(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err)
{
    char defs[512];
    spm_cl_program_defines(plan, r->cl.dev.index, defs, sizeof defs, r->kname);
    if (plan->integrator == SPM_INTEGRATOR_LIGHT)
        return spm_clr_light_build(r, plan, defs, err);
    if (plan->integrator == SPM_INTEGRATOR_BDPT)
        return spm_clr_bdpt_build(r, plan, defs, err);
    if (spm_cl_build(&r->cl, spm_cl_program_files, SPM_CL_PROGRAM_NFILES, defs, &r->prog, err))
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

/* PoCL compiles a kernel's work-group functions for the shape of a launch
 * at its first launch of that shape, not in clBuildProgram, and keeps one
 * version per shape: the local size, a zero global offset, and whether the
 * global size is below the device's grid specialisation limit (USHRT_MAX on
 * its CPU devices; its cache names them 64-1-1-goffs0-smallgrid and
 * 64-1-1-goffs0). A pass launches every kernel with LOCAL_SIZE and offset 0,
 * at a batch's size: a pass is about 2^16 paths (spm_spp_per_pass), so its
 * launches fall on either side of the limit, and the last pass of a render
 * may be smaller than the others. So every kernel is launched here once in
 * each class, with nothing to do (no path, no pixel: each work-item returns
 * at once), and no render or benchmark times a compile. Other platforms
 * compile in clBuildProgram; they get the small launch only (under Oclgrind,
 * which simulates every work-item, 2^16 of them per kernel take seconds). */
#define POCL_GRID_LIMIT 65535u
int spm_clr_warm_up(spm_cl_renderer *r, spm_error *err)
{
    if (r->bdpt)
        return spm_clr_bdpt_warm_up(r, err);
    if (r->light)
        return spm_clr_light_warm_up(r, err);
    /* the smallest launch, and the smallest at or over the limit */
    const size_t sizes[2] = {LOCAL_SIZE, (POCL_GRID_LIMIT + LOCAL_SIZE - 1) / LOCAL_SIZE * LOCAL_SIZE};
    int nsizes = strstr(r->cl.dev.platform_name, "Portable Computing Language") ? 2 : 1;
    int rc = 0;
    for (int k = 0; k < nsizes && !rc; k++) {
        batch b = {0, 1, 0, 0, 0, sizes[k]};
        cl_event ev[NSLOTS + 2] = {NULL};
        size_t off[NSLOTS + 1] = {0};
        rc = spm_clr_run_trace(r, &b, &ev[NSLOTS], err) ||
             spm_clr_run_shade(r, &b, off, r->ident, 1, ev, err) ||
             spm_clr_run_accumulate(r, &b, &ev[NSLOTS + 1], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(warm-up)", err);
        spm_clr_release_events(ev, NSLOTS + 2, NULL);
    }
    return rc;
}
