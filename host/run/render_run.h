/* The render loop: hands out passes to one or more backends (devices) running
 * in their own threads, and adds finished pass images to the film strictly in
 * pass order, so the image does not depend on which device rendered what.
 *
 * A chunk of work is one pass: samples [k*spp_per_pass, (k+1)*spp_per_pass)
 * of every pixel, the grid of passes depending on the image size alone; a
 * render from `start` samples (a resumed film) begins with the rest of the
 * grid pass `start` is in, and the last pass ends at spp. So a render that
 * stopped on the grid and was resumed adds the very passes, in the same order,
 * as one render to the same spp (docs/RENDERING.md). A device that fails is
 * dropped for the rest of the render and its pass goes back to the queue for
 * the others.
 *
 * A time budget (time_s) counts from the loop's start: a device takes a pass
 * only while its mean pass time says the pass ends within the budget (its
 * first pass measures it), and once the budget is spent the passes in flight
 * stop and are dropped; only a film without any pass waits for its first. The
 * thread that calls the loop watches it meanwhile and writes checkpoints.
 *
 * A test hook, active only when the environment sets it: SPECMIP_TEST_MEET=N
 * makes each backend, once it has taken its first pass, wait (at most 30 s)
 * until N backends have taken theirs, so that a test of several devices sees
 * every device render a pass however loaded the machine is (without it a
 * device that comes up first may take every pass of a small render). */
#ifndef SPM_RENDER_RUN_H
#define SPM_RENDER_RUN_H
#include <signal.h>
#include "backend.h"
#include "film.h"

#define SPM_MAX_BACKENDS 16


typedef struct {
    spm_pass_stats total;
    spm_pass_stats per_backend[SPM_MAX_BACKENDS];
    int passes_by_backend[SPM_MAX_BACKENDS];
    double busy_s[SPM_MAX_BACKENDS]; /* wall time each backend spent rendering its passes */
    int failed[SPM_MAX_BACKENDS];    /* a backend that failed: its passes went to the others */
    double wall_s;
    double cpu_s;                   /* process CPU time meanwhile: a CPU device's kernels count,
                                       so cpu_s / wall_s shows how many cores the render had */
    int npasses;                    /* passes the render was cut into */
    int passes_in_film;             /* passes added to the film (all of them unless cut short) */
    int spp_done;                   /* samples per pixel in the film (start included) */
    int passes_dropped;             /* finished beyond a gap and left out (o->contiguous) */
    int interrupted;
    int time_up;                    /* ended by the time budget before spp */
} spm_run_result;

typedef struct {
    int spp;                        /* samples per pixel in all (>= 1) */
    spm_u32 spp_per_pass;           /* samples per pixel in one pass (>= 1) */
    volatile sig_atomic_t *stop;    /* when set: passes in flight end at their next batch
                                       boundary and are dropped, no more are handed out */
    int progress;                   /* print a progress line on stderr */
    int start;                      /* samples per pixel already in the film (< spp) */
    double time_s;                  /* the loop's time budget in seconds; 0: none */
    int contiguous;                 /* cut short: passes beyond the first gap are dropped, so the
                                       film holds samples [0, spp_done) and can be resumed */
    /* Every checkpoint_s seconds, when passes were added since the last one:
     * checkpoint(ctx, copy of the film, the result so far), from the
     * watching thread while the devices go on. NULL: none. */
    double checkpoint_s;
    void (*checkpoint)(void *ctx, const spm_film *film, const spm_run_result *r);
    void *checkpoint_ctx;
} spm_run_opts;

/* Samples per pixel in one pass: enough paths per pass to fill a device
 * (~64K), depending only on the image size so any device split gives the same passes. */
spm_u32 spm_spp_per_pass(size_t npix, int spp);

/* The end game: near the end a slow device leaves the last passes to faster
 * ones rather than hold up the render with a pass of its own. A device that
 * renders a pass in t_me seconds takes one if it has no estimate yet (t_me <=
 * 0), if it is the fastest (the others' times t_other[0..n), 0 where unknown,
 * are none faster: someone must take it), or if the others together would
 * still be busy when it is done: t_me * sum(1 / t_other) <= work, where work
 * counts in passes what the others have ahead of them (the passes not handed
 * out and the unfinished part of those they are rendering). */
int spm_run_worth_taking(double t_me, const double *t_other, int n, double work);

/* Renders samples o->start to o->spp of every pixel into film (which holds
 * o->start samples) with backends b[0..nb). Returns 0;
 * or 1 with err filled when every backend failed before the end (the film then
 * holds every pass that was finished, added in pass order: nothing rendered is
 * lost) or the arguments are wrong. An interruption (o->stop) returns 0 with
 * r->interrupted set, the budget's end r->time_up. r is filled in every case. */
int spm_render_run(spm_backend **b, int nb, size_t npix, const spm_run_opts *o, spm_film *film,
                   spm_run_result *r, spm_error *err);

/* Finished pass images (3 + film->nspec floats a pixel) wait for any earlier
 * pass still in flight: a fast device runs ahead of a slow one by at most
 * max_waiting_bytes of them (but
 * always by two passes per device). spm_render_run allows 256 MiB. */
int spm_render_run_window(spm_backend **b, int nb, size_t npix, const spm_run_opts *o,
                          size_t max_waiting_bytes, spm_film *film, spm_run_result *r,
                          spm_error *err);
#endif
