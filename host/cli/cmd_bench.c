/* specmip bench: options -> the study (bench_study.c) or the operator
 * micro-benchmark (bench_ops.c) -> CSV, then charts and RESULTS.md by
 * bench/report/bench_report.sh (gnuplot). */
#include <errno.h>
#include <glob.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "bench_ops.h"
#include "bench_rays.h"
#include "bench_report.h"
#include "scene_build.h"
#include "bench_study.h"
#include "cli_args.h"
#include "commands.h"
#include "render_setup.h"
#include "spectrum.h"

#define MAX_SCENES 64


static void usage(FILE *f)
{
    fprintf(f,
        "usage: specmip bench [options]\n"
        "The speed/accuracy study: renders every scene in every mode at several spp with one\n"
        "seed, side by side, and writes DIR/bench.csv (one row per render: times, paths/s,\n"
        "paths per level, bias = dE00 against ref and truth of the same seed, error = dE00\n"
        "against a converged truth of another seed with the noise floors); then every mode at\n"
        "equal time: its spp chosen from a short calibration run so that its render takes\n"
        "each budget x ref's time at the base spp, its error against the converged truth;\n"
        "then charts (DIR/*.png) and DIR/RESULTS.md through bench/report/bench_report.sh\n"
        "(gnuplot).\n\n"
        "  --scenes A,B,...   scene files (default: the bundled scenes/*.scene)\n"
        "  --modes M,...      modes with rows (default: every mode, 'specmip modes';\n"
        "                     truth and ref are always rendered: the others are measured on them)\n"
        "  --spp N,...        samples per pixel, ascending (default 64)\n"
        "  --truth-spp N      spp of the converged truth (default 1024)\n"
        "  --size WxH         image size (default 96x96)\n"
        "  --thresholds T,... the ml threshold sweep (default 1,2; 'none': no sweep)\n"
        "  --sweep-spp N      spp of the sweep (default: the largest --spp)\n"
        "  --budgets B,...    equal-time budgets, ascending, as multiples of ref's time at\n"
        "                     --equal-spp (default 0.25,1,4; 'none': no equal-time part)\n"
        "  --equal-spp N      the base spp of those budgets (default: the largest --spp)\n"
        "  --calib-spp N      spp of each mode's calibration run (default: --equal-spp / 4,\n"
        "                     at least 1)\n"
        "  --threshold T      pretest threshold of the main rows, 0 to 1e6 (default 2)\n"
        "  --blur N           box blur before dE (default 5, as `specmip compare`)\n"
        "  --repeat N         each timed render runs N times, the fastest counts (default 2;\n"
        "                     the modes take turns)\n"
        "  --seed S           seed of the compared renders, 0 to 4294967295 (truth uses S+1,\n"
        "                     S+2 too, modulo 2^32; default 1)\n"
        "  --backend B        opencl (default) | cpu\n"
        "  --device D         OpenCL device index (default 0)\n"
        "  --out DIR          output directory (default bench-out)\n"
        "  --quick            three scenes (cornell, cornell_spiky, metameric), 64x64, truth at\n"
        "                     512 spp: a few minutes; options given explicitly still apply\n"
        "  --no-charts        CSV only\n"
        "  --progress, --quiet  progress line on stderr (default: when stderr is a terminal)\n"
        "  --ops              the operator micro-benchmark instead (kernels/opbench.cl):\n"
        "                     multiply, scaled add, set, clear per level and vector width,\n"
        "                     ns/op and ratios; writes DIR/ops.csv and prints a table\n"
        "  --ops-items N, --ops-iters K   its work-items (default 4096) and ops each (1024)\n"
        "  --rays SCENE       traversal alone instead: the CPU reference traces SCENE's paths\n"
        "                     ('default': the built-in scene) at --size (default 256x256) and\n"
        "                     --rays-spp N (default 1), recording every camera, bounce and shadow\n"
        "                     ray; they are replayed through the renderer's traversal\n"
        "                     (kernels/rays.cl on --device) and the reference's, closest-hit and\n"
        "                     shadow rays timed apart (fastest of --repeat), answers compared\n"
        "  --rays-save FILE, --rays-load FILE   write the recorded rays / replay a file's\n"
        "                     (recorded on the same scene and BVH, else an input error)\n"
        "  --rays-stats       also count nodes visited and triangle tests per ray\n"
        "  --rays-group N     the replay's work-group size (default 64, the renderer's)\n"
        "  --embree           also replay through Embree 3 (when built with it), --threads N\n"
        "                     threads (default 2), its runs alternating with the kernel's, and\n"
        "                     give specmip/Embree ratios;\n"
        "                     --embree-quality low|medium|high its BVH (default medium)\n"
        "  --json             the ray benchmark's results as one JSON object on stdout\n"
        "Ctrl-C stops the current render, which is dropped; finished rows are kept (exit 130);\n"
        "a second Ctrl-C exits at once.\n");
}

