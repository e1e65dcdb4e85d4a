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
#include "backends.h"
#include "bench_study.h"
#include "cli_args.h"
#include "paths.h"
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
        "(gnuplot).\n\n");
    spm_opt_help(f, SPM_CMD_BENCH, 21);
    fprintf(f,
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
static int rays_option(const spm_option *opt, const char *v, double d, options *o)
{
    switch (opt->id) {
    case SPM_O_RAYS:
        o->rays_on = 1;
        o->rays.scene = strcmp(v, "default") ? v : NULL;
        return 0;
    case SPM_O_RAYS_SPP: o->rays.spp = (int)d; return 0;
    case SPM_O_RAYS_GROUP: o->rays.group = (int)d; return 0;
    case SPM_O_RAYS_PACKET: o->rays.packet = 1; return 0;
    case SPM_O_RAYS_QUANT: o->rays.quant = 1; return 0;
    case SPM_O_RAYS_SORT: o->rays.sort = 1; return 0;
    case SPM_O_RAYS_WAVEFRONT: o->rays.wavefront = (int)d; return 0;
    case SPM_O_RAYS_SAVE: o->rays.save = v; return 0;
    case SPM_O_RAYS_LOAD: o->rays.load = v; return 0;
    case SPM_O_RAYS_STATS: o->rays.stats = 1; return 0;
    case SPM_O_EMBREE: o->rays.embree = 1; return 0;
    case SPM_O_JSON: o->rays.json = 1; return 0;
    case SPM_O_THREADS: o->rays.threads = (int)d; return 0;
    case SPM_O_EMBREE_QUALITY: {
        static const char *const q[] = {"low", "medium", "high"};
        o->rays.embree_quality = -1;
        for (int k = 0; k < 3; k++)
            if (!strcmp(v, q[k]))
                o->rays.embree_quality = k;
        if (o->rays.embree_quality < 0)
            return fail("--embree-quality is low, medium or high, not '%s'%s", v, "");
        return 0;
    }
    default:
        return NOT_MINE;
    }
}

/* "--budgets B,..." or "--thresholds T,...", each in the option's range, or
 * 'none'; budgets ascending. */
static int number_list(const spm_option *opt, const char *v, double *out, int max, int *n)
{
    if (!strcmp(v, "none")) {
        *n = 0;
        return 0;
    }
    if (parse_list(opt->name, v, opt->lo, opt->hi, max, out, n))
        return SPM_EXIT_INPUT;
    for (int k = 1; k < *n && opt->id == SPM_O_BUDGETS; k++)
        if (out[k] <= out[k - 1])
            return fail("--budgets takes ascending numbers, not '%s'%s", v, "");
    return 0;
}

/* The study's sample counts, budgets and thresholds: 0, NOT_MINE, or an exit
 * code. */
static int list_option(const spm_option *opt, const char *v, double d, options *o)
{
    spm_bench_plan *p = &o->plan;
    double list[SPM_BENCH_MAX_SPP];
    int nl;
    switch (opt->id) {
    case SPM_O_SPP:
        if (parse_list(opt->name, v, opt->lo, opt->hi, SPM_BENCH_MAX_SPP, list, &nl))
            return SPM_EXIT_INPUT;
        for (int k = 0; k < nl; k++) {
            if (list[k] != (int)list[k] || (k && list[k] <= list[k - 1]))
                return fail("--spp takes ascending whole numbers, not '%s'%s", v, "");
            p->spps[k] = (int)list[k];
        }
        p->nspp = nl;
        o->have_spp = 1;
        return 0;
    case SPM_O_TRUTH_SPP: p->truth_spp = (int)d; o->have_truth_spp = 1; return 0;
    case SPM_O_SWEEP_SPP: p->sweep_spp = (int)d; o->have_sweep_spp = 1; return 0;
    case SPM_O_EQUAL_SPP: p->equal_spp = (int)d; o->have_equal_spp = 1; return 0;
    case SPM_O_CALIB_SPP: p->calib_spp = (int)d; o->have_calib_spp = 1; return 0;
    case SPM_O_BUDGETS:
        return number_list(opt, v, p->budgets, SPM_BENCH_MAX_BUDGETS, &p->nbudgets);
    case SPM_O_THRESHOLDS:
        return number_list(opt, v, p->thresholds, SPM_BENCH_MAX_THRESHOLDS, &p->nthresholds);
    default:
        return NOT_MINE;
    }
}

/* The options of a render: scenes, modes, size, backend and devices, seed. */
static int render_option(const spm_option *opt, const char *v, double d, options *o)
{
    spm_bench_plan *p = &o->plan;
    int w, h;
    char end;
    const spm_backend_kind *k;
    switch (opt->id) {
    case SPM_O_SCENES:
        free(o->scene_buf);
        o->scene_buf = spm_xstrdup(v);
        p->nscenes = split_names(o->scene_buf, o->scenes, MAX_SCENES);
        if (p->nscenes <= 0)
            return fail("--scenes takes up to 64 files separated by commas, not '%s'%s", v, "");
        o->have_scenes = 1;
        return 0;
    case SPM_O_MODES: return parse_modes(v, p) ? SPM_EXIT_INPUT : 0;
    case SPM_O_SIZE:
        if (sscanf(v, "%dx%d%c", &w, &h, &end) != 2 || w < opt->lo || h < opt->lo ||
            w > opt->hi || h > opt->hi) {
            fprintf(stderr, "specmip bench: --size takes WxH, each side from %g to %g, e.g. "
                            "64x64, not '%s'\n", opt->lo, opt->hi, v);
            return SPM_EXIT_INPUT;
        }
        p->width = w;
        p->height = h;
        o->have_size = 1;
        return 0;
    case SPM_O_THRESHOLD: p->pretest.threshold = d; return 0;
    case SPM_O_FOV: p->cam.fov = d; return 0;
    case SPM_O_LOOK_FROM:
        p->cam.has_from = 1;
        return spm_arg_point("bench", "--look-from", v, p->cam.from) ? SPM_EXIT_INPUT : 0;
    case SPM_O_LOOK_AT:
        p->cam.has_at = 1;
        return spm_arg_point("bench", "--look-at", v, p->cam.at) ? SPM_EXIT_INPUT : 0;
    case SPM_O_SEED: p->seed = (spm_u32)d; return 0; /* the truth's S+1, S+2 wrap modulo 2^32 */
    case SPM_O_BACKEND:
        if (!(k = spm_backend_kind_find(v)))
            return fail("--backend is opencl or cpu, not '%s'%s", v, "");
        p->use_cpu = !strcmp(k->name, "cpu");
        return 0;
    case SPM_O_DEVICE:
        return spm_opt_devices("bench", v, p->devices, SPM_MAX_BACKENDS, &p->ndevices,
                               &p->all_devices) ? SPM_EXIT_INPUT : 0;
    default:
        return NOT_MINE;
    }
}

static int parse_args(int argc, char **argv, options *o)
{
    spm_bench_plan *p = &o->plan;
    spm_opt_iter it;
    int more;
    for (spm_opt_start(&it, SPM_CMD_BENCH, "bench", argc, argv); (more = spm_opt_each(&it)) > 0;) {
        if (!it.opt)
            return fail("unexpected argument '%s' (scenes go in --scenes)%s", it.value, "");
        int rc = rays_option(it.opt, it.value, it.number, o);
        if (rc == NOT_MINE)
            rc = list_option(it.opt, it.value, it.number, o);
        if (rc == NOT_MINE)
            rc = render_option(it.opt, it.value, it.number, o);
        if (rc != NOT_MINE) {
            if (rc)
                return rc;
            continue;
        }
        switch (it.opt->id) {
        case SPM_O_HELP: usage(stdout); return -1;
        case SPM_O_QUICK: o->quick = 1; break;
        case SPM_O_NO_CHARTS: o->charts = 0; break;
        case SPM_O_OPS: o->ops = 1; break;
        case SPM_O_PROGRESS: p->progress = 2; break;
        case SPM_O_QUIET: p->progress = 0; spm_quiet_notes = 1; break;
        case SPM_O_BLUR:
            if (it.number > 1 && (int)it.number % 2 == 0)
                return fail("--blur needs an odd window (or 0 for none), not '%s'%s", it.value, "");
            p->blur = (int)it.number;
            break;
        case SPM_O_REPEAT: p->repeat = (int)it.number; break;
        case SPM_O_OUT: o->out = it.value; break;
        case SPM_O_ALLOW_PATH: {
            spm_error e;
            if (spm_paths_allow(it.value, &e))
                return fail("%s%s", e.msg, "");
            break;
        }
        case SPM_O_OPS_ITEMS: o->ops_items = (int)it.number; break;
        case SPM_O_OPS_ITERS: o->ops_iters = (int)it.number; break;
        default: break;
        }
    }
    if (more < 0)
        return SPM_EXIT_INPUT;
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
    char failed[4096];
    if (spm_make_dirs(dir, failed, sizeof failed)) {
        fprintf(stderr, "specmip bench: cannot create %s: %s\n", failed, strerror(errno));
        return 1;
    }
    return 0;
}

/* --ops and --rays time one device: a list of several or 'all' is refused. */
static int one_device(const options *o)
{
    if (!o->plan.all_devices && o->plan.ndevices <= 1)
        return 0;
    return fail("--ops and --rays time one device: --device takes one index with them%s%s", "",
                "");
}

/* --rays: the traversal benchmark (bench_rays.c); writes nothing but --rays-save. */
static int run_rays(options *o)
{
    spm_rays_opts *r = &o->rays;
    r->width = o->have_size ? o->plan.width : 256;
    r->height = o->have_size ? o->plan.height : 256;
    r->spp = r->spp ? r->spp : 1;
    r->seed = o->plan.seed;
    r->device = o->plan.devices[0];
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
    if (!rc && (o.rays_on || o.ops))
        rc = one_device(&o);
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
    spm_bench_write_meta(o.out, o.ops ? "ops" : "bench", p->use_cpu, p->devices,
                         p->all_devices ? -1 : p->ndevices, argc, argv);
    spm_catch_interrupts();
    spm_error err;
    err.msg[0] = 0;
    if (o.ops) {
        rc = spm_bench_ops(p->devices[0], o.ops_items, o.ops_iters, o.out, &err);
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
