#include "cli_args.h"
#include "modes.h"
#include "render_run.h"
#include "scene_build.h"
#include <errno.h>
#include <math.h>
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

int spm_arg_point(const char *cmd, const char *opt, const char *s, double out[3])
{
    const char *at = s;
    for (int k = 0; k < 3; k++) {
        char *end;
        errno = 0;
        out[k] = strtod(at, &end);
        if (end == at || errno || !(fabs(out[k]) <= SPM_SCENE_MAX_COORD) ||
            *end != (k < 2 ? ',' : 0)) {
            fprintf(stderr, "specmip %s: %s needs a point X,Y,Z (three numbers within +-%g), "
                            "not '%s'\n", cmd, opt, SPM_SCENE_MAX_COORD, s);
            return 1;
        }
        at = end + 1;
    }
    return 0;
}

#define R SPM_CMD_RENDER
#define B SPM_CMD_BENCH
#define S SPM_CMD_SPECTRUM
#define ROW(id, name, value, kind, lo, hi, cmds, help) \
    {SPM_O_##id, name, NULL, value, SPM_ARG_##kind, lo, hi, cmds, NULL, help}
/* The order is each command's help order. */
const spm_option spm_options[] = {
    /* render */
    {SPM_O_OUTPUT, "--output", "-o", "FILE", SPM_ARG_TEXT, 0, 0, R, NULL,
     "image to write, by extension: .exr, .tif or .hdr (linear sRGB,\n"
     "float; EXR keeps how it was made in its header; .hdr drops\n"
     "negative values) or .png, .ppm or .jpg (tone-mapped sRGB,\n"
     "8-bit); up to 4 times, each file once (default:\n"
     "specmip.png and specmip.exr); a symbolic link is written\n"
     "through to its target; a name ending in .spectral.exr gets\n"
     "the spectrum of every pixel (OpenEXR spectral layout, absolute\n"
     "radiance; every mode but rgb)"},
    ROW(SPECTRAL_NM, "--spectral-nm", "N", TEXT, 1, 5, R,
        "bin width of a .spectral.exr: 5 (default) or, in truth mode, 1"),
    ROW(MODE, "--mode", "M", TEXT, 0, 0, R,
        "spectral mode (default ml; 'specmip modes' lists them):"),
    ROW(INTEGRATOR, "--integrator", "I", TEXT, 0, 0, R,
        "path (default: camera paths with next-event estimation) |\n"
        "light (subpaths from the lights, each vertex splatted into\n"
        "the pixel that sees it) |\n"
        "bdpt (both joined in every way, weighed by MIS)"),
    ROW(LIGHT_SAMPLER, "--light-sampler", "S", TEXT, 0, 0, R,
        "how next-event estimation picks a light: tree (a light tree,\n"
        "by power, distance and orientation to the shading point) |\n"
        "power (in proportion to power); default tree for a scene of\n"
        "at least 64 placed lights, else power"),
    ROW(SPP, "--spp", "N", INT, 1, SPM_SCENE_MAX_SPP, R,
        "samples per pixel, %R (default: the scene's, else 16)"),
    ROW(TIME, "--time", "SECONDS", REAL, 0.01, 1e7, R,
        "render for this long (%R s): passes are begun while they end\n"
        "within it, each device's first pass measuring its speed; the\n"
        "rendering alone counts (not loading, kernel builds or writing);\n"
        "with --spp both limits apply, else only the time does"),
    ROW(CHECKPOINT, "--checkpoint", "SECONDS", REAL, 0.1, 1e7, R,
        "every SECONDS (%R) write every output and the film (as\n"
        "--film) as the render goes, each file replaced whole"),
    ROW(FILM, "--film", NULL, FLAG, 0, 0, R,
        "keep the film (the per-pixel sums) beside the first .exr output\n"
        "as NAME.exr.film, named in its header, so that --resume can\n"
        "continue the render"),
    ROW(RESUME, "--resume", "OUT.exr", TEXT, 0, 0, R,
        "continue the render whose EXR this is from its film, to --spp\n"
        "or for --time: the same scene and options (refused, naming\n"
        "what differs, if not); the outputs default to OUT.exr"),
    /* bench */
    ROW(SCENES, "--scenes", "A,B,...", TEXT, 0, 0, B,
        "scene files (default: the bundled scenes/*.scene)"),
    ROW(MODES, "--modes", "M,...", TEXT, 0, 0, B,
        "modes with rows (default: every mode, 'specmip modes';\n"
        "truth and ref are always rendered: the others are measured on them)"),
    /* bench's --spp is a list, each of render's range */
    ROW(SPP, "--spp", "N,...", TEXT, 1, SPM_SCENE_MAX_SPP, B,
        "samples per pixel, ascending, each %R (default 64)"),
    ROW(TRUTH_SPP, "--truth-spp", "N", INT, 1, SPM_SCENE_MAX_SPP, B,
        "spp of the converged truth, %R (default 1024)"),
    ROW(SIZE, "--size", "WxH", TEXT, 1, SPM_SCENE_MAX_SIDE, B,
        "image size, each side %R (default 96x96)"),
    ROW(THRESHOLDS, "--thresholds", "T,...", TEXT, 0.01, 100, B,
        "the ml threshold sweep, each %R (default 1,2;\n"
        "'none': no sweep)"),
    ROW(SWEEP_SPP, "--sweep-spp", "N", INT, 1, SPM_SCENE_MAX_SPP, B,
        "spp of the sweep, %R (default: the largest --spp)"),
    ROW(BUDGETS, "--budgets", "B,...", TEXT, 0.01, 1000, B,
        "equal-time budgets, ascending, each %R, as multiples of\n"
        "ref's time at --equal-spp (default 0.25,1,4; 'none': no\n"
        "equal-time part)"),
    ROW(EQUAL_SPP, "--equal-spp", "N", INT, 1, SPM_SCENE_MAX_SPP, B,
        "the base spp of those budgets, %R (default: the\n"
        "largest --spp)"),
    ROW(CALIB_SPP, "--calib-spp", "N", INT, 1, SPM_SCENE_MAX_SPP, B,
        "spp of each mode's calibration run, %R (default:\n"
        "--equal-spp / 4, at least 1)"),
    ROW(BLUR, "--blur", "N", INT, 0, 99, B,
        "box blur before dE, %R, odd or 0 (default 5, as\n"
        "`specmip compare`)"),
    ROW(REPEAT, "--repeat", "N", INT, 1, 100, B,
        "each timed render runs N times, %R, the fastest counts\n"
        "(default 2; the modes take turns)"),
    /* spectrum */
    ROW(COLUMN, "--column", "NAME", TEXT, 0, 0, S, "use only the value column called NAME"),
    ROW(ILLUMINANT, "--illuminant", "X", TEXT, 0, 0, S,
        "light for a reflectance: a name (A, D50, D65, F1..F12, HP1..HP5,\n"
        "LED_B1..LED_B5, LED_BH1, LED_RGB1, LED_V1, LED_V2, or a NIST lamp\n"
        "such as nist_mercury) resolved in spectra/, or a CSV file.\n"
        "Default D65. XYZ is scaled so the perfect white under it has\n"
        "Y = 100, and that white is the CIELAB white."),
    ROW(EMISSION, "--emission", NULL, FLAG, 0, 0, S,
        "FILE is a light: XYZ is scaled to Y = 100 and CIELAB uses the\n"
        "D65 white of Y = 100; the pretest sees it on its own"),
    ROW(LEVEL, "--level", "L", INT, 0, SPM_NUM_LEVELS - 1, S,
        "compute XYZ, Lab and sRGB from level L (%R: 400, 80, 40, 20,\n"
        "10 bins) instead of the 1 nm truth; the illuminant stays at 1 nm"),
    /* shared */
    ROW(SEED, "--seed", "S", INT, 0, 4294967295.0, R | B,
        "random seed, %R (default 1): the same seed, the same\n"
        "paths; bench's truths use S+1 and S+2, modulo 2^32"),
    ROW(LOOK_FROM, "--look-from", "X,Y,Z", TEXT, 0, 0, R | B,
        "the camera's position (default: the scene's; alone, the\n"
        "direction is kept)"),
    ROW(LOOK_AT, "--look-at", "X,Y,Z", TEXT, 0, 0, R | B,
        "the point the camera looks at (the scene's up vector kept)"),
    ROW(FOV, "--fov", "DEGREES", REAL, 1, 179, R | B,
        "the field of view, %R, across the scene's fov axis\n"
        "(horizontal unless its camera says 'vertical')"),
    ROW(CAMERA, "--camera", "NAME|N", TEXT, 0, 0, R,
        "a model file's own camera by its name or index from 0\n"
        "(default: its first; a model without one is framed)"),
    {SPM_O_WIDTH, "--width", NULL, "W", SPM_ARG_INT, 1, SPM_SCENE_MAX_SIDE, R,
     "--width W, --height H",
     "image size, %R (default: the scene's); one of them alone\n"
     "keeps the scene's aspect ratio (the other rounded); the\n"
     "field of view is horizontal, so both change the vertical one"},
    ROW(HEIGHT, "--height", "H", INT, 1, SPM_SCENE_MAX_SIDE, R, NULL),
    ROW(BACKEND, "--backend", "B", TEXT, 0, 0, R | B,
        "opencl (default) | cpu (the scalar CPU reference)"),
    ROW(DEVICE, "--device", "D", TEXT, 0, 255, R | B,
        "OpenCL device index (%R), a list 0,2, or all (default 0);\n"
        "all: every device but a second platform's CPU devices\n"
        "and simulators; see 'specmip devices'; bench --ops and\n"
        "--rays time one device"),
    ROW(THRESHOLD, "--threshold", "T", REAL, 0, 1e6, R | B | S,
        "pretest colour-difference threshold, %R (default 2)"),
    ROW(METRIC, "--metric", "M", TEXT, 0, 0, R | S,
        "de00 (CIEDE2000, default) | deab (CIE 1976): the\n"
        "pretest's colour difference"),
    ROW(JSON, "--json", NULL, FLAG, 0, 0, S,
        "one JSON object per spectrum (an array for several columns)\n"
        "with keys XYZ, Lab, sRGB {linear, encoded}, levels\n"
        "[{level, bins, dE00, dEab}] and chosen_level"),
    ROW(COARSEST_LEVEL, "--coarsest-level", "L", INT, 0, SPM_NUM_LEVELS - 1, R,
        "coarsest level the pretest may pick, %R: 0 (400 bins of 1 nm:\n"
        "no mipmapping), 1 (80), 2 (40), 3 (20, default) or 4 (10)"),
    ROW(TONEMAP, "--tonemap", "T", TEXT, 0, 0, R,
        "PNG/PPM tone mapping on luminance: linear (default; 'auto' is\n"
        "the same) | thesis (the thesis' operator, scale = 1/(5 + L))"),
    ROW(EXPOSURE, "--exposure", "E", TEXT, 0, 0, R,
        "auto (default: the 99th percentile of Y maps to white) or a\n"
        "number multiplying Y before the operator"),
    ROW(WHITE, "--white", "W", TEXT, 0, 0, R,
        "white balance: the image adapted (Bradford) from white W to\n"
        "the display's D65, as a camera would: D65 (default: unchanged),\n"
        "E, A, D50, F1..F12 or another illuminant of spectra/, auto (the\n"
        "scene's most powerful emitter) or a spectrum's CSV file; every\n"
        "output but a .spectral.exr, which stays as rendered"),
    ROW(STATS, "--stats", NULL, FLAG, 0, 0, R,
        "print the time of every stage, the BVH (nodes, SAH cost,\n"
        "threads), peak memory, paths/s and (ml, mlc) paths per level\n"
        "(stdout)"),
    ROW(JSON, "--json", NULL, FLAG, 0, 0, R,
        "print the statistics as one JSON object (stdout; with --stats\n"
        "too, the text goes to stderr)"),
    {SPM_O_PROGRESS, "--progress", NULL, NULL, SPM_ARG_FLAG, 0, 0, R | B,
     "--progress, --quiet", "progress line on stderr even when it is not a terminal\n"
                            "(default: when it is), or none and no notes (warnings stay)"},
    ROW(QUIET, "--quiet", NULL, FLAG, 0, 0, R | B, NULL),
    ROW(VERBOSE, "--verbose", NULL, FLAG, 0, 0, R,
        "print the pretest's level table (mlc: its own)"),
    ROW(STRICT, "--strict", NULL, FLAG, 0, 0, R,
        "what a scene holds that specmip does not render is an error\n"
        "(exit 2), not a warning (pbrt-v4 and Mitsuba files)"),
    /* bench */
    ROW(OUT, "--out", "DIR", TEXT, 0, 0, B, "output directory (default bench-out)"),
    ROW(QUICK, "--quick", NULL, FLAG, 0, 0, B,
        "three scenes (cornell, cornell_spiky, metameric), 64x64, truth at\n"
        "512 spp: a few minutes; options given explicitly still apply"),
    ROW(NO_CHARTS, "--no-charts", NULL, FLAG, 0, 0, B, "CSV only"),
    ROW(OPS, "--ops", NULL, FLAG, 0, 0, B,
        "the operator micro-benchmark instead (kernels/opbench.cl):\n"
        "multiply, scaled add, set, clear per level and vector width,\n"
        "ns/op and ratios; writes DIR/ops.csv and prints a table"),
    ROW(OPS_ITEMS, "--ops-items", "N", INT, 1, 1 << 24, B,
        "its work-items, %R (default 4096)"),
    ROW(OPS_ITERS, "--ops-iters", "K", INT, 1, 1 << 24, B,
        "and ops each, %R (default 1024)"),
    ROW(RAYS, "--rays", "SCENE", TEXT, 0, 0, B,
        "traversal alone instead: the CPU reference traces SCENE's paths\n"
        "('default': the built-in scene) at --size (default 256x256) and\n"
        "--rays-spp, recording every camera, bounce and shadow\n"
        "ray; they are replayed through the renderer's traversal\n"
        "(kernels/rays.cl on --device) and the reference's, closest-hit and\n"
        "shadow rays timed apart (fastest of --repeat), answers compared"),
    ROW(RAYS_SPP, "--rays-spp", "N", INT, 1, 1 << 16, B, "its spp, %R (default 1)"),
    {SPM_O_RAYS_SAVE, "--rays-save", NULL, "FILE", SPM_ARG_TEXT, 0, 0, B,
     "--rays-save FILE, --rays-load FILE",
     "write the recorded rays / replay a file's\n"
     "(recorded on the same scene and BVH, else an input error)"},
    ROW(RAYS_LOAD, "--rays-load", "FILE", TEXT, 0, 0, B, NULL),
    ROW(RAYS_STATS, "--rays-stats", NULL, FLAG, 0, 0, B,
        "also count nodes visited and triangle tests per ray"),
    ROW(RAYS_GROUP, "--rays-group", "N", INT, 1, 1024, B,
        "the replay's work-group size, %R (default 64, the renderer's)"),
    ROW(RAYS_PACKET, "--rays-packet", NULL, FLAG, 0, 0, B,
        "replay through the packet variant instead: the rays of a\n"
        "work-group share one node stream (kernels/traverse_packet.clh;\n"
        "--rays-group at most 64)"),
    ROW(RAYS_QUANT, "--rays-quant", NULL, FLAG, 0, 0, B,
        "replay through the quantised tree instead: each node's child\n"
        "boxes as 8-bit codes rounded outward, 64 bytes a node\n"
        "(kernels/traverse_quant.clh)"),
    ROW(RAYS_SORT, "--rays-sort", NULL, FLAG, 0, 0, B,
        "replay each kind of ray sorted by direction octant, then\n"
        "origin (Morton order), as a wavefront could between bounces"),
    ROW(RAYS_WAVEFRONT, "--rays-wavefront", "N", INT, 1, 16, B,
        "trace N bounces of a wavefront instead (camera rays, then at\n"
        "each hit a cosine bounce and a shadow ray to an emitter), each\n"
        "bounce in path order and sorted by octant and origin, both timed\n"
        "with the sort's cost and compared ray by ray, %R"),
    ROW(EMBREE, "--embree", NULL, FLAG, 0, 0, B,
        "also replay through Embree 3 (when built with it), its runs\n"
        "alternating with the kernel's, and give specmip/Embree ratios"),
    ROW(THREADS, "--threads", "N", INT, 1, 64, B, "Embree's threads, %R (default 2)"),
    ROW(EMBREE_QUALITY, "--embree-quality", "Q", TEXT, 0, 0, B,
        "low|medium|high: Embree's BVH (default medium)"),
    ROW(JSON, "--json", NULL, FLAG, 0, 0, B,
        "the ray benchmark's results as one JSON object on stdout"),
    ROW(ALLOW_PATH, "--allow-path", "DIR", TEXT, 0, 0, R | B,
        "a folder the files a scene names (meshes, spectra, images, a\n"
        "model's buffers) may also be in; repeatable. By default only\n"
        "the scene file's own folder and below, and specmip's spectra/\n"
        "and scenes/ (docs/SCENE_FORMAT.md, 'Where referenced files may be')"),
    {SPM_O_DEFINE, "--define", "-D", "N=V", SPM_ARG_TEXT, 0, 0, R, NULL,
     "a Mitsuba scene's parameter $N, over its <default>;\nrepeatable"},
    {SPM_O_HELP, "--help", "-h", NULL, SPM_ARG_FLAG, 0, 0, R | B | S, NULL, "this text"},
};
const int spm_noptions = (int)(sizeof spm_options / sizeof spm_options[0]);
#undef ROW

static const spm_option *find(unsigned cmd, const char *a)
{
    for (int k = 0; k < spm_noptions; k++)
        if ((spm_options[k].cmds & cmd) &&
            (!strcmp(a, spm_options[k].name) ||
             (spm_options[k].alias && !strcmp(a, spm_options[k].alias))))
            return &spm_options[k];
    return NULL;
}

static int next(unsigned cmd, const char *name, int argc, char **argv, int *i,
                const spm_option **opt, const char **value, double *number)
{
    const char *a = argv[*i];
    *opt = NULL;
    *value = a;
    *number = 0;
    if (a[0] != '-' || !a[1])
        return 0; /* a positional argument */
    const spm_option *o = find(cmd, a);
    if (!o) {
        fprintf(stderr, "specmip %s: unknown option '%s' (see specmip %s --help)\n", name, a,
                name);
        return SPM_EXIT_INPUT;
    }
    *opt = o;
    if (o->kind == SPM_ARG_FLAG)
        return 0;
    if (*i + 1 >= argc) {
        fprintf(stderr, "specmip %s: %s needs a value\n", name, a);
        return SPM_EXIT_INPUT;
    }
    *value = argv[++*i];
    long n;
    if (o->kind == SPM_ARG_INT) {
        if (spm_arg_long(name, o->name, *value, (long)o->lo, (long)o->hi, &n))
            return SPM_EXIT_INPUT;
        *number = (double)n;
    } else if (o->kind == SPM_ARG_REAL &&
               spm_arg_double(name, o->name, *value, o->lo, o->hi, number)) {
        return SPM_EXIT_INPUT;
    }
    return 0;
}

void spm_opt_start(spm_opt_iter *it, unsigned cmd, const char *name, int argc, char **argv)
{
    memset(it, 0, sizeof *it);
    it->cmd = cmd;
    it->name = name;
    it->argc = argc;
    it->argv = argv;
}

int spm_opt_each(spm_opt_iter *it)
{
    if (++it->i >= it->argc)
        return 0;
    return next(it->cmd, it->name, it->argc, it->argv, &it->i, &it->opt, &it->value,
                &it->number) ? -1 : 1;
}

/* One help line: "%R" is the row's range. */
static void help_line(FILE *f, const spm_option *o, const char *line, size_t len)
{
    const char *r = strstr(line, "%R");
    if (!r || (size_t)(r - line) >= len) {
        fprintf(f, "%.*s\n", (int)len, line);
        return;
    }
    fprintf(f, "%.*s%.15g to %.15g%.*s\n", (int)(r - line), line, o->lo, o->hi,
            (int)(len - (size_t)(r - line) - 2), r + 2);
}

void spm_opt_help(FILE *f, unsigned cmd, int col)
{
    for (int k = 0; k < spm_noptions; k++) {
        const spm_option *o = &spm_options[k];
        if (!(o->cmds & cmd) || !o->help)
            continue;
        char label[96];
        if (o->label)
            snprintf(label, sizeof label, "%s", o->label);
        else
            snprintf(label, sizeof label, "%s%s%s%s%s", o->alias ? o->alias : "",
                     o->alias ? ", " : "", o->name, o->value ? " " : "", o->value ? o->value : "");
        int pad = col - 2 - (int)strlen(label);
        fprintf(f, "  %s%*s", label, pad >= 1 ? pad : 3, "");
        for (const char *l = o->help, *e;; l = e + 1) {
            e = strchr(l, '\n');
            if (l != o->help)
                fprintf(f, "%*s", col, "");
            help_line(f, o, l, e ? (size_t)(e - l) : strlen(l));
            if (!e)
                break;
        }
        if (o->id == SPM_O_MODE)
            spm_modes_help(f, col + 2);
    }
}

int spm_opt_devices(const char *name, const char *s, int *devices, int max, int *n, int *all)
{
    if (!strcmp(s, "all")) {
        *all = 1;
        return 0;
    }
    const spm_option *o = find(SPM_CMD_RENDER | SPM_CMD_BENCH, "--device");
    const char *p = s;
    *n = 0; /* the last --device counts */
    do {
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || v < (long)o->lo || v > (long)o->hi || (*end && (*end != ',' || !end[1])) ||
            *n >= max) {
            fprintf(stderr,
                    "specmip %s: --device takes an index from %g to %g, a list like 0,2 (at "
                    "most %d) or 'all', not '%s'\n", name, o->lo, o->hi, max, s);
            return 1;
        }
        devices[(*n)++] = (int)v;
        p = *end ? end + 1 : end;
    } while (*p);
    *all = 0;
    return 0;
}
