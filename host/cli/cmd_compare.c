/* specmip compare A B: colour difference statistics between two images. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "commands.h"
#include "compare.h"
#include "heatmap.h"
#include "image_io.h"
#include "output.h"
#include "util.h"

static void usage(FILE *f)
{
    fprintf(f,
        "usage: specmip compare A B [--blur N] [--white-y Y] [--heatmap OUT.png] [--json]\n\n"
        "Colour difference of image B against the reference A (EXR or anything OpenImageIO\n"
        "reads; float images are linear sRGB primaries, 8/16-bit images sRGB-encoded).\n"
        "Both are blurred with an N x N box (default 5; 0 or 1: none; near the border the\n"
        "mean over the part of the window inside the image), then compared per pixel in\n"
        "CIELAB with one white: D65 chromaticity, Yn = the 99.9th percentile of A's Y.\n\n"
        "  --blur N        box blur window side, odd (default 5)\n"
        "  --white-y Y     use Yn = Y instead of the percentile\n"
        "  --heatmap OUT   write a false-colour CIEDE2000 map with a colour bar (0-10)\n"
        "  --json          print one JSON object instead of the tables\n\n"
        "Prints mean, median, 95th/99th percentile and max of CIEDE2000 and Delta E*ab, and\n"
        "pixel counts in the disjoint buckets <1, 1-2, 2-3, 3-4, 4-5, >=5.\n"
        "Exit codes: 0 ok, 1 write failure, 2 usage or input error.\n");
}

static int parse_int(const char *s, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < 0 || v > 1000)
        return 1;
    *out = (int)v;
    return 0;
}

static void json_string(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            printf("\\%c", c);
        else if (c < 0x20)
            printf("\\u%04x", c);
        else
            putchar(c);
    }
    putchar('"');
}

static void json_stats(const char *prefix, const spm_de_stats *s)
{
    printf(", \"%smean\": %.6g, \"%smedian\": %.6g, \"%sp95\": %.6g, \"%sp99\": %.6g, "
           "\"%smax\": %.6g, \"%sbuckets\": [",
           prefix, s->mean, prefix, s->median, prefix, s->p95, prefix, s->p99, prefix, s->max,
           prefix);
    for (int i = 0; i < SPM_COMPARE_BUCKETS; i++)
        printf("%s%lld", i ? ", " : "", s->buckets[i]);
    printf("]");
}

static void print_json(const char *a, const char *b, const spm_compare_opts *o,
                       const spm_compare_result *r)
{
    printf("{\"a\": ");
    json_string(a);
    printf(", \"b\": ");
    json_string(b);
    printf(", \"width\": %d, \"height\": %d, \"blur\": %d, \"white_y\": %.6g, \"nonfinite\": %lld, "
           "\"bucket_upper\": [1, 2, 3, 4, 5]",
           r->width, r->height, o->blur, r->white_y, r->nonfinite);
    json_stats("", &r->de00);
    json_stats("dEab_", &r->deab);
    printf("}\n");
}

static void print_tables(const char *a, const char *b, const spm_compare_opts *o,
                         const spm_compare_result *r)
{
    printf("%s vs %s: %dx%d pixels, blur %d, white Yn = %.6g (%s)\n", a, b, r->width, r->height,
           o->blur, r->white_y, o->white_y > 0 ? "given" : "99.9th percentile of A");
    printf("%-6s %10s %10s %10s %10s %10s\n", "", "mean", "median", "p95", "p99", "max");
    const spm_de_stats *s[2] = {&r->de00, &r->deab};
    const char *name[2] = {"dE00", "dE*ab"};
    for (int k = 0; k < 2; k++)
        printf("%-6s %10.4f %10.4f %10.4f %10.4f %10.4f\n", name[k], s[k]->mean, s[k]->median,
               s[k]->p95, s[k]->p99, s[k]->max);
    printf("%-6s %9s %9s %9s %9s %9s %9s\n", "pixels", "<1", "<2", "<3", "<4", "<5", ">=5");
    for (int k = 0; k < 2; k++) {
        printf("%-6s", name[k]);
        for (int i = 0; i < SPM_COMPARE_BUCKETS; i++)
            printf(" %9lld", s[k]->buckets[i]);
        printf("\n");
    }
}

int spm_cmd_compare(int argc, char **argv)
{
    spm_compare_opts opts = {.blur = 5, .white_y = 0.0};
    const char *files[2] = {NULL, NULL}, *heatmap = NULL;
    int nfiles = 0, json = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        int has_value = i + 1 < argc;
        if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            usage(stdout);
            return SPM_EXIT_OK;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if (!strcmp(arg, "--blur") && has_value) {
            if (parse_int(argv[++i], &opts.blur) || (opts.blur > 1 && opts.blur % 2 == 0)) {
                fprintf(stderr, "specmip compare: --blur '%s' is not 0 or an odd size up to 999\n", argv[i]);
                return SPM_EXIT_INPUT;
            }
        } else if (!strcmp(arg, "--white-y") && has_value) {
            char *end;
            opts.white_y = strtod(argv[++i], &end);
            if (end == argv[i] || *end || !isfinite(opts.white_y) || opts.white_y <= 0) {
                fprintf(stderr, "specmip compare: --white-y '%s' is not a positive number\n", argv[i]);
                return SPM_EXIT_INPUT;
            }
        } else if (!strcmp(arg, "--heatmap") && has_value) {
            heatmap = argv[++i];
        } else if (arg[0] == '-' && arg[1]) {
            fprintf(stderr, "specmip compare: unknown option or missing value: %s\n", arg);
            usage(stderr);
            return SPM_EXIT_INPUT;
        } else if (nfiles < 2) {
            files[nfiles++] = arg;
        } else {
            fprintf(stderr, "specmip compare: more than two images given ('%s')\n", arg);
            return SPM_EXIT_INPUT;
        }
    }
    if (nfiles != 2) {
        fprintf(stderr, "specmip compare: two images are needed\n");
        usage(stderr);
        return SPM_EXIT_INPUT;
    }
    spm_error err;
    if (heatmap && spm_output_check(heatmap, &err)) {
        fprintf(stderr, "specmip compare: %s\n", err.msg);
        return SPM_EXIT_INPUT;
    }
    spm_image img[2] = {{0, 0, NULL, 0}, {0, 0, NULL, 0}};
    spm_compare_result res = {0};
    int rc = SPM_EXIT_OK;
    for (int k = 0; k < 2 && rc == SPM_EXIT_OK; k++)
        if (spm_image_read(files[k], &img[k], &err))
            rc = SPM_EXIT_INPUT;
    if (rc == SPM_EXIT_OK && spm_compare_images(&img[0], &img[1], &opts, &res, &err))
        rc = SPM_EXIT_INPUT;
    if (rc != SPM_EXIT_OK) {
        fprintf(stderr, "specmip compare: %s\n", err.msg);
    } else {
        if (res.nonfinite)
            spm_warnf("%lld NaN/Inf values in the images were replaced by 0", res.nonfinite);
        if (img[0].encoded != img[1].encoded) {
            int e = img[1].encoded;
            spm_warnf("%s is linear light and %s display-encoded integer codes (decoded as sRGB): "
                      "a render's linear image against a tone-mapped one differs by the tone "
                      "mapping too; compare like with like (two .exr, or two .png)",
                      files[e ? 0 : 1], files[e ? 1 : 0]);
        }
        if (json)
            print_json(files[0], files[1], &opts, &res);
        else
            print_tables(files[0], files[1], &opts, &res);
        if (heatmap && spm_heatmap_write(heatmap, res.width, res.height, res.de00_map, &err)) {
            fprintf(stderr, "specmip compare: %s\n", err.msg);
            rc = SPM_EXIT_RUNTIME;
        }
    }
    spm_compare_result_free(&res);
    spm_image_free(&img[0]);
    spm_image_free(&img[1]);
    return rc;
}
