#include "bench_study.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench_image.h"
#include "pocl_cache.h"
#include "backend_cpu.h"
#include "backends.h"
#include "backend_cl.h"
#include "scene_build.h"

#define MAX_BACKENDS_PER_SCENE (SPM_MODE_COUNT + 4)

typedef struct {
    const spm_bench_plan *p;
    spm_bench_csv *csv;
    double t0, units_total, units_done;
    double floor_p99; /* the scene's two converged truths: p99 ΔE00 */
} study;

/* One scene's setup and its backends, one per (mode, seed) and device (the
 * devices the setup opened), created on first use and warmed up once, so no
 * render's time includes a kernel build. */
typedef struct {
    spm_render_setup s;
    spm_render_config cfg; /* the setup's, for the pretest another mode reads */
    char name[256];
    size_t npix;
    spm_backend *b[MAX_BACKENDS_PER_SCENE][SPM_MAX_BACKENDS];
    int bmode[MAX_BACKENDS_PER_SCENE];
    spm_u32 bseed[MAX_BACKENDS_PER_SCENE];
    int owned[MAX_BACKENDS_PER_SCENE]; /* 0: the setup's own, closed with it */
    spm_render_plan plan[MAX_BACKENDS_PER_SCENE]; /* an owned backend's plan */
    int nb;
} scene_run;

typedef struct {
    spm_image img;
    spm_run_result res;
    int compiled; /* of the run kept in res: spm_pocl_cache_grew */
} render_out;

static void scene_name(const char *path, char *out, size_t n)
{
    const char *base = strrchr(path, '/');
    snprintf(out, n, "%s", base ? base + 1 : path);
    char *dot = strchr(out, '.');
    if (dot && dot != out)
        *dot = 0;
}

static void progress(study *st, const char *scene, const char *what, int spp)
{
    if (!st->p->progress)
        return;
    double el = spm_now() - st->t0;
    double frac = st->units_total > 0 ? st->units_done / st->units_total : 0.0;
    double eta = frac > 0.01 ? el * (1.0 - frac) / frac : -1.0;
    char etas[32] = "?";
    if (eta >= 0)
        snprintf(etas, sizeof etas, "%dm%02ds", (int)eta / 60, (int)eta % 60);
    fprintf(stderr, "%sbench: %3.0f%%  %-16s %-14s spp %-6d %dm%02ds elapsed, ETA %s%s",
            st->p->progress == 1 ? "\r" : "", 100.0 * frac, scene, what, spp, (int)el / 60,
            (int)el % 60, etas, st->p->progress == 1 ? "   " : "\n");
    fflush(stderr);
}

static void add_backends(scene_run *r, spm_backend *const *b, int mode, spm_u32 seed, int owned)
{
    memcpy(r->b[r->nb], b, (size_t)r->s.nb * sizeof *b);
    r->bmode[r->nb] = mode;
    r->bseed[r->nb] = seed;
    r->owned[r->nb++] = owned;
}

/* One pass at the size of the first render: the device program's first run
 * (PoCL finishes compiling its work-group functions there) is not timed. */
static int warm_up(spm_backend *b, size_t npix, spm_error *err)
{
    float *buf = spm_xmalloc(3 * npix * sizeof *buf);
    spm_pass_stats st;
    memset(&st, 0, sizeof st);
    int rc = b->pass(b, 0, 1, buf, &st, err);
    free(buf);
    return rc;
}

/* The backends of (mode, seed), one per device: r->s.nb of them. */
static spm_backend **backend_for(const spm_bench_plan *p, scene_run *r, int mode, spm_u32 seed,
                                 spm_error *err)
{
    for (int i = 0; i < r->nb; i++)
        if (r->bmode[i] == mode && r->bseed[i] == seed)
            return r->b[i];
    if (r->nb == MAX_BACKENDS_PER_SCENE) {
        spm_errorf(err, "too many backends for one scene");
        return NULL;
    }
    spm_render_plan *plan = &r->plan[r->nb];
    r->cfg.mode = mode;
    if (spm_render_setup_levels(&r->cfg, &r->s, err))
        return NULL;
    if (spm_render_plan_init(plan, &r->s.geom, &r->s.tables, mode, seed, err))
        return NULL;
    spm_backend *b[SPM_MAX_BACKENDS];
    int n = 0;
    for (; n < r->s.nb; n++) {
        b[n] = p->use_cpu ? spm_backend_cpu_create(plan, err)
                          : spm_backend_cl_create(r->s.device[n], plan, err);
        if (b[n] && warm_up(b[n], r->npix, err)) {
            b[n]->destroy(b[n]);
            b[n] = NULL;
        }
        if (!b[n])
            break;
    }
    if (n < r->s.nb) {
        while (n--)
            b[n]->destroy(b[n]);
        spm_render_plan_free(plan);
        return NULL;
    }
    add_backends(r, b, mode, seed, 1);
    return r->b[r->nb - 1];
}

