/* A render backend renders passes: given the first sample index and the
 * samples per pixel of a pass, it returns the pass image (per pixel the XYZ
 * sum of its samples, added in sample order). The OpenCL devices and the CPU
 * reference are backends; the render loop does not know which it drives. */
#ifndef SPM_BACKEND_H
#define SPM_BACKEND_H
#include "render_plan.h"

typedef struct spm_backend spm_backend;
struct spm_backend {
    char name[256];
    int (*pass)(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                spm_pass_stats *st, spm_error *err);
    void (*destroy)(spm_backend *b);
    void *impl;
};

/* Every backend is built from a render plan (render_plan.h), which must
 * outlive it. NULL on failure, with err filled. */
spm_backend *spm_backend_cpu_create(const spm_render_plan *plan, spm_error *err);
/* OpenCL device `device` (index as `specmip devices` lists them). */
spm_backend *spm_backend_cl_create(int device, const spm_render_plan *plan, spm_error *err);
#endif
