/* Pieces every sub-command's option handling shares: checked numbers, and
 * Ctrl-C / SIGTERM turned into a stop flag the render loops poll. */
#ifndef SPM_CLI_ARGS_H
#define SPM_CLI_ARGS_H
#include <signal.h>

/* A whole number / a number in [lo, hi]; otherwise prints
 * "specmip CMD: OPT needs ..." and returns 1. */
int spm_arg_long(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out);
int spm_arg_double(const char *cmd, const char *opt, const char *s, double lo, double hi,
                   double *out);

/* Set while SIGINT/SIGTERM are caught (between catch and release). */
extern volatile sig_atomic_t spm_stop_flag;
void spm_catch_interrupts(void);
void spm_release_interrupts(void);
#endif