/* Renders into o (image in linear sRGB, statistics) `times` times: a repeat
 * gives the same image (deterministic film), and the fastest run's statistics
 * are kept, the least disturbed by whatever else the machine runs. 0, an exit
 * code, or SPM_EXIT_INTERRUPTED (the unfinished render is dropped). */
static int render_with(study *st, scene_run *r, spm_backend **b, int spp, int times,
                       const char *what, render_out *o, spm_error *err)
{
    int rc = 0;
    for (int k = 0; k < times && !rc; k++) {
        progress(st, r->name, what, spp);
        spm_film film;
        if (spm_film_init(&film, r->s.scene.width, r->s.scene.height, err))
            return SPM_EXIT_INPUT;
        spm_run_opts ro = {.spp = spp, .spp_per_pass = spm_spp_per_pass(r->npix, spp),
                           .stop = st->p->stop, .progress = 0};
        spm_run_result res;
        spm_pocl_cache c0 = spm_pocl_cache_now();
        rc = spm_render_run(b, r->s.nb, r->npix, &ro, &film, &res, err) ? SPM_EXIT_RUNTIME : 0;
        spm_pocl_cache c1 = spm_pocl_cache_now();
        int compiled = st->p->use_cpu ? -1 : spm_pocl_cache_grew(&c0, &c1);
        if (!rc && compiled == 1)
            fprintf(stderr, "%sspecmip bench: WARNING: PoCL compiled kernels during the timed "
                            "render of %s, %s at %d spp: its time includes compile time (the "
                            "row's compiled_during_timing is 1)\n",
                    st->p->progress == 1 ? "\n" : "", r->name, what, spp);
        if (!rc && (res.interrupted || res.spp_done != spp))
            rc = SPM_EXIT_INTERRUPTED;
        if (!rc && (k == 0 || res.wall_s < o->res.wall_s)) {
            o->res = res;
            o->compiled = compiled;
        }
        if (!rc && k == 0)
            spm_bench_film_image(&film, &o->img);
        spm_film_free(&film);
        st->units_done += spp;
    }
    return rc;
}

static int render(study *st, scene_run *r, int mode, spm_u32 seed, int spp, int times,
                  render_out *o, spm_error *err)
{
    memset(o, 0, sizeof *o);
    spm_backend **b = backend_for(st->p, r, mode, seed, err);
    if (!b)
        return SPM_EXIT_RUNTIME;
    return render_with(st, r, b, spp, times, spm_mode_name(mode), o, err);
}

/* One more render of mode into o, the modes' repeats taken in turns so that a
 * burst of load elsewhere on the machine slows one round of every mode, not
 * all the runs of one: the first run's image is kept (a repeat gives the same
 * image) and the fastest run's statistics. */
static int render_again(study *st, scene_run *r, int mode, spm_u32 seed, int spp, int first,
                        render_out *o, spm_error *err)
{
    render_out t;
    int rc = render(st, r, mode, seed, spp, 1, &t, err);
    if (!rc && first) {
        *o = t;
        return 0;
    }
    if (!rc && t.res.wall_s < o->res.wall_s) {
        o->res = t.res;
        o->compiled = t.compiled;
    }
    spm_image_free(&t.img);
    return rc;
}

static int open_scene(const spm_bench_plan *p, const char *path, int mode, double threshold,
                      scene_run *r, spm_error *err)
{
    memset(r, 0, sizeof *r);
    spm_render_config cfg;
    spm_render_config_defaults(&cfg);
    cfg.scene_path = path;
    cfg.mode = mode;
    cfg.seed = p->seed;
    cfg.width = p->width;
    cfg.height = p->height;
    cfg.backend = p->use_cpu ? &spm_backend_kind_cpu : &spm_backend_kind_opencl;
    memcpy(cfg.devices, p->devices, sizeof cfg.devices);
    cfg.ndevices = p->ndevices;
    cfg.all_devices = p->all_devices;
    cfg.pretest = p->pretest;
    cfg.pretest.threshold = threshold;
    cfg.cam = p->cam;
    int rc = spm_render_setup_open(&cfg, &r->s, err);
    if (rc)
        return rc;
    r->cfg = cfg;
    scene_name(path, r->name, sizeof r->name);
    r->npix = (size_t)r->s.scene.width * (size_t)r->s.scene.height;
    for (int i = 0; i < r->s.nb; i++)
        if (warm_up(r->s.b[i], r->npix, err))
            return SPM_EXIT_RUNTIME;
    add_backends(r, r->s.b, mode, p->seed, 0);
    return 0;
}

