/* `specmip bench --ops`: the operator micro-benchmark (kernels/opbench.cl).
 * Times multiply, scaled add, set and clear at each level's layout and at
 * truth and rgb; prints ns per operation (one operation = one whole spectrum)
 * and the ratio to level 0, writes DIR/ops.csv and the command to reproduce. */
#ifndef SPM_BENCH_OPS_H
#define SPM_BENCH_OPS_H
#include "util.h"

/* 0, or an exit code with err filled. */
/* Its program (built without options). */
extern const char spm_ops_program_file[];
int spm_bench_ops(int device, int items, int iters, const char *dir, spm_error *err);
#endif
