/* `specmip modes`: the spectral modes, for people and scripts. */
#include <stdio.h>
#include <string.h>
#include "commands.h"
#include "modes.h"
#include "util.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: specmip modes [--json]\n\n"
               "Lists the spectral modes 'specmip render --mode' takes, one a line:\n"
               "NAME, TAB, 'levelled' (each path is shaded at its own level) or 'single',\n"
               "TAB, what it is. --json prints an array of {name, levelled, composite,\n"
               "per_path, help} instead.\n");
}

int spm_cmd_modes(int argc, char **argv)
{
    int json = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return SPM_EXIT_OK;
        }
        if (!strcmp(argv[i], "--json")) {
            json = 1;
            continue;
        }
        fprintf(stderr, "specmip modes: unknown option '%s'\n", argv[i]);
        usage(stderr);
        return SPM_EXIT_INPUT;
    }
    spm_modes_print(stdout, json);
    return SPM_EXIT_OK;
}
