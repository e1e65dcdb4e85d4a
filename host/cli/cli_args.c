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
