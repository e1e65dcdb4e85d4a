/* The bench's CSV: one row per render. Rows go to DIR/bench.csv.part, each
 * flushed as soon as it is complete, so an interrupted study keeps every
 * finished row; spm_bench_csv_close renames the file to DIR/bench.csv. */
#ifndef SPM_BENCH_CSV_H
#define SPM_BENCH_CSV_H
#include <stdint.h>
#include <stdio.h>
#include "backend.h"
#include "compare.h"

typedef struct {
    const char *scene;     /* file name without directory and extension */
    const char *kind;      /* "main" (modes x spp), "equal" (modes x time budgets) or "sweep"
                              (ml over thresholds) */
    const char *mode;
    double threshold;      /* pretest threshold the tables were built with */
    int spp, width, height;
    unsigned seed;
    double wall_s;         /* whole render (spm_render_run), after a warm-up pass */
    double time_vs_ref;    /* wall_s / wall_s of ref at the same scene and spp; equal rows:
                              wall_s / budget_s */
    spm_pass_stats st;     /* kernel stage times, paths, per-level paths */
    spm_de_stats bias_ref, bias_truth; /* same seed: against ref and truth */
    spm_de_stats err;      /* against the converged truth (independent seed) */
    spm_de_stats noise;    /* two independent truth renders at this spp */
    int no_bias;           /* equal rows: the modes ran at different spp, so bias and noise
                              are not measured (their fields are left empty) */
    double conv_floor;     /* mean ΔE00 of two independent converged truth renders */
    int truth_spp;         /* spp of the converged truth */
    double budget;         /* equal rows: the budget as a multiple of ref's time at the base spp */
    double budget_s;       /* equal rows: that budget in seconds (from the calibration) */
    double s_per_spp;      /* equal rows: the mode's calibrated seconds per sample, from which
                              spp = budget_s / s_per_spp, rounded (at least 1) */
    double conv_floor_p99; /* p99 ΔE00 of the two converged truths */
    int compiled;          /* 1: PoCL compiled during the timed run kept in wall_s (its time
                              includes a compile), 0: it did not, -1: not watched (the CPU
                              backend, or no PoCL cache: pocl_cache.h) */
    int devices;           /* the backends (--device) that rendered passes of that run */
} spm_bench_row;

typedef struct {
    FILE *f;
    char part[4096], final[4096];
    int rows;
} spm_bench_csv;

/* The header names, comma-separated (also what the report script reads). */
extern const char spm_bench_csv_header[];

int spm_bench_csv_open(spm_bench_csv *c, const char *dir, spm_error *err);
int spm_bench_csv_write(spm_bench_csv *c, const spm_bench_row *r, spm_error *err);
/* Closes and renames the part file to bench.csv. */
int spm_bench_csv_close(spm_bench_csv *c, spm_error *err);
#endif