static int fail(const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "specmip bench: ");
    fprintf(stderr, fmt, a, b);
    fprintf(stderr, "\n");
    return SPM_EXIT_INPUT;
}

/* "a,b,c" -> numbers in [lo, hi], at most max of them */
static int parse_list(const char *opt, const char *s, double lo, double hi, int max, double *out,
                      int *n)
{
    *n = 0;
    const char *p = s;
    while (*p) {
        char *end;
        double v = strtod(p, &end);
        if (end == p || (*end && *end != ',') || !(v >= lo && v <= hi) || *n >= max) {
            fprintf(stderr,
                    "specmip bench: %s takes up to %d comma-separated numbers from %g to %g, not "
                    "'%s'\n", opt, max, lo, hi, s);
            return 1;
        }
        out[(*n)++] = v;
        p = *end ? end + 1 : end;
    }
    return *n ? 0 : 1;
}

typedef struct {
    spm_bench_plan plan;
    const char *scenes[MAX_SCENES];
    char *scene_buf;
    const char *out;
    int quick, charts, ops, ops_items, ops_iters;
    spm_rays_opts rays;
    int rays_on;
    int have_spp, have_truth_spp, have_size, have_sweep_spp, have_scenes, have_equal_spp,
        have_calib_spp;
} options;

static int split_names(char *s, const char **out, int max)
{
    int n = 0;
    for (char *tok = strtok(s, ","); tok; tok = strtok(NULL, ","))
        if (n < max)
            out[n++] = tok;
        else
            return -1;
    return n;
}

static int parse_modes(const char *s, spm_bench_plan *p)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", s);
    const char *names[SPM_MODE_COUNT + 1];
    int n = split_names(buf, names, SPM_MODE_COUNT);
    if (n <= 0)
        return fail("--modes takes modes separated by commas, not '%s'%s", s, "");
    p->nmodes = 0;
    char list[256];
    for (int i = 0; i < n; i++) {
        int m = spm_mode_parse(names[i]);
        if (m < 0)
            return fail("unknown mode '%s' in --modes (%s)", names[i],
                        spm_mode_list(", ", list, sizeof list));
        for (int j = 0; j < p->nmodes; j++)
            if (p->modes[j] == m)
                return fail("mode '%s' twice in --modes%s", names[i], "");
        p->modes[p->nmodes++] = m;
    }
    return 0;
}

#define NOT_MINE (-2) /* an option helper's: the option is another's */

