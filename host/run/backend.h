/* A render backend renders passes: given the first sample index and the
 * samples per pixel of a pass, it returns the pass image (per pixel the XYZ
 * sum of its samples, added in sample order). The OpenCL devices and the CPU
 * reference are backends; the render loop does not know which it drives. */
#ifndef SPM_BACKEND_H
#define SPM_BACKEND_H
#include <signal.h>
#include "render_plan.h"

/* How the render loop follows a pass and stops it between batches (a pass is
 * rendered in batches of whole pixels). All zero: the pass runs to its end. */
typedef struct {
    volatile sig_atomic_t *stop; /* set: the pass ends at its next batch boundary */
    void (*batch_done)(void *ctx, uint64_t paths); /* the pass's paths done so far */
    void *ctx;
} spm_pass_ctl;

/* What pass() returns when ctl.stop ended it early: not a failure, but the
 * pass image is incomplete and must be dropped. */
#define SPM_PASS_STOPPED 2

typedef struct spm_backend spm_backend;
struct spm_backend {
    char name[256];
    /* 0, SPM_PASS_STOPPED, or 1 with err filled */
    int (*pass)(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                spm_pass_stats *st, spm_error *err);
    void (*destroy)(spm_backend *b);
    void *impl;
    spm_pass_ctl ctl; /* set by the render loop for its passes */
};

/* Every backend is built from a render plan (render_plan.h), which must
 * outlive it. NULL on failure, with err filled. */
spm_backend *spm_backend_cpu_create(const spm_render_plan *plan, spm_error *err);
/* OpenCL device `device` (index as `specmip devices` lists them). */
spm_backend *spm_backend_cl_create(int device, const spm_render_plan *plan, spm_error *err);
/* For backends: after each batch of a pass but the last. Reports progress,
 * honours the test pause "pass" (interrupt.h) and returns 1 when the pass is
 * to stop (c may be NULL). */
int spm_pass_batch_end(const spm_pass_ctl *c, uint64_t paths_so_far);
#endif
