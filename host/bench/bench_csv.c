#include "bench_csv.h"
#include <errno.h>
#include <string.h>
#include "interrupt.h"

#define DE_COLS(p) p "_mean," p "_p99," p "_max"
const char spm_bench_csv_header[] =
    "scene,kind,mode,threshold,spp,width,height,seed,wall_s,time_vs_ref,kernel_s,trace_s,"
    "shade_s,paths,paths_per_s,l0_paths,l1_paths,l2_paths,l3_paths,l4_paths,truncated," DE_COLS("bias_ref")
    "," DE_COLS("bias_truth") "," DE_COLS("err") "," DE_COLS("noise") ",conv_floor_mean,truth_spp,budget,budget_s,conv_floor_p99,"
    "compiled_during_timing,s_per_spp,devices";

int spm_bench_csv_open(spm_bench_csv *c, const char *dir, spm_error *err)
{
    snprintf(c->final, sizeof c->final, "%s/bench.csv", dir);
    snprintf(c->part, sizeof c->part, "%s/bench.csv.part", dir);
    c->rows = 0;
    c->f = fopen(c->part, "w");
    if (!c->f) {
        spm_errorf(err, "%s: %s", c->part, strerror(errno));
        return 1;
    }
    fprintf(c->f, "%s\n", spm_bench_csv_header);
    fflush(c->f);
    return 0;
}

static void de(FILE *f, const spm_de_stats *s)
{
    fprintf(f, ",%.5f,%.5f,%.5f", s->mean, s->p99, s->max);
}

int spm_bench_csv_write(spm_bench_csv *c, const spm_bench_row *r, spm_error *err)
{
    const spm_pass_stats *t = &r->st;
    FILE *f = c->f;
    fprintf(f, "%s,%s,%s,%g,%d,%d,%d,%u,%.6f,%.4f,%.6f,%.6f,%.6f,%llu,%.1f", r->scene, r->kind,
            r->mode, r->threshold, r->spp, r->width, r->height, r->seed, r->wall_s, r->time_vs_ref,
            t->trace_s + t->shade_s + t->accum_s, t->trace_s, t->shade_s,
            (unsigned long long)t->paths, r->wall_s > 0 ? (double)t->paths / r->wall_s : 0.0);
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        const uint64_t *lp = t->level_paths[l];
        fprintf(f, ",%llu", (unsigned long long)(lp[0] + lp[1] + lp[2]));
    }
    fprintf(f, ",%llu", (unsigned long long)t->truncated);
    if (r->no_bias) {
        fprintf(f, ",,,,,,");
    } else {
        de(f, &r->bias_ref);
        de(f, &r->bias_truth);
    }
    de(f, &r->err);
    if (r->no_bias)
        fprintf(f, ",,,");
    else
        de(f, &r->noise);
    fprintf(f, ",%.5f,%d,%g,%.9g,%.5f,%d,%.9g,%d\n", r->conv_floor, r->truth_spp, r->budget,
            r->budget_s, r->conv_floor_p99, r->compiled, r->s_per_spp, r->devices);
    if (fflush(f) || ferror(f)) {
        spm_errorf(err, "%s: write failed: %s", c->part, strerror(errno));
        return 1;
    }
    c->rows++;
    spm_test_pause("row");
    return 0;
}

int spm_bench_csv_close(spm_bench_csv *c, spm_error *err)
{
    if (!c->f)
        return 0;
    int bad = fclose(c->f) != 0;
    c->f = NULL;
    if (bad || rename(c->part, c->final)) {
        spm_errorf(err, "%s: %s", c->final, strerror(errno));
        return 1;
    }
    return 0;
}