/* The --rays study's options: 0, NOT_MINE, or an exit code. */
static int rays_option(const char *a, const char *v, options *o)
{
    long n;
    if (!strcmp(a, "--rays")) {
        o->rays_on = 1;
        o->rays.scene = strcmp(v, "default") ? v : NULL;
    } else if (!strcmp(a, "--rays-spp")) {
        if (spm_arg_long("bench", a, v, 1, 1 << 16, &n))
            return SPM_EXIT_INPUT;
        o->rays.spp = (int)n;
    } else if (!strcmp(a, "--rays-group")) {
        if (spm_arg_long("bench", a, v, 1, 1024, &n))
            return SPM_EXIT_INPUT;
        o->rays.group = (int)n;
    } else if (!strcmp(a, "--rays-save")) {
        o->rays.save = v;
    } else if (!strcmp(a, "--rays-load")) {
        o->rays.load = v;
    } else if (!strcmp(a, "--rays-stats")) {
        o->rays.stats = 1;
    } else if (!strcmp(a, "--embree")) {
        o->rays.embree = 1;
    } else if (!strcmp(a, "--embree-quality")) {
        static const char *const q[] = {"low", "medium", "high"};
        o->rays.embree_quality = -1;
        for (int k = 0; k < 3; k++)
            if (!strcmp(v, q[k]))
                o->rays.embree_quality = k;
        if (o->rays.embree_quality < 0)
            return fail("--embree-quality is low, medium or high, not '%s'%s", v, "");
    } else if (!strcmp(a, "--json")) {
        o->rays.json = 1;
    } else if (!strcmp(a, "--threads")) {
        if (spm_arg_long("bench", a, v, 1, 64, &n))
            return SPM_EXIT_INPUT;
        o->rays.threads = (int)n;
    } else {
        return NOT_MINE;
    }
    return 0;
}

/* The study's sample counts, budgets and thresholds: 0, NOT_MINE, or an exit
 * code. */
static int list_option(const char *a, const char *v, options *o)
{
    spm_bench_plan *p = &o->plan;
    double list[SPM_BENCH_MAX_THRESHOLDS];
    int nl;
    long n;
    if (!strcmp(a, "--spp")) {
        if (parse_list(a, v, 1, SPM_SCENE_MAX_SPP, SPM_BENCH_MAX_SPP, list, &nl))
            return SPM_EXIT_INPUT;
        for (int k = 0; k < nl; k++) {
            if (list[k] != (int)list[k] || (k && list[k] <= list[k - 1]))
                return fail("--spp takes ascending whole numbers, not '%s'%s", v, "");
            p->spps[k] = (int)list[k];
        }
        p->nspp = nl;
        o->have_spp = 1;
    } else if (!strcmp(a, "--truth-spp") || !strcmp(a, "--sweep-spp")) {
        if (spm_arg_long("bench", a, v, 1, 1 << 20, &n))
            return SPM_EXIT_INPUT;
        if (!strcmp(a, "--truth-spp")) {
            p->truth_spp = (int)n;
            o->have_truth_spp = 1;
        } else {
            p->sweep_spp = (int)n;
            o->have_sweep_spp = 1;
        }
    } else if (!strcmp(a, "--equal-spp") || !strcmp(a, "--calib-spp")) {
        if (spm_arg_long("bench", a, v, 1, SPM_SCENE_MAX_SPP, &n))
            return SPM_EXIT_INPUT;
        if (!strcmp(a, "--equal-spp")) {
            p->equal_spp = (int)n;
            o->have_equal_spp = 1;
        } else {
            p->calib_spp = (int)n;
            o->have_calib_spp = 1;
        }
    } else if (!strcmp(a, "--budgets")) {
        if (!strcmp(v, "none")) {
            p->nbudgets = 0;
        } else {
            if (parse_list(a, v, 0.01, 1000, SPM_BENCH_MAX_BUDGETS, list, &nl))
                return SPM_EXIT_INPUT;
            for (int k = 1; k < nl; k++)
                if (list[k] <= list[k - 1])
                    return fail("--budgets takes ascending numbers, not '%s'%s", v, "");
            memcpy(p->budgets, list, (size_t)nl * sizeof *list);
            p->nbudgets = nl;
        }
    } else if (!strcmp(a, "--thresholds")) {
        if (!strcmp(v, "none")) {
            p->nthresholds = 0;
        } else {
            if (parse_list(a, v, 0.01, 100, SPM_BENCH_MAX_THRESHOLDS, list, &nl))
                return SPM_EXIT_INPUT;
            memcpy(p->thresholds, list, (size_t)nl * sizeof *list);
            p->nthresholds = nl;
        }
    } else {
        return NOT_MINE;
    }
    return 0;
}

