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

#endif
