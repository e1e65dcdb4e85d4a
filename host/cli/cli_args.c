#include "cli_args.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int spm_arg_long(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (!*s || *end || errno || v < lo || v > hi) {
        fprintf(stderr, "specmip %s: %s needs a whole number from %ld to %ld, not '%s'\n", cmd, opt,
                lo, hi, s);
        return 1;
    }
    *out = v;
    return 0;
}

int spm_arg_double(const char *cmd, const char *opt, const char *s, double lo, double hi,
                   double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (!*s || *end || errno || !(v >= lo && v <= hi)) {
        fprintf(stderr, "specmip %s: %s needs a number from %g to %g, not '%s'\n", cmd, opt, lo, hi,
                s);
        return 1;
    }
    *out = v;
    return 0;
}

const spm_opt_range spm_opt_ranges[SPM_OPT_COUNT] = {
    [SPM_OPT_SEED] = {"--seed", 0, 4294967295.0, 1},
    /* up to 1e6: far above any colour difference, i.e. "always the coarsest level" */
    [SPM_OPT_THRESHOLD] = {"--threshold", 0, 1e6, 0},
};

int spm_opt_number(const char *cmd, spm_opt_id id, const char *s, double *out)
{
    const spm_opt_range *r = &spm_opt_ranges[id];
    if (!r->whole)
        return spm_arg_double(cmd, r->name, s, r->lo, r->hi, out);
    long n;
    if (spm_arg_long(cmd, r->name, s, (long)r->lo, (long)r->hi, &n))
        return 1;
    *out = (double)n;
    return 0;
}