static int parse_args(int argc, char **argv, options *o)
{
    spm_bench_plan *p = &o->plan;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        long n;
        static const char *const with_value[] = {
            "--scenes", "--modes", "--spp", "--truth-spp", "--sweep-spp", "--size", "--thresholds",
            "--threshold", "--blur", "--repeat", "--seed", "--backend", "--device", "--out", "--ops-items",
            "--ops-iters", "--rays", "--rays-spp", "--rays-save", "--rays-load", "--threads",
            "--embree-quality", "--rays-group", "--budgets", "--equal-spp", "--calib-spp"};
        int takes_value = 0;
        for (size_t k = 0; k < sizeof with_value / sizeof *with_value; k++)
            takes_value |= !strcmp(a, with_value[k]);
        if (takes_value) {
            if (!v)
                return fail("%s needs a value%s", a, "");
            i++;
        }
        int rc = rays_option(a, v, o);
        if (rc == NOT_MINE)
            rc = list_option(a, v, o);
        if (rc != NOT_MINE) {
            if (rc)
                return rc;
            continue;
        }
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return -1;
        } else if (!strcmp(a, "--quick")) {
            o->quick = 1;
        } else if (!strcmp(a, "--no-charts")) {
            o->charts = 0;
        } else if (!strcmp(a, "--ops")) {
            o->ops = 1;
        } else if (!strcmp(a, "--progress")) {
            p->progress = 2;
        } else if (!strcmp(a, "--quiet")) {
            p->progress = 0;
        } else if (!strcmp(a, "--scenes")) {
            free(o->scene_buf);
            o->scene_buf = spm_xstrdup(v);
            p->nscenes = split_names(o->scene_buf, o->scenes, MAX_SCENES);
            if (p->nscenes <= 0)
                return fail("--scenes takes up to 64 files separated by commas, not '%s'%s", v, "");
            o->have_scenes = 1;
        } else if (!strcmp(a, "--modes")) {
            if (parse_modes(v, p))
                return SPM_EXIT_INPUT;
        } else if (!strcmp(a, "--size")) {
            int w, h;
            char end;
            if (sscanf(v, "%dx%d%c", &w, &h, &end) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384)
                return fail("--size takes WxH, e.g. 64x64, not '%s'%s", v, "");
            p->width = w;
            p->height = h;
            o->have_size = 1;
        } else if (!strcmp(a, "--threshold")) {
            double d;
            if (spm_opt_number("bench", SPM_OPT_THRESHOLD, v, &d))
                return SPM_EXIT_INPUT;
            p->pretest.threshold = d;
        } else if (!strcmp(a, "--blur")) {
            if (spm_arg_long("bench", a, v, 0, 99, &n))
                return SPM_EXIT_INPUT;
            if (n > 1 && n % 2 == 0)
                return fail("--blur needs an odd window (or 0 for none), not '%s'%s", v, "");
            p->blur = (int)n;
        } else if (!strcmp(a, "--repeat")) {
            if (spm_arg_long("bench", a, v, 1, 100, &n))
                return SPM_EXIT_INPUT;
            p->repeat = (int)n;
        } else if (!strcmp(a, "--seed")) {
            double d;
            if (spm_opt_number("bench", SPM_OPT_SEED, v, &d))
                return SPM_EXIT_INPUT;
            p->seed = (spm_u32)d; /* the truth's S+1, S+2 wrap modulo 2^32 */
        } else if (!strcmp(a, "--backend")) {
            if (strcmp(v, "cpu") && strcmp(v, "opencl"))
                return fail("--backend is opencl or cpu, not '%s'%s", v, "");
            p->use_cpu = !strcmp(v, "cpu");
        } else if (!strcmp(a, "--device")) {
            if (spm_arg_long("bench", a, v, 0, 255, &n))
                return SPM_EXIT_INPUT;
            p->device = (int)n;
        } else if (!strcmp(a, "--out")) {
            o->out = v;
        } else if (!strcmp(a, "--ops-items") || !strcmp(a, "--ops-iters")) {
            if (spm_arg_long("bench", a, v, 1, 1 << 24, &n))
                return SPM_EXIT_INPUT;
            *(!strcmp(a, "--ops-items") ? &o->ops_items : &o->ops_iters) = (int)n;
        } else if (a[0] == '-') {
            return fail("unknown option '%s' (see specmip bench --help)%s", a, "");
        } else {
            return fail("unexpected argument '%s' (scenes go in --scenes)%s", a, "");
        }
    }
    return 0;
}