static void close_scene(scene_run *r)
{
    for (int i = 0; i < r->nb; i++)
        if (r->owned[i]) {
            for (int d = 0; d < r->s.nb; d++)
                r->b[i][d]->destroy(r->b[i][d]);
            spm_render_plan_free(&r->plan[i]);
        }
    spm_render_setup_close(&r->s);
}

static void row_init(spm_bench_row *row, const scene_run *r, const char *kind, int mode,
                     double threshold, int spp, const render_out *o, const spm_bench_plan *p)
{
    memset(row, 0, sizeof *row);
    row->scene = r->name;
    row->kind = kind;
    row->mode = spm_mode_name(mode);
    row->threshold = threshold;
    row->spp = spp;
    row->width = r->s.scene.width;
    row->height = r->s.scene.height;
    row->seed = p->seed;
    row->wall_s = o->res.wall_s;
    row->compiled = o->compiled;
    for (int i = 0; i < SPM_MAX_BACKENDS; i++)
        row->devices += o->res.passes_by_backend[i] > 0;
    row->st = o->res.total;
    row->truth_spp = p->truth_spp;
}

/* bias against ref and truth of the same seed, error against the converged truth */
static int accuracy(const spm_bench_plan *p, spm_bench_row *row, const spm_image *img,
                    const spm_image *ref, const spm_image *truth, const spm_image *conv,
                    spm_error *err)
{
    return spm_bench_delta_e(ref, img, p->blur, &row->bias_ref, err) ||
           spm_bench_delta_e(truth, img, p->blur, &row->bias_truth, err) ||
           spm_bench_delta_e(conv, img, p->blur, &row->err, err);
}

static int has_mode(const spm_bench_plan *p, int mode)
{
    for (int i = 0; i < p->nmodes; i++)
        if (p->modes[i] == mode)
            return 1;
    return 0;
}

/* The modes rendered at each spp: truth and ref first (the others are measured
 * against them), then the requested ones in their order. */
static int rendered_modes(const spm_bench_plan *p, int *out)
{
    int n = 0;
    out[n++] = SPM_MODE_TRUTH;
    out[n++] = SPM_MODE_REF;
    for (int i = 0; i < p->nmodes; i++)
        if (p->modes[i] != SPM_MODE_TRUTH && p->modes[i] != SPM_MODE_REF)
            out[n++] = p->modes[i];
    return n;
}

typedef struct {
    spm_image ref, truth; /* at the sweep's spp, seed p->seed */
    spm_de_stats noise;
} sweep_base;

/* ml with tables built for each threshold (each its own setup), and ref of
 * the main setup rendered again right before it, so that each time ratio is
 * taken side by side, not minutes apart on a shared machine. */
static int sweep(study *st, scene_run *main, const char *path, const sweep_base *base,
                 const spm_image *conv, double conv_floor, spm_error *err)
{
    const spm_bench_plan *p = st->p;
    for (int t = 0; t < p->nthresholds; t++) {
        scene_run r;
        render_out o, ref;
        memset(&o, 0, sizeof o);
        int rc = render(st, main, SPM_MODE_REF, p->seed, p->sweep_spp, p->repeat, &ref, err);
        spm_image_free(&ref.img);
        if (!rc)
            rc = open_scene(p, path, SPM_MODE_ML, p->thresholds[t], &r, err);
        else
            memset(&r, 0, sizeof r);
        char what[32];
        snprintf(what, sizeof what, "ml dE<%g", p->thresholds[t]);
        if (!rc)
            rc = render_with(st, &r, r.s.b, p->sweep_spp, p->repeat, what, &o, err);
        spm_bench_row row;
        if (!rc) {
            row_init(&row, &r, "sweep", SPM_MODE_ML, p->thresholds[t], p->sweep_spp, &o, p);
            row.time_vs_ref = ref.res.wall_s > 0 ? o.res.wall_s / ref.res.wall_s : 0.0;
            row.conv_floor = conv_floor;
            row.conv_floor_p99 = st->floor_p99;
            row.noise = base->noise;
            if (accuracy(p, &row, &o.img, &base->ref, &base->truth, conv, err) ||
                spm_bench_csv_write(st->csv, &row, err))
                rc = SPM_EXIT_RUNTIME;
        }
        spm_image_free(&o.img);
        close_scene(&r);
        if (rc)
            return rc;
    }
    return 0;
}

