/* The speed/accuracy study behind `specmip bench`: for each scene,
 * every mode at several spp with the same seed (timed side by side), compared
 * against ref and truth of that seed (bias) and against a converged truth of
 * other seeds (error); then every mode at equal time (its spp chosen from a
 * short calibration run so that its render takes a multiple of ref's time at a
 * base spp), against the converged truth; then ml over a range of pretest
 * thresholds. */
#ifndef SPM_BENCH_STUDY_H
#define SPM_BENCH_STUDY_H
#include <signal.h>
#include "bench_csv.h"
#include "pretest.h"
#include "render_run.h"
#include "scene_camera.h"

#define SPM_BENCH_MAX_SPP 16
#define SPM_BENCH_MAX_THRESHOLDS 16
#define SPM_BENCH_MAX_BUDGETS 8

typedef struct {
    const char *const *scenes;
    int nscenes;
    int modes[SPM_MODE_COUNT];   /* rows are written for these (truth and ref always render) */
    int nmodes;
    int spps[SPM_BENCH_MAX_SPP]; /* ascending */
    int nspp;
    int truth_spp;               /* the converged truth */
    double thresholds[SPM_BENCH_MAX_THRESHOLDS]; /* the sweep (none: no sweep) */
    int nthresholds;
    int sweep_spp;               /* one of spps */
    double budgets[SPM_BENCH_MAX_BUDGETS]; /* equal time: multiples of ref's time at equal_spp,
                                              ascending (none: no equal-time part) */
    int nbudgets;
    int equal_spp;               /* the base spp whose ref time is the budget unit */
    int calib_spp;               /* the short run each mode's time per sample comes from */
    int width, height;           /* 0: the scene's */
    int blur;                    /* box blur before ΔE (odd, or 0/1 for none) */
    int repeat;                  /* timed renders run this often; the fastest counts */
    spm_u32 seed;
    int use_cpu;
    int devices[SPM_MAX_BACKENDS]; /* --device: a list (0 of them: device 0) or all */
    int ndevices, all_devices;
    spm_pretest_opts pretest;    /* the main rows' pretest (threshold) */
    spm_camera_override cam;     /* --look-from, --look-at, --fov */
    int progress;                /* 0: quiet, 1: one updating line (terminal), 2: a line per step */
    volatile sig_atomic_t *stop;
} spm_bench_plan;

/* Runs the plan, writing rows to csv as they finish. Returns 0, an exit code
 * (1 runtime, 2 input) with err filled, or SPM_EXIT_INTERRUPTED when stop was set. */
int spm_bench_study(const spm_bench_plan *p, spm_bench_csv *csv, spm_error *err);
#endif
