/* specmip bench: placeholder until the study lands (issue 6). */
#include <stdio.h>
#include "commands.h"
#include "util.h"

int spm_cmd_bench(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "specmip bench: not implemented yet\n");
    return SPM_EXIT_RUNTIME;
}