/* One spp: every mode with the same seed; rows for the requested modes. */
static int one_spp(study *st, scene_run *r, int spp, const spm_image *conv, double conv_floor,
                   sweep_base *base, spm_error *err)
{
    const spm_bench_plan *p = st->p;
    int modes[SPM_MODE_COUNT + 2];
    int nm = rendered_modes(p, modes);
    render_out out[SPM_MODE_COUNT + 2], noise;
    memset(out, 0, sizeof out);
    memset(&noise, 0, sizeof noise);
    int rc = 0;
    for (int k = 0; k < p->repeat && !rc; k++)
        for (int i = 0; i < nm && !rc; i++)
            rc = render_again(st, r, modes[i], p->seed, spp, k == 0, &out[i], err);
    /* the noise floor at this spp: truth with the next seed */
    if (!rc)
        rc = render(st, r, SPM_MODE_TRUTH, p->seed + 1, spp, 1, &noise, err);
    spm_de_stats noise_de;
    if (!rc && spm_bench_delta_e(&out[0].img, &noise.img, p->blur, &noise_de, err))
        rc = SPM_EXIT_RUNTIME;
    for (int i = 0; i < nm && !rc; i++) {
        if (!has_mode(p, modes[i]))
            continue;
        spm_bench_row row;
        row_init(&row, r, "main", modes[i], p->pretest.threshold, spp, &out[i], p);
        row.time_vs_ref = out[1].res.wall_s > 0 ? out[i].res.wall_s / out[1].res.wall_s : 0.0;
        row.noise = noise_de;
        row.conv_floor = conv_floor;
        row.conv_floor_p99 = st->floor_p99;
        if (accuracy(p, &row, &out[i].img, &out[1].img, &out[0].img, conv, err) ||
            spm_bench_csv_write(st->csv, &row, err))
            rc = SPM_EXIT_RUNTIME;
    }
    if (!rc && spp == p->sweep_spp) { /* kept for the sweep */
        base->truth = out[0].img;
        base->ref = out[1].img;
        base->noise = noise_de;
        out[0].img.rgb = out[1].img.rgb = NULL;
    }
    for (int i = 0; i < nm; i++)
        spm_image_free(&out[i].img);
    spm_image_free(&noise.img);
    return rc;
}

/* The modes timed at equal time: ref (its time is the budget unit) and the
 * requested ones. */
static int equal_modes(const spm_bench_plan *p, int *out)
{
    int n = 0;
    out[n++] = SPM_MODE_REF;
    for (int i = 0; i < p->nmodes; i++)
        if (p->modes[i] != SPM_MODE_REF)
            out[n++] = p->modes[i];
    return n;
}

/* The spp whose render takes about budget_s at s_per_spp seconds a sample
 * (render time is close to linear in spp: a pass is at least 2^16 paths, so
 * the fixed cost per render is a small part of even the calibration run). */
static int equal_spp_for(double budget_s, double s_per_spp)
{
    double n = s_per_spp > 0 ? budget_s / s_per_spp : 1.0;
    if (!(n >= 1.0))
        return 1;
    if (n > SPM_SCENE_MAX_SPP)
        return SPM_SCENE_MAX_SPP;
    return (int)(n + 0.5);
}

/* Equal time: each mode's time per sample from a short run (the fastest of
 * p->repeat, the modes in turns), then, per budget b, each mode at the spp
 * that takes about b x ref's time at p->equal_spp, compared with the converged
 * truth. A budget's renders run once: the row records the time they took. */
