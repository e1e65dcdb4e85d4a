/* specmip: command dispatcher. */
#include <stdio.h>
#include <string.h>
#include "commands.h"
#include "util.h"

static const struct {
    const char *name;
    int (*run)(int, char **);
    const char *what;
} commands[] = {
    {"render", spm_cmd_render, "render a scene (default: the built-in Cornell box)"},
    {"spectrum", spm_cmd_spectrum, "colour of a spectrum file, its levels and the pretest's choice"},
    {"devices", spm_cmd_devices, "list OpenCL platforms and devices"},
    {"compare", spm_cmd_compare, "colour difference statistics between two images"},
    {"bench", spm_cmd_bench, "speed/accuracy study: CSV and charts"},
    {"modes", spm_cmd_modes, "list the spectral modes (--json for scripts)"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: specmip COMMAND [options]   (specmip COMMAND --help for its options)\n\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].what);
    fprintf(f, "  %-9s %s\n", "version", "print the version (also specmip --version)");
    fprintf(f, "\nWith no command, 'specmip' runs 'specmip render'.\n"
               "Exit codes: 0 ok, 1 runtime failure, 2 usage or input error, 130 interrupted.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        char *args[] = {"render", NULL};
        return spm_cmd_render(1, args);
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return SPM_EXIT_OK;
    }
    if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "version")) {
        printf("specmip %s\n", SPM_VERSION);
        return SPM_EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (!strcmp(argv[1], commands[i].name))
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "specmip: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return SPM_EXIT_INPUT;
}
