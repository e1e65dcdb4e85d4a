/* `specmip spectrum`: the colour of a spectrum file, its error at each level
 * and the level the pretest chooses for it. */
#include "cli_args.h"
#include "colour.h"
#include "commands.h"
#include "csv.h"
#include "pretest.h"
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct {
    const char *file, *column, *illum;
    int emission, level, json;
    spm_pretest_opts pt;
} options;

/* One spectrum's results. */
typedef struct {
    double xyz[3], lab[3], lin[3], enc[3];
    double de00[SPM_NUM_LEVELS], deab[SPM_NUM_LEVELS];
    spm_pretest_result pt;
} report;

static void help(FILE *f)
{
    fprintf(f,
            "usage: specmip spectrum FILE [--column NAME] [--illuminant NAME|FILE] [--emission]\n"
            "                        [--level L] [--threshold T] [--metric de00|deab] [--json]\n"
            "\n"
            "Prints the colour of a spectrum in a CSV file (first column wavelength in nm,\n"
            "'#' lines are comments, then a required header line of distinct column names)\n"
            "and its spectral levels.\n"
            "\n"
            "  FILE               the spectrum; a file with several value columns prints each\n"
            "                     column on its own unless --column picks one; a bare name\n"
            "                     not found here is looked for in the bundled spectra/\n");
    spm_opt_help(f, SPM_CMD_SPECTRUM, 21);
    fprintf(f,
            "\n"
            "sRGB is the IEC 61966-2-1 encoding of XYZ/100, without chromatic adaptation.\n"
            "The levels table gives each level's difference to level 0, the 1 nm truth (same\n"
            "illuminant and white). The pretest (reflectance with the illuminant, or a light\n"
            "alone; levels 0..3) picks the coarsest level whose worst error stays within the\n"
            "threshold.\n"
            "Exit codes: 0 ok, 2 usage or input error (bad files are reported as file:line).\n");
}

static int usage_error(const char *fmt, const char *arg)
{
    fputs("specmip spectrum: ", stderr);
    fprintf(stderr, fmt, arg);
    fputs("\n(specmip spectrum --help lists the options)\n", stderr);
    return SPM_EXIT_INPUT;
}

/* Returns -1 to go on, otherwise the exit code. */
/* FILE as given if it can be read or names a folder; otherwise a bare name is
 * looked for in the bundled spectra/ as a scene's spectrum files and
 * --illuminant are (the error, if neither is there, names FILE as given). */
static const char *bundled_file(const char *file)
{
    static char path[4096];
    if (access(file, R_OK) == 0 || strchr(file, '/'))
        return file;
    char rel[1100];
    snprintf(rel, sizeof rel, "spectra/%s", file);
    return access(spm_data_path(rel, path, sizeof path), R_OK) == 0 ? path : file;
}

static int parse_args(int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->illum = "D65";
    o->level = -1;
    spm_pretest_defaults(&o->pt);
    spm_opt_iter it;
    int more;
    for (spm_opt_start(&it, SPM_CMD_SPECTRUM, "spectrum", argc, argv); (more = spm_opt_each(&it)) > 0;) {
        if (!it.opt && o->file)
            return usage_error("more than one FILE ('%s')", it.value);
        if (!it.opt) {
            o->file = it.value;
            continue;
        }
        switch (it.opt->id) {
        case SPM_O_HELP: help(stdout); return SPM_EXIT_OK;
        case SPM_O_EMISSION: o->emission = 1; break;
        case SPM_O_JSON: o->json = 1; break;
        case SPM_O_COLUMN: o->column = it.value; break;
        case SPM_O_ILLUMINANT: o->illum = it.value; break;
        case SPM_O_LEVEL: o->level = (int)it.number; break;
        case SPM_O_THRESHOLD: o->pt.threshold = it.number; break;
        case SPM_O_METRIC:
            if (strcmp(it.value, "de00") && strcmp(it.value, "deab"))
                return usage_error("--metric takes de00 or deab, not '%s'", it.value);
            o->pt.metric = !strcmp(it.value, "deab") ? SPM_METRIC_DEAB : SPM_METRIC_DE00;
            break;
        default: break;
        }
    }
    if (more < 0)
        return SPM_EXIT_INPUT;
    if (!o->file)
        return usage_error("%s", "missing FILE");
    o->file = bundled_file(o->file);
    return -1;
}