/* Defaults, the --quick ones where not given explicitly. */
static int finish_plan(options *o, glob_t *g)
{
    spm_bench_plan *p = &o->plan;
    static const int spps[] = {64};
    if (!o->have_spp) {
        p->nspp = 1;
        memcpy(p->spps, spps, sizeof spps);
    }
    if (!o->have_truth_spp)
        p->truth_spp = o->quick ? 512 : 1024;
    if (!o->have_size)
        p->width = p->height = o->quick ? 64 : 96;
    if (!o->have_sweep_spp)
        p->sweep_spp = p->spps[p->nspp - 1];
    if (!o->have_equal_spp)
        p->equal_spp = p->spps[p->nspp - 1];
    if (!o->have_calib_spp)
        p->calib_spp = p->equal_spp / 4 > 1 ? p->equal_spp / 4 : 1;
    int found = 0;
    for (int i = 0; i < p->nspp; i++)
        found |= p->spps[i] == p->sweep_spp;
    if (!found && p->nthresholds) {
        fprintf(stderr, "specmip bench: --sweep-spp %d must be one of the --spp values\n",
                p->sweep_spp);
        return SPM_EXIT_INPUT;
    }
    if (p->truth_spp < p->spps[p->nspp - 1])
        fprintf(stderr, "specmip: warning: --truth-spp %d is below the largest --spp: the "
                        "'converged' truth is noisier than the renders it judges\n", p->truth_spp);
    if (!o->have_scenes) {
        char dir[4096];
        /* quick: the smooth and the spiky box, and the scene where rgb breaks */
        spm_data_path(o->quick ? "scenes/{cornell,cornell_spiky,metameric}.scene" : "scenes/*.scene",
                      dir, sizeof dir);
        if (glob(dir, GLOB_BRACE, NULL, g) || !g->gl_pathc) {
            fprintf(stderr, "specmip bench: no scenes match %s\n", dir);
            return SPM_EXIT_INPUT;
        }
        p->nscenes = 0;
        for (size_t i = 0; i < g->gl_pathc && p->nscenes < MAX_SCENES; i++)
            o->scenes[p->nscenes++] = g->gl_pathv[i];
    }
    p->scenes = o->scenes;
    return 0;
}

static int make_dir(const char *dir)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", dir);
    for (char *s = buf + 1;; s++) {
        int end = !*s;
        if (*s == '/' || end) {
            *s = 0;
            if (mkdir(buf, 0777) && errno != EEXIST) {
                fprintf(stderr, "specmip bench: cannot create %s: %s\n", buf, strerror(errno));
                return 1;
            }
            if (end)
                return 0;
            *s = '/';
        }
    }
}

