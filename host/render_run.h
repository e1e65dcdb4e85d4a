/* The render loop: hands out passes to one or more backends (devices) running
 * in their own threads, and adds finished pass images to the film strictly in
 * pass order, so the image does not depend on which device rendered what. */
#ifndef SPM_RENDER_RUN_H
#define SPM_RENDER_RUN_H
#include <signal.h>
#include "backend.h"
#include "film.h"

typedef struct {
    int spp;                        /* samples per pixel in all */
    spm_u32 spp_per_pass;           /* samples per pixel in one pass */
    volatile sig_atomic_t *stop;    /* when set: finish passes in flight, hand out no more */
    int progress;                   /* print a progress line on stderr */
} spm_run_opts;

typedef struct {
    spm_pass_stats total;
    spm_pass_stats per_backend[16];
    int passes_by_backend[16];
    int failed[16];                 /* a backend that failed: its passes went to the others */
    double wall_s;
    int spp_done;                   /* samples per pixel in the film */
    int interrupted;
} spm_run_result;

#define SPM_MAX_BACKENDS 16

/* Samples per pixel in one pass: enough paths per pass to fill a device
 * (~64K), depending only on the image size so any device split gives the same passes. */
spm_u32 spm_spp_per_pass(size_t npix, int spp);

int spm_render_run(spm_backend **b, int nb, size_t npix, const spm_run_opts *o, spm_film *film,
                   spm_run_result *r, spm_error *err);
#endif