/* A bundled illuminant's file by name, preferring the 1 nm tables. */
static int find_illuminant(const char *name, char *path, size_t size)
{
    char upper[128], lower[128]; /* CIE names are upper case, NIST lamps lower case */
    size_t n = strlen(name);
    if (n == 0 || n >= sizeof lower)
        return 1;
    for (size_t i = 0; i <= n; i++) {
        upper[i] = (char)toupper((unsigned char)name[i]);
        lower[i] = (char)tolower((unsigned char)name[i]);
    }
    const char *nist = strncmp(lower, "nist_", 5) ? lower : lower + 5;
    char rel[256];
    const char *patterns[] = {"spectra/illuminant_%s_1nm.csv", "spectra/illuminant_%s.csv",
                              "spectra/lightsource_nist_%s.csv"};
    for (int p = 0; p < 3; p++) {
        snprintf(rel, sizeof rel, patterns[p], p == 2 ? nist : upper);
        if (access(spm_data_path(rel, path, size), R_OK) == 0)
            return 0;
    }
    return 1;
}

static int load_illuminant(const char *arg, spm_spectrum *out, spm_error *err)
{
    char path[4096];
    size_t n = strlen(arg);
    int is_file = strchr(arg, '/') || (n > 4 && !strcmp(arg + n - 4, ".csv"));
    if (!is_file && find_illuminant(arg, path, sizeof path)) {
        spm_errorf(err,
                   "unknown illuminant '%s' (a name such as A, D50, D65, F1..F12, HP1, "
                   "LED_B1, nist_mercury, or a path ending in .csv)",
                   arg);
        return 1;
    }
    return spm_spectrum_load(is_file ? arg : path, NULL, SPM_KIND_EMISSION, out, err);
}

/* XYZ of s at level l (the light at level 0, 1 nm), with 1 nm weights. */
static void level_xyz(const spm_spectrum *s, int l, const double *light, double scale,
                      double xyz[3])
{
    double bins[SPM_TRUTH_BINS], prod[SPM_TRUTH_BINS];
    int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(l);
    spm_spectrum_level(s, l, bins);
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        prod[b] = bins[b / w] * light[b];
    spm_xyz_bins(prod, 0, xyz);
    for (int k = 0; k < 3; k++)
        xyz[k] *= scale;
}

