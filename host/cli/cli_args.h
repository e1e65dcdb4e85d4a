/* Pieces every sub-command's option handling shares: checked numbers, and
 * Ctrl-C / SIGTERM turned into a stop flag the long steps poll (interrupt.h). */
#ifndef SPM_CLI_ARGS_H
#define SPM_CLI_ARGS_H
#include "interrupt.h"
#include <stdio.h>

/* A whole number / a number in [lo, hi]; otherwise prints
 * "specmip CMD: OPT needs ..." and returns 1. */
int spm_arg_long(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out);
int spm_arg_double(const char *cmd, const char *opt, const char *s, double lo, double hi,
                   double *out);
/* A point "X,Y,Z" of three finite numbers; otherwise prints why, returns 1. */
int spm_arg_point(const char *cmd, const char *opt, const char *s, double out[3]);

/* The options of render, bench and spectrum, one table (cli_args.c): each
 * row names an option, the kind of its value, its range, the commands that
 * take it and its help text, from which the commands' help is printed; the
 * commands parse through spm_opt_next and store what it found. An option two
 * commands spell alike but mean differently (render's --spp N, bench's list)
 * has a row per meaning; one meaning has one range. */
typedef enum { SPM_CMD_RENDER = 1, SPM_CMD_BENCH = 2, SPM_CMD_SPECTRUM = 4 } spm_cmd_bit;
typedef enum {
    SPM_ARG_FLAG,  /* no value */
    SPM_ARG_INT,   /* a whole number in [lo, hi] */
    SPM_ARG_REAL,  /* a number in [lo, hi] */
    SPM_ARG_TEXT   /* a word the command reads (a list's numbers in [lo, hi]) */
} spm_arg_kind;
typedef enum {
    SPM_O_HELP, SPM_O_OUTPUT, SPM_O_SPECTRAL_NM, SPM_O_MODE, SPM_O_INTEGRATOR, SPM_O_SPP, SPM_O_SEED,
    SPM_O_WIDTH, SPM_O_HEIGHT, SPM_O_BACKEND, SPM_O_DEVICE, SPM_O_THRESHOLD, SPM_O_METRIC,
    SPM_O_COARSEST_LEVEL, SPM_O_TONEMAP, SPM_O_EXPOSURE, SPM_O_STATS, SPM_O_JSON,
    SPM_O_PROGRESS, SPM_O_QUIET, SPM_O_VERBOSE, SPM_O_ALLOW_PATH, SPM_O_WHITE, SPM_O_STRICT, SPM_O_DEFINE,
    SPM_O_TIME, SPM_O_CHECKPOINT, SPM_O_RESUME, SPM_O_FILM, SPM_O_LOOK_FROM, SPM_O_LOOK_AT,
    SPM_O_FOV, SPM_O_CAMERA, SPM_O_LIGHT_SAMPLER,
    /* bench */
    SPM_O_SCENES, SPM_O_MODES, SPM_O_TRUTH_SPP, SPM_O_SIZE, SPM_O_THRESHOLDS, SPM_O_SWEEP_SPP,
    SPM_O_BUDGETS, SPM_O_EQUAL_SPP, SPM_O_CALIB_SPP, SPM_O_BLUR, SPM_O_REPEAT, SPM_O_OUT,
    SPM_O_QUICK, SPM_O_NO_CHARTS, SPM_O_OPS, SPM_O_OPS_ITEMS, SPM_O_OPS_ITERS, SPM_O_RAYS,
    SPM_O_RAYS_SPP, SPM_O_RAYS_SAVE, SPM_O_RAYS_LOAD, SPM_O_RAYS_STATS, SPM_O_RAYS_GROUP,
    SPM_O_RAYS_PACKET, SPM_O_RAYS_QUANT, SPM_O_RAYS_SORT, SPM_O_RAYS_WAVEFRONT,
    SPM_O_EMBREE, SPM_O_THREADS, SPM_O_EMBREE_QUALITY,
    /* spectrum */
    SPM_O_COLUMN, SPM_O_ILLUMINANT, SPM_O_EMISSION, SPM_O_LEVEL
} spm_opt_id;
typedef struct {
    spm_opt_id id;
    const char *name;   /* "--output" */
    const char *alias;  /* "-o", or NULL */
    const char *value;  /* the value's name in the help ("FILE"); NULL for a flag */
    spm_arg_kind kind;
    double lo, hi;      /* INT, REAL and lists: the range; "%R" in help prints it */
    unsigned cmds;      /* spm_cmd_bit: the commands that take it */
    const char *label;  /* the help's left column, when not "NAME VALUE" */
    const char *help;   /* lines split by '\n'; NULL: told in the row before */
} spm_option;
extern const spm_option spm_options[];
extern const int spm_noptions;

/* A command's arguments, one at a time (spm_opt_each). */
typedef struct {
    unsigned cmd;          /* spm_cmd_bit */
    const char *name;      /* the command, in messages */
    int argc, i;
    char **argv;
    const spm_option *opt; /* the option, NULL: a positional argument (value) */
    const char *value;     /* its value, or the positional argument */
    double number;         /* an INT's or REAL's value, checked against its range */
} spm_opt_iter;
void spm_opt_start(spm_opt_iter *it, unsigned cmd, const char *name, int argc, char **argv);
/* The next argument: 1 with opt, value and number set, 0 at the end, -1 on
 * an unknown option, a missing value or one out of its range (the error on
 * stderr). */
int spm_opt_each(spm_opt_iter *it);
/* The options of `cmd`, help text in the column `col`. */
void spm_opt_help(FILE *f, unsigned cmd, int col);
/* --device's value, a device index, a list 0,2 or `all`, into devices[max]
 * (*n of them) or *all; 1 with the error on stderr. */
int spm_opt_devices(const char *name, const char *s, int *devices, int max, int *n, int *all);

#endif
