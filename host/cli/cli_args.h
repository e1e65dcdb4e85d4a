/* Pieces every sub-command's option handling shares: checked numbers, and
 * Ctrl-C / SIGTERM turned into a stop flag the long steps poll (interrupt.h). */
#ifndef SPM_CLI_ARGS_H
#define SPM_CLI_ARGS_H
#include "interrupt.h"

/* A whole number / a number in [lo, hi]; otherwise prints
 * "specmip CMD: OPT needs ..." and returns 1. */
int spm_arg_long(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out);
int spm_arg_double(const char *cmd, const char *opt, const char *s, double lo, double hi,
                   double *out);

/* The numeric options several commands take, one range each, shared by
 * render, bench and spectrum (and their help text). Seeds are taken modulo
 * 2^32: bench's truth renders use S+1 and S+2, which wrap. */
typedef enum { SPM_OPT_SEED, SPM_OPT_THRESHOLD, SPM_OPT_COUNT } spm_opt_id;
typedef struct {
    const char *name; /* "--seed" */
    double lo, hi;
    int whole; /* a whole number */
} spm_opt_range;
extern const spm_opt_range spm_opt_ranges[SPM_OPT_COUNT];
/* S as option ID of command CMD within its range; otherwise prints
 * "specmip CMD: OPT needs ..." and returns 1. */
int spm_opt_number(const char *cmd, spm_opt_id id, const char *s, double *out);

#endif