static void analyse(const spm_spectrum *s, const spm_spectrum *illum, const options *o,
                    report *r)
{
    double light[SPM_TRUTH_BINS], white[3], scale;
    if (s->kind == SPM_KIND_EMISSION) {
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            light[b] = 1.0;
        double y0[3];
        level_xyz(s, 0, light, 1.0, y0);
        scale = y0[1] > 0 ? 100.0 / y0[1] : 0.0;
        spm_white_d65(white);
        for (int k = 0; k < 3; k++)
            white[k] *= 100.0;
    } else {
        spm_spectrum one;
        spm_spectrum_constant(1.0, SPM_KIND_REFLECTANCE, &one);
        spm_spectrum_level(illum, 0, light);
        level_xyz(&one, 0, light, 1.0, white);
        scale = white[1] > 0 ? 100.0 / white[1] : 0.0;
        for (int k = 0; k < 3; k++)
            white[k] *= scale;
    }
    /* Each level against level 0, same light and white. */
    double lab0[3], xyz[3], lab[3];
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        level_xyz(s, l, light, scale, xyz);
        spm_xyz_to_lab(xyz, white, l == 0 ? lab0 : lab);
        r->de00[l] = l == 0 ? 0.0 : spm_delta_e_2000(lab0, lab);
        r->deab[l] = l == 0 ? 0.0 : spm_delta_e_ab(lab0, lab);
    }
    /* The reported colour: from the 1 nm truth, or from --level. */
    if (o->level >= 0) {
        level_xyz(s, o->level, light, scale, r->xyz);
        spm_xyz_to_lab(r->xyz, white, r->lab);
    } else if (s->kind == SPM_KIND_EMISSION) {
        spm_xyz_emission(s, r->xyz);
        double f = r->xyz[1] > 0 ? 100.0 / r->xyz[1] : 0.0;
        for (int k = 0; k < 3; k++)
            r->xyz[k] *= f;
        spm_xyz_to_lab(r->xyz, white, r->lab);
    } else {
        spm_spectrum one;
        spm_spectrum_constant(1.0, SPM_KIND_REFLECTANCE, &one);
        double w[3];
        spm_xyz_reflectance(s, illum, r->xyz);
        spm_xyz_reflectance(&one, illum, w);
        spm_xyz_to_lab(r->xyz, w, r->lab);
    }
    double xyz1[3] = {r->xyz[0] / 100.0, r->xyz[1] / 100.0, r->xyz[2] / 100.0};
    spm_xyz_to_linear_srgb(xyz1, r->lin);
    for (int k = 0; k < 3; k++)
        r->enc[k] = spm_srgb_encode(r->lin[k]);
    const spm_spectrum *set[2] = {s, illum};
    spm_pretest_result res[2];
    spm_pretest_run(set, s->kind == SPM_KIND_EMISSION ? 1 : 2, &o->pt, res);
    r->pt = res[0];
}

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

static void json_vec(FILE *f, const char *key, const double v[3])
{
    fprintf(f, "\"%s\": [%.6f, %.6f, %.6f]", key, v[0], v[1], v[2]);
}

static void print_json(FILE *f, const char *name, const options *o, const report *r)
{
    fputs("{\"name\": ", f);
    json_string(f, name);
    fprintf(f, ", \"kind\": \"%s\", \"illuminant\": ", o->emission ? "emission" : "reflectance");
    if (o->emission)
        fputs("null", f);
    else
        json_string(f, o->illum);
    fprintf(f, ", \"from_level\": ");
    if (o->level >= 0)
        fprintf(f, "%d, ", o->level);
    else
        fputs("\"truth\", ", f);
    json_vec(f, "XYZ", r->xyz);
    fputs(", ", f);
    json_vec(f, "Lab", r->lab);
    fputs(", \"sRGB\": {", f);
    json_vec(f, "linear", r->lin);
    fputs(", ", f);
    json_vec(f, "encoded", r->enc);
    fputs("}, \"levels\": [", f);
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        fprintf(f, "%s{\"level\": %d, \"bins\": %d, \"dE00\": %.6f, \"dEab\": %.6f}",
                l ? ", " : "", l, SPM_LEVEL_BINS(l), r->de00[l], r->deab[l]);
    fprintf(f, "], \"chosen_level\": %d, \"level_k\": [", r->pt.level);
    for (int k = 0; k < SPM_PRETEST_KMAX; k++)
        fprintf(f, "%s%d", k ? ", " : "", r->pt.level_k[k]);
    fprintf(f, "], \"metric\": \"%s\", \"threshold\": %g}",
            o->pt.metric == SPM_METRIC_DEAB ? "deab" : "de00", o->pt.threshold);
}

