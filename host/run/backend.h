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

/* A kind of backend (OpenCL, the CPU reference): how the set-up checks and
 * opens it. The kinds are listed above run/ (backends/backends.h), so that
 * run/ reaches a backend only through this interface. */
typedef struct {
    const char *name; /* --backend's value */
    int per_device;   /* one backend per device index (--device); else one, index ignored */
    int compiles;     /* builds kernels: PoCL's cache is watched during a timed render */
    int light;        /* renders --integrator light (render_plan.h SPM_INTEGRATOR_LIGHT) */
    int bdpt;         /* renders --integrator bdpt (SPM_INTEGRATOR_BDPT) */
    /* --device all: the indices it selects (at most max; more are warned of). */
    int (*all_devices)(int *list, int *n, int max, spm_error *err);
    /* Before anything is built: the device exists (its name into name[256]) and
     * a render of width x height, paths_per_pass paths a pass, fits its memory. */
    int (*check)(int device, const spm_render_plan *plan, int width, int height,
                 size_t paths_per_pass, char *name, spm_error *err);
    /* Built from a render plan (render_plan.h), which must outlive the backend.
     * NULL on failure, with err filled. */
    spm_backend *(*create)(int device, const spm_render_plan *plan, spm_error *err);
} spm_backend_kind;

/* For backends: after each batch of a pass but the last. Reports progress,
 * honours the test pause "pass" (interrupt.h) and returns 1 when the pass is
 * to stop (c may be NULL). */
int spm_pass_batch_end(const spm_pass_ctl *c, uint64_t paths_so_far);
#endif