/* --rays: the traversal benchmark (bench_rays.c); writes nothing but --rays-save. */
static int run_rays(options *o)
{
    spm_rays_opts *r = &o->rays;
    r->width = o->have_size ? o->plan.width : 256;
    r->height = o->have_size ? o->plan.height : 256;
    r->spp = r->spp ? r->spp : 1;
    r->seed = o->plan.seed;
    r->device = o->plan.device;
    r->repeat = o->plan.repeat;
    r->threads = r->threads ? r->threads : 2;
    free(o->scene_buf);
    spm_catch_interrupts();
    spm_error err;
    err.msg[0] = 0;
    int rc = spm_bench_rays(r, &err);
    if (rc)
        fprintf(stderr, "specmip bench: %s\n", err.msg);
    spm_release_interrupts();
    return rc;
}

int spm_cmd_bench(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    o.out = "bench-out";
    o.charts = 1;
    o.ops_items = 4096;
    o.ops_iters = 1024;
    o.rays.embree_quality = 1; /* medium, Embree's default */
    spm_bench_plan *p = &o.plan;
    static const double sweep[] = {1, 2};
    memcpy(p->thresholds, sweep, sizeof sweep);
    p->nthresholds = 2;
    static const double budgets[] = {0.25, 1, 4};
    memcpy(p->budgets, budgets, sizeof budgets);
    p->nbudgets = 3;
    for (int m = 0; m < SPM_MODE_COUNT; m++)
        p->modes[m] = m;
    p->nmodes = SPM_MODE_COUNT;
    p->blur = 5;
    p->repeat = 2;
    p->seed = 1;
    p->progress = isatty(2);
    p->stop = &spm_stop_flag;
    spm_pretest_defaults(&p->pretest);
    int rc = parse_args(argc, argv, &o);
    if (!rc && !o.rays_on &&
        (o.rays.save || o.rays.load || o.rays.json || o.rays.embree || o.rays.stats))
        rc = fail("--rays-save, --rays-load, --rays-stats, --embree and --json go with --rays%s%s",
                  "", "");
    if (!rc && o.rays_on)
        return run_rays(&o);
    glob_t g;
    memset(&g, 0, sizeof g);
    if (!rc)
        rc = finish_plan(&o, &g);
    if (!rc && make_dir(o.out))
        rc = SPM_EXIT_INPUT;
    if (rc) {
        globfree(&g);
        free(o.scene_buf);
        return rc < 0 ? SPM_EXIT_OK : rc;
    }
    spm_bench_write_meta(o.out, o.ops ? "ops" : "bench", p->use_cpu, p->device, argc, argv);
    spm_catch_interrupts();
    spm_error err;
    err.msg[0] = 0;
    if (o.ops) {
        rc = spm_bench_ops(p->device, o.ops_items, o.ops_iters, o.out, &err);
    } else {
        spm_bench_csv csv;
        rc = spm_bench_csv_open(&csv, o.out, &err) ? SPM_EXIT_INPUT : 0;
        double t0 = spm_now();
        if (!rc)
            rc = spm_bench_study(p, &csv, &err);
        if (!rc)
            spm_bench_meta_elapsed(o.out, "bench", spm_now() - t0);
        /* an interrupted study keeps its finished rows under the final name */
        spm_error close_err;
        if (csv.f && spm_bench_csv_close(&csv, &close_err) && !rc) {
            err = close_err;
            rc = SPM_EXIT_RUNTIME;
        }
        if (rc && rc != SPM_EXIT_INTERRUPTED)
            fprintf(stderr, "specmip bench: %s\n", err.msg);
        if ((!rc || rc == SPM_EXIT_INTERRUPTED) && csv.rows) {
            fprintf(stderr, "specmip bench: %d rows in %s/bench.csv\n", csv.rows, o.out);
            if (o.charts && spm_bench_report(o.out) && !rc)
                rc = SPM_EXIT_RUNTIME;
        }
    }
    if (o.ops && rc)
        fprintf(stderr, "specmip bench: %s\n", err.msg);
    spm_release_interrupts();
    if (rc == SPM_EXIT_INTERRUPTED)
        fprintf(stderr, "specmip bench: interrupted; finished rows kept\n");
    globfree(&g);
    free(o.scene_buf);
    return rc;
}
