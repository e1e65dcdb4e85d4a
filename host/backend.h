/* A render backend renders passes: given the first sample index and the
 * samples per pixel of a pass, it returns the pass image (per pixel the XYZ
 * sum of its samples, added in sample order). The OpenCL devices and the CPU
 * reference are backends; the render loop does not know which it drives. */
#ifndef SPM_BACKEND_H
#define SPM_BACKEND_H
#include <signal.h>
#include <stdint.h>
#include "geometry.h"
#include "tables.h"

typedef struct {
    double trace_s, shade_s, accum_s;  /* stage times: kernel (event) time or CPU time */
    uint64_t paths;
    uint64_t level_paths[SPM_NUM_LEVELS][3]; /* paths shaded at each level, by SPM_SETBY_* */
    uint64_t truncated;                      /* paths that hit SPM_MAX_DEPTH */
    uint64_t nonfinite;                      /* samples with NaN/Inf XYZ, left out of the film */
    uint64_t untimed;                        /* kernel launches the device gave no time for:
                                                the stage times are then unknown */
} spm_pass_stats;

void spm_pass_stats_add(spm_pass_stats *into, const spm_pass_stats *s);

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

/* For backends: after each batch of a pass but the last. Reports progress,
 * honours the test pause "pass" (interrupt.h) and returns 1 when the pass is
 * to stop (c may be NULL). */
int spm_pass_batch_end(const spm_pass_ctl *c, uint64_t paths_so_far);

/* What every backend is built from. */
typedef struct {
    const spm_geometry *geom;
    const spm_tables *tables;
    int mode;       /* enum spm_mode */
    spm_u32 seed;
} spm_backend_input;

spm_backend *spm_backend_cpu_create(const spm_backend_input *in, spm_error *err);
/* OpenCL device `device` (index as `specmip devices` lists them). NULL on failure. */
spm_backend *spm_backend_cl_create(int device, const spm_backend_input *in, spm_error *err);
/* Per-path statistics shared by the backends: level counts from the level
 * bytes (all paths counted at level 0 in modes other than ml/mlc). */
void spm_count_levels(int mode, const spm_path *paths, const uint8_t *levels, size_t n,
                      spm_pass_stats *st);
/* Sum each pixel's samples (contiguous, in sample order) into pass_xyz,
 * leaving out and counting non-finite samples. */
void spm_accumulate_pass(const float *xyz, size_t npix, spm_u32 spp, float *pass_xyz,
                         spm_pass_stats *st);
#endif
