/* specmip: command dispatcher. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
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
    fprintf(f, "\nWith no command ('specmip', 'specmip SCENE [options]'), 'specmip' runs 'specmip render'.\n"
               "Every option also takes its value as --name=value.\n"
               "Exit codes: 0 ok, 1 runtime failure, 2 usage or input error, 130 interrupted.\n");
}

/* "--name=value" as two arguments, "--name" "value", for every command: the
 * commands' parsers then see one form. Only arguments starting with "--" are
 * split, so a file name holding '=' is kept whole. main frees the copy. */
static char **split_equals(int *argc, char **argv)
{
    int n = *argc;
    for (int i = 1; i < *argc; i++)
        n += argv[i][0] == '-' && argv[i][1] == '-' && strchr(argv[i], '=') != NULL;
    char **out = calloc((size_t)n + 1, sizeof *out);
    if (!out)
        return argv;
    int k = 0;
    for (int i = 0; i < *argc; i++) {
        char *eq = i && argv[i][0] == '-' && argv[i][1] == '-' ? strchr(argv[i], '=') : NULL;
        if (eq) {
            *eq = 0; /* argv's strings are the program's to modify (C11 5.1.2.2.1) */
            out[k++] = argv[i];
            out[k++] = eq + 1;
        } else {
            out[k++] = argv[i];
        }
    }
    *argc = k;
    return out;
}

/* What 'specmip SCENE ...' and 'specmip --option ...' mean: render (the
 * usage's "with no command"). A word that is neither a command, an option nor
 * a readable file or scene name stays an unknown command, so a typo such as
 * 'rendr' is not read as a scene. */
static int means_render(const char *a)
{
    size_t n = strlen(a);
    return a[0] == '-' || access(a, R_OK) == 0 || (n > 6 && !strcmp(a + n - 6, ".scene")) ||
           (n > 7 && !strcmp(a + n - 7, ".ml.txt"));
}

static int run(int argc, char **argv)
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
    if (means_render(argv[1])) {
        argv[0] = "render";
        return spm_cmd_render(argc, argv);
    }
    fprintf(stderr, "specmip: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return SPM_EXIT_INPUT;
}

int main(int argc, char **argv)
{
    char **args = split_equals(&argc, argv);
    int rc = run(argc, args);
    if (args != argv)
        free(args);
    return rc;
}