static int equal_time(study *st, scene_run *r, const spm_image *conv, double conv_floor,
                      spm_error *err)
{
    const spm_bench_plan *p = st->p;
    int modes[SPM_MODE_COUNT + 1];
    int nm = equal_modes(p, modes);
    double s_per_spp[SPM_MODE_COUNT + 1];
    render_out cal[SPM_MODE_COUNT + 1];
    memset(cal, 0, sizeof cal);
    int rc = 0;
    for (int k = 0; k < p->repeat && !rc; k++)
        for (int i = 0; i < nm && !rc; i++)
            rc = render_again(st, r, modes[i], p->seed, p->calib_spp, k == 0, &cal[i], err);
    for (int i = 0; i < nm; i++) {
        s_per_spp[i] = cal[i].res.wall_s / p->calib_spp;
        spm_image_free(&cal[i].img);
    }
    double unit_s = s_per_spp[0] * p->equal_spp; /* ref at the base spp */
    for (int b = 0; b < p->nbudgets && !rc; b++) {
        double budget_s = p->budgets[b] * unit_s;
        for (int i = 0; i < nm && !rc; i++) {
            if (!has_mode(p, modes[i]))
                continue;
            int spp = equal_spp_for(budget_s, s_per_spp[i]);
            render_out o;
            rc = render(st, r, modes[i], p->seed, spp, 1, &o, err);
            spm_bench_row row;
            if (!rc) {
                row_init(&row, r, "equal", modes[i], p->pretest.threshold, spp, &o, p);
                row.no_bias = 1;
                row.budget = p->budgets[b];
                row.budget_s = budget_s;
                row.s_per_spp = s_per_spp[i];
                row.time_vs_ref = budget_s > 0 ? o.res.wall_s / budget_s : 0.0;
                row.conv_floor = conv_floor;
                row.conv_floor_p99 = st->floor_p99;
                if (spm_bench_delta_e(conv, &o.img, p->blur, &row.err, err) ||
                    spm_bench_csv_write(st->csv, &row, err))
                    rc = SPM_EXIT_RUNTIME;
            }
            spm_image_free(&o.img);
        }
    }
    return rc;
}

static int one_scene(study *st, const char *path, spm_error *err)
{
    const spm_bench_plan *p = st->p;
    scene_run r;
    int rc = open_scene(p, path, SPM_MODE_REF, p->pretest.threshold, &r, err);
    render_out conv, conv2;
    memset(&conv, 0, sizeof conv);
    memset(&conv2, 0, sizeof conv2);
    sweep_base base;
    memset(&base, 0, sizeof base);
    /* converged truth, and a second one of another seed: the floor below which
     * an error against it cannot be resolved */
    if (!rc)
        rc = render(st, &r, SPM_MODE_TRUTH, p->seed + 1, p->truth_spp, 1, &conv, err);
    if (!rc)
        rc = render(st, &r, SPM_MODE_TRUTH, p->seed + 2, p->truth_spp, 1, &conv2, err);
    spm_de_stats floor_de;
    memset(&floor_de, 0, sizeof floor_de);
    if (!rc && spm_bench_delta_e(&conv.img, &conv2.img, p->blur, &floor_de, err))
        rc = SPM_EXIT_RUNTIME;
    spm_image_free(&conv2.img);
    st->floor_p99 = floor_de.p99;
    for (int i = 0; i < p->nspp && !rc; i++)
        rc = one_spp(st, &r, p->spps[i], &conv.img, floor_de.mean, &base, err);
    if (!rc && p->nbudgets)
        rc = equal_time(st, &r, &conv.img, floor_de.mean, err);
    if (!rc && p->nthresholds && has_mode(p, SPM_MODE_ML) && base.ref.rgb)
        rc = sweep(st, &r, path, &base, &conv.img, floor_de.mean, err);
    close_scene(&r);
    spm_image_free(&conv.img);
    spm_image_free(&base.ref);
    spm_image_free(&base.truth);
    if (rc == SPM_EXIT_RUNTIME) { /* input errors already name the file */
        spm_error e = *err;
        spm_errorf(err, "%s: %s", path, e.msg);
    }
    return rc;
}

int spm_bench_study(const spm_bench_plan *p, spm_bench_csv *csv, spm_error *err)
{
    study st = {p, csv, spm_now(), 0.0, 0.0, 0.0};
    int modes[SPM_MODE_COUNT + 2];
    int nm = rendered_modes(p, modes);
    double per_scene = 2.0 * p->truth_spp;
    for (int i = 0; i < p->nspp; i++)
        per_scene += (nm * p->repeat + 1.0) * p->spps[i];
    if (has_mode(p, SPM_MODE_ML))
        per_scene += 2.0 * p->nthresholds * p->sweep_spp * p->repeat; /* ml and ref */
    if (p->nbudgets) { /* calibration, then about the budget's ref spp per mode */
        int em[SPM_MODE_COUNT + 1];
        int ne = equal_modes(p, em);
        per_scene += (double)ne * p->calib_spp * p->repeat;
        for (int b = 0; b < p->nbudgets; b++)
            per_scene += (double)p->nmodes * p->budgets[b] * p->equal_spp;
    }
    st.units_total = per_scene * p->nscenes;
    int rc = 0;
    for (int s = 0; s < p->nscenes && !rc; s++)
        rc = one_scene(&st, p->scenes[s], err);
    if (p->progress == 1)
        fprintf(stderr, "\n");
    return rc;
}