static void print_text(FILE *f, const char *name, const options *o, const report *r)
{
    if (o->emission)
        fprintf(f, "%s: emission (scaled to Y = 100; Lab white D65)\n", name);
    else
        fprintf(f, "%s: reflectance under %s (white Y = 100)\n", name, o->illum);
    fprintf(f, "  from         %s\n", o->level >= 0 ? "the --level bins" : "1 nm truth");
    fprintf(f, "  XYZ          %10.4f %10.4f %10.4f\n", r->xyz[0], r->xyz[1], r->xyz[2]);
    fprintf(f, "  Lab          %10.4f %10.4f %10.4f\n", r->lab[0], r->lab[1], r->lab[2]);
    fprintf(f, "  sRGB linear  %10.4f %10.4f %10.4f\n", r->lin[0], r->lin[1], r->lin[2]);
    fprintf(f, "  sRGB         %10.4f %10.4f %10.4f  (8-bit %d %d %d)\n", r->enc[0], r->enc[1],
            r->enc[2], (int)(r->enc[0] * 255 + 0.5), (int)(r->enc[1] * 255 + 0.5),
            (int)(r->enc[2] * 255 + 0.5));
    fprintf(f, "  level  bins    dE00    dEab   (against level 0, 1 nm)\n");
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        fprintf(f, "  %5d  %4d  %6.3f  %6.3f\n", l, SPM_LEVEL_BINS(l), r->de00[l], r->deab[l]);
    fprintf(f, "  chosen level %d\n", r->pt.level);
    const char *names[1] = {name};
    spm_pretest_print(f, names, &r->pt, 1, &o->pt);
}

int spm_cmd_spectrum(int argc, char **argv)
{
    options o;
    int rc = parse_args(argc, argv, &o);
    if (rc >= 0)
        return rc;
    spm_error err;
    spm_spectrum illum, s;
    spm_csv csv;
    spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &illum); /* unused for an emission */
    if (spm_cmf_init(&err)) {
        fprintf(stderr, "specmip: %s\n", err.msg);
        return SPM_EXIT_RUNTIME;
    }
    if (!o.emission && load_illuminant(o.illum, &illum, &err)) {
        fprintf(stderr, "specmip: %s\n", err.msg);
        return SPM_EXIT_INPUT;
    }
    if (spm_csv_load(o.file, &csv, &err)) {
        fprintf(stderr, "specmip: %s\n", err.msg);
        return SPM_EXIT_INPUT;
    }
    int first = 1, last = csv.ncols - 1;
    if (o.column) {
        first = last = spm_csv_column(&csv, o.column);
        if (first < 0) {
            fprintf(stderr, "specmip: %s:%d: no column named '%s'\n", o.file, csv.header_line,
                    o.column);
            spm_csv_free(&csv);
            return SPM_EXIT_INPUT;
        }
    }
    int many = last > first;
    spm_kind kind = o.emission ? SPM_KIND_EMISSION : SPM_KIND_REFLECTANCE;
    report *reps = spm_xcalloc((size_t)(last - first + 1), sizeof *reps);
    /* Check every column before printing anything: a bad file prints only its error. */
    for (int c = first; c <= last && rc < 0; c++) {
        if (spm_spectrum_from_csv(&csv, c, o.file, kind, &s, &err)) {
            fprintf(stderr, "specmip: %s\n", err.msg);
            rc = SPM_EXIT_INPUT;
        } else {
            analyse(&s, &illum, &o, &reps[c - first]);
        }
    }
    if (rc < 0) {
        rc = SPM_EXIT_OK;
        if (o.json && many)
            fputs("[\n", stdout);
        for (int c = first; c <= last; c++) {
            char name[2048];
            if (many || o.column)
                snprintf(name, sizeof name, "%s:%s", o.file, csv.names[c]);
            else
                snprintf(name, sizeof name, "%s", o.file);
            if (o.json) {
                print_json(stdout, name, &o, &reps[c - first]);
                fputs(many && c < last ? ",\n" : "\n", stdout);
            } else {
                print_text(stdout, name, &o, &reps[c - first]);
            }
        }
        if (o.json && many)
            fputs("]\n", stdout);
    }
    free(reps);
    spm_csv_free(&csv);
    return rc;
}
