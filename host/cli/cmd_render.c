/* specmip render: options -> setup -> render loop -> images + statistics. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "cli_args.h"
#include "paths.h"
#include "render_white.h"
#include "mpi_render.h"
#include "commands.h"
#include "film_spectral.h"
#include "output.h"
#include "render_meta.h"
#include "render_hints.h"
#include "pocl_cache.h"
#include "backends.h"
#include "render_stats.h"
#include "spectral_exr.h"
#include "film_file.h"
#include "render_resume.h"
#include "scene_build.h"
#include <strings.h>

#define MAX_OUTPUTS 4


static void usage(FILE *f)
{
    fprintf(f,
        "usage: specmip render [SCENE] [options]   (also: specmip SCENE [options])\n"
        "Options take their value as '--spp 16' or '--spp=16'.\n"
        "Renders SCENE (a .scene file, whose 'mesh FILE' statements import models, a\n"
        "MiniLight .ml.txt file, a pbrt-v4 .pbrt file, docs/PBRT.md, or a Mitsuba 3 .xml\n"
        "file, docs/MITSUBA.md), or a model alone (.glb, .gltf, .obj, .ply, .stl: framed\n"
        "by a camera and lit by a default light, docs/SCENE_FORMAT.md); without SCENE the\n"
        "built-in Cornell box (ColorChecker walls, equal-energy light).\n\n");
    spm_opt_help(f, SPM_CMD_RENDER, 25);
    fprintf(f,
        "Under mpirun every rank renders passes on its own --device/--backend; rank 0 reads\n"
        "the scene, sends it to the others and alone writes outputs (README: several machines).\n"
        "Ctrl-C (or SIGTERM) stops within a batch of paths, writes the image of the passes done\n"
        "and exits 130 (nothing is written when no pass is done); a second Ctrl-C exits at once\n"
        "without writing. Existing outputs are replaced only by complete images.\n"
        "--time, --checkpoint, --film and --resume: docs/RENDERING.md.\n");
}

/* The test hook of util.h: SPECMIP_TEST_REFUSE_SCENE_FILES=others makes the
 * ranks above 0 refuse every scene file, =all every process. */
static void refuse_scene_files(const spm_mpi *m)
{
    static char who[32];
    const char *v = getenv("SPECMIP_TEST_REFUSE_SCENE_FILES");
    if (!v || !(!strcmp(v, "all") || (!strcmp(v, "others") && m->rank > 0)))
        return;
    snprintf(who, sizeof who, "rank %d", m->rank);
    spm_input_files_refused = who;
}

/* What the command line asks for, beside the render's configuration. */
typedef struct {
    spm_render_config cfg;
    const char *outputs[MAX_OUTPUTS];
    int nout, nspectral; /* outputs, and how many of them are .spectral.exr */
    int stats, json, progress, spec_nm;
    spm_tonemap tm;
    /* the film kept beside the first .exr output (--film, --checkpoint, --resume) */
    int keep_film;
    const char *resume;
    double checkpoint_s;
    char film_path[4096], film_name[256];
    spm_film_print print; /* what the render is, for its film */
    int pass_spp;
    const char *white;       /* --white, or NULL */
    char white_desc[160];    /* what it resolved to, for the images' metadata */
} render_opts;

#define HELP_SHOWN (-1) /* parse_args: --help printed, nothing to render */

/* The options that take a word: 0 or SPM_EXIT_INPUT with the error on stderr. */
static int word_option(spm_opt_id id, const char *v, render_opts *o)
{
    spm_error e;
    char names[256];
    switch (id) {
    case SPM_O_OUTPUT:
        if (o->nout >= MAX_OUTPUTS) {
            fprintf(stderr, "specmip render: at most %d outputs\n", MAX_OUTPUTS);
            return SPM_EXIT_INPUT;
        }
        o->outputs[o->nout++] = v;
        return 0;
    case SPM_O_MODE:
        if ((o->cfg.mode = spm_mode_parse(v)) < 0) {
            fprintf(stderr, "specmip render: unknown mode '%s' (%s)\n", v,
                    spm_mode_list(", ", names, sizeof names));
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_INTEGRATOR:
        if ((o->cfg.integrator = spm_integrator_parse(v)) < 0) {
            fprintf(stderr, "specmip render: --integrator is path, light or bdpt, not '%s'\n", v);
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_LIGHT_SAMPLER:
        if ((o->cfg.light_sampler = spm_light_sampler_parse(v)) < 0) {
            fprintf(stderr, "specmip render: --light-sampler is tree or power, not '%s'\n", v);
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_SPECTRAL_NM:
        if (strcmp(v, "1") && strcmp(v, "5")) {
            fprintf(stderr, "specmip render: --spectral-nm is 1 or 5, not '%s'\n", v);
            return SPM_EXIT_INPUT;
        }
        o->spec_nm = v[0] - '0';
        return 0;
    case SPM_O_BACKEND:
        if (!(o->cfg.backend = spm_backend_kind_find(v))) {
            fprintf(stderr, "specmip render: --backend is opencl or cpu, not '%s'\n", v);
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_WHITE:
        o->white = v;
        return 0;
    case SPM_O_DEFINE:
        if (spm_scene_define(v, &e)) {
            fprintf(stderr, "specmip render: %s\n", e.msg);
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_CAMERA:
        return spm_scene_model_camera(v);
    case SPM_O_LOOK_FROM:
        o->cfg.cam.has_from = 1;
        return spm_arg_point("render", "--look-from", v, o->cfg.cam.from) ? SPM_EXIT_INPUT : 0;
    case SPM_O_LOOK_AT:
        o->cfg.cam.has_at = 1;
        return spm_arg_point("render", "--look-at", v, o->cfg.cam.at) ? SPM_EXIT_INPUT : 0;
    case SPM_O_ALLOW_PATH:
        if (spm_paths_allow(v, &e)) {
            fprintf(stderr, "specmip render: %s\n", e.msg);
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_DEVICE:
        return spm_opt_devices("render", v, o->cfg.devices, SPM_MAX_BACKENDS, &o->cfg.ndevices,
                               &o->cfg.all_devices) ? SPM_EXIT_INPUT : 0;
    case SPM_O_RESUME:
        o->resume = v;
        return 0;
    case SPM_O_METRIC:
        if (strcmp(v, "de00") && strcmp(v, "deab")) {
            fprintf(stderr, "specmip render: --metric is de00 or deab, not '%s'\n", v);
            return SPM_EXIT_INPUT;
        }
        o->cfg.pretest.metric = !strcmp(v, "deab") ? SPM_METRIC_DEAB : SPM_METRIC_DE00;
        return 0;
    case SPM_O_TONEMAP:
    case SPM_O_EXPOSURE:
        if (id == SPM_O_TONEMAP ? spm_tonemap_select(&o->tm, v, &e)
                                : spm_tonemap_set_exposure(&o->tm, v, &e)) {
            fprintf(stderr, "specmip render: %s: %s\n",
                    id == SPM_O_TONEMAP ? "--tonemap" : "--exposure", e.msg);
            return SPM_EXIT_INPUT;
        }
        return 0;
    default:
        return 0;
    }
}

/* 0, HELP_SHOWN, or SPM_EXIT_INPUT with the error on stderr. */
static int parse_args(int argc, char **argv, render_opts *o)
{
    memset(o, 0, sizeof *o);
    spm_render_config_defaults(&o->cfg);
    o->progress = isatty(2);
    spm_tonemap_default(&o->tm);
    spm_opt_iter it;
    int more;
    for (spm_opt_start(&it, SPM_CMD_RENDER, "render", argc, argv); (more = spm_opt_each(&it)) > 0;) {
        if (!it.opt && !o->cfg.scene_path) {
            o->cfg.scene_path = it.value;
            continue;
        }
        if (!it.opt) {
            fprintf(stderr, "specmip render: one scene only ('%s' and '%s')\n", o->cfg.scene_path, it.value);
            return SPM_EXIT_INPUT;
        }
        switch (it.opt->id) {
        case SPM_O_HELP: usage(stdout); return HELP_SHOWN;
        case SPM_O_SPP: o->cfg.spp = (int)it.number; break;
        case SPM_O_SEED: o->cfg.seed = (spm_u32)it.number; break;
        case SPM_O_WIDTH: o->cfg.width = (int)it.number; break;
        case SPM_O_HEIGHT: o->cfg.height = (int)it.number; break;
        case SPM_O_THRESHOLD: o->cfg.pretest.threshold = it.number; break;
        case SPM_O_COARSEST_LEVEL: o->cfg.pretest.coarsest_level = (int)it.number; break;
        case SPM_O_STATS: o->stats = 1; break;
        case SPM_O_JSON: o->json = 1; break;
        case SPM_O_PROGRESS: o->progress = 1; break;
        case SPM_O_QUIET: o->progress = 0; spm_quiet_notes = 1; break;
        case SPM_O_VERBOSE: o->cfg.verbose = 1; break;
        case SPM_O_STRICT: spm_scene_strict = 1; break;
        case SPM_O_TIME: o->cfg.time_s = it.number; break;
        case SPM_O_CHECKPOINT: o->checkpoint_s = it.number; break;
        case SPM_O_FILM: o->keep_film = 1; break;
        case SPM_O_FOV: o->cfg.cam.fov = it.number; break;
        default:
            if (word_option(it.opt->id, it.value, o))
                return SPM_EXIT_INPUT;
        }
    }
    if (more < 0)
        return SPM_EXIT_INPUT;
    /* with a time budget, an explicit --spp alone limits the samples */
    if (o->cfg.time_s > 0 && !o->cfg.spp)
        o->cfg.spp = SPM_SCENE_MAX_SPP;
    o->keep_film |= o->checkpoint_s > 0 || o->resume;
    return 0;
}

/* The film's file: beside the first .exr output, which names it. */
static int film_file(render_opts *o)
{
    if (!o->keep_film)
        return 0;
    for (int i = 0; i < o->nout; i++) {
        size_t n = strlen(o->outputs[i]);
        if (n > 4 && !strcasecmp(o->outputs[i] + n - 4, ".exr")) {
            const char *slash = strrchr(o->outputs[i], '/');
            snprintf(o->film_path, sizeof o->film_path, "%s.film", o->outputs[i]);
            snprintf(o->film_name, sizeof o->film_name, "%s.film",
                     slash ? slash + 1 : o->outputs[i]);
            o->cfg.film_name = o->film_name;
            return 0;
        }
    }
    fprintf(stderr, "specmip render: --film, --checkpoint and --resume need an .exr output: the "
                    "film is kept beside it and named in its header\n");
    return SPM_EXIT_INPUT;
}

/* The outputs, by default an image and an EXR; spectral ones need a spectral
 * mode, at one of its bin widths. */
static int check_outputs(render_opts *o)
{
    if (!o->nout && o->resume) {
        o->outputs[o->nout++] = o->resume;
    } else if (!o->nout) {
        o->outputs[o->nout++] = "specmip.png";
        o->outputs[o->nout++] = "specmip.exr";
    }
    if (film_file(o))
        return SPM_EXIT_INPUT;
    for (int i = 0; i < o->nout; i++)
        o->nspectral += spm_spectral_path(o->outputs[i]);
    if (!o->nspectral) {
        if (!o->spec_nm)
            return 0;
        fprintf(stderr, "specmip render: --spectral-nm needs a .spectral.exr output\n");
        return SPM_EXIT_INPUT;
    }
    const spm_mode_desc *m = spm_mode(o->cfg.mode);
    o->cfg.spec_nm = o->spec_nm ? o->spec_nm : m->spec_nm[0];
    if (!m->spec_nm[0]) {
        fprintf(stderr, "specmip render: %s mode has no spectrum to write: a .spectral.exr "
                        "output needs a spectral mode\n", m->name);
        return SPM_EXIT_INPUT;
    }
    if (!spm_mode_spec_ok(m, o->cfg.spec_nm)) {
        fprintf(stderr, "specmip render: --spectral-nm %d: %s mode writes %d nm bins%s\n",
                o->cfg.spec_nm, m->name, m->spec_nm[0], m->spec_nm[1] ? " or 1 nm" : " only");
        return SPM_EXIT_INPUT;
    }
    return 0;
}

/* PoCL's kernel cache before and after the render loop: a render that
 * compiled is timed with its compiles (the CPU reference compiles nothing: a
 * cache that grew meanwhile is another process's). Said with --stats only, the
 * times it qualifies; --json carries it as compiled_during_timing. */
static void watch_compiles(const render_opts *o, spm_render_setup *s, const spm_pocl_cache *c0,
                           const spm_pocl_cache *c1)
{
    s->times.compiled_in_render = o->cfg.backend->compiles ? spm_pocl_cache_grew(c0, c1) : -1;
    if (s->times.compiled_in_render == 1 && o->stats) { /* a note on the timing: --stats' */
        char dir[4096];
        fprintf(stderr, "specmip render: WARNING: PoCL's kernel cache %s gained %lld files "
                        "during the render: kernels were compiled (by this render, unless another "
                        "process shares the cache), and the render time may include that\n",
                spm_pocl_cache_dir(dir, sizeof dir), c1->files - (c0->files > 0 ? c0->files : 0));
    }
}

/* The film (when kept), then every output, of `film` as r left it after
 * render_s seconds: 0, or the number of files not written (each reported).
 * With `film_first` a film that cannot be written leaves the outputs as
 * they were too (a checkpoint: the previous film and images stay a pair). */
static int write_all(const render_opts *o, const spm_render_setup *s, const spm_film *film,
                     const spm_run_result *r, double render_s, int film_first)
{
    spm_error err;
    int failed = 0;
    if (o->keep_film && spm_film_save(o->film_path, film, &o->print, o->pass_spp, &err)) {
        fprintf(stderr, "specmip render: %s\n", err.msg);
        if (film_first)
            return 1;
        failed++;
    }
    spm_render_meta meta;
    spm_render_meta_make(&o->cfg, s, r, render_s, &meta);
    if (o->white && meta.n < SPM_META_MAX)
        meta.a[meta.n++] = (spm_image_attr){"specmip:white", SPM_ATTR_STRING, 0, 0, o->white_desc};
    for (int i = 0; i < o->nout; i++)
        if (spm_spectral_path(o->outputs[i])
                ? spm_spectral_exr_write(o->outputs[i], film, meta.a, meta.n, &err)
                : spm_output_write_film_attrs(o->outputs[i], film, &o->tm, meta.a, meta.n, &err)) {
            fprintf(stderr, "specmip render: %s\n", err.msg);
            failed++;
        }
    return failed;
}

/* spm_run_opts.checkpoint: the film and outputs so far, from the render
 * loop's watching thread. */
typedef struct {
    const render_opts *o;
    const spm_render_setup *s;
} checkpoint_ctx;

static void checkpoint(void *ctx, const spm_film *film, const spm_run_result *r)
{
    const checkpoint_ctx *k = ctx;
    if (write_all(k->o, k->s, film, r, r->wall_s, 1))
        fprintf(stderr, "specmip render: checkpoint at %d samples per pixel not written; "
                        "rendering goes on\n", r->spp_done);
    else
        fprintf(stderr, "%sspecmip render: checkpoint: %d samples per pixel written\n",
                k->o->progress ? "\n" : "", r->spp_done);
}

/* The images of a render loop that ended without error; the exit code. */
static int write_outputs(const render_opts *o, spm_render_setup *s, const spm_run_result *res,
                         spm_film *film)
{
    int rc = 0, spp = spm_render_spp(&o->cfg, &s->scene);
    spm_render_warn_dropped(res, film);
    if (!res->interrupted)
        spm_render_hint_black(film);
    if (res->passes_dropped)
        fprintf(stderr, "specmip render: %d finished passes after one that was not were left "
                        "out, so that the film can be resumed\n", res->passes_dropped);
    /* the image so far after an interruption; a signal now is acted on
     * after the writes (an image write cannot be interrupted) */
    double t0 = spm_now();
    if (write_all(o, s, film, res, s->times.render_s, 0))
        rc = SPM_EXIT_RUNTIME;
    s->times.output_s = spm_now() - t0;
    if (res->time_up)
        fprintf(stderr, "specmip render: the time budget (%g s) ended the render at %d samples "
                        "per pixel\n", o->cfg.time_s, res->spp_done);
    if (!rc && res->interrupted) {
        fprintf(stderr, "specmip render: interrupted after %d of %d samples per pixel; "
                        "image written\n", res->spp_done, spp);
        rc = SPM_EXIT_INTERRUPTED;
    } else if (!rc && spm_stop_requested()) {
        fprintf(stderr, "specmip render: interrupted once the render was done; the "
                        "complete image was written\n");
        rc = SPM_EXIT_INTERRUPTED;
    }
    return rc;
}

/* A render that keeps its film: what it is (the print), its pass grid, and
 * with --resume the film it continues, loaded into film. 0 or an exit code. */
static int prepare_film(render_opts *o, const spm_render_setup *s, spm_film *film, spm_error *err)
{
    int spp = spm_render_spp(&o->cfg, &s->scene);
    o->pass_spp = (int)spm_spp_per_pass((size_t)s->scene.width * (size_t)s->scene.height, spp);
    spm_render_print(&o->cfg, s, &o->print);
    return o->resume ? spm_resume_load(o->resume, &o->print, spp, o->pass_spp, film, err) : 0;
}

/* Rank 0's render loop over the film, then the images; the exit code.
 * *torn_down: mpirun is ending every rank (an interrupted render). */
static int render_film(render_opts *o, spm_mpi *mpi, spm_render_setup *s, spm_film *film,
                       spm_run_result *res, int *torn_down, spm_error *err)
{
    int spp = spm_render_spp(&o->cfg, &s->scene);
    size_t npix = (size_t)s->scene.width * (size_t)s->scene.height;
    checkpoint_ctx ck = {o, s};
    o->pass_spp = (int)spm_spp_per_pass(npix, spp);
    spm_run_opts ro = {.spp = spp, .spp_per_pass = (spm_u32)o->pass_spp, .stop = &spm_stop_flag,
                       .progress = o->progress};
    ro.start = (int)film->samples;
    ro.time_s = o->cfg.time_s;
    ro.contiguous = o->keep_film;
    if (o->checkpoint_s > 0) {
        ro.checkpoint_s = o->checkpoint_s;
        ro.checkpoint = checkpoint;
        ro.checkpoint_ctx = &ck;
    }
    spm_pocl_cache cache0 = spm_pocl_cache_now();
    double t0 = spm_now();
    int rc = spm_mpi_render_run(mpi, s, npix, &ro, film, res, err);
    s->times.render_s = spm_now() - t0;
    spm_pocl_cache cache1 = spm_pocl_cache_now();
    watch_compiles(o, s, &cache0, &cache1);
    *torn_down = res->interrupted;
    if (!rc && res->interrupted && spm_mpi_check_signalled(mpi, err)) {
        /* a rank died: what the others did is not what was asked for */
        fprintf(stderr, "specmip render: %s; no image written\n", err->msg);
        return SPM_EXIT_RUNTIME;
    }
    if (rc) {
        /* the render is not what was asked for: existing outputs stay */
        fprintf(stderr, "specmip render: %s; no image written\n", err->msg);
        return SPM_EXIT_RUNTIME;
    }
    if (res->interrupted && res->passes_in_film == 0) {
        fprintf(stderr, "specmip render: interrupted in the first pass (of %d samples per pixel); "
                        "nothing rendered, %s\n", (int)ro.spp_per_pass,
                ro.start ? "the outputs and film left as they were" : "no image written");
        return SPM_EXIT_INTERRUPTED;
    }
    return write_outputs(o, s, res, film);
}

int spm_cmd_render(int argc, char **argv)
{
    render_opts o;
    int rc = parse_args(argc, argv, &o);
    if (rc)
        return rc == HELP_SHOWN ? SPM_EXIT_OK : rc;
    if ((rc = check_outputs(&o)))
        return rc;
    spm_error err;
    err.msg[0] = 0;
    spm_mpi mpi;
    if (spm_mpi_start(&mpi, &err)) {
        fprintf(stderr, "specmip render: %s\n", err.msg);
        return SPM_EXIT_RUNTIME;
    }
    if (mpi.size > 1 && o.nspectral) {
        /* the ranks' pass images carry XYZ only */
        if (mpi.rank == 0)
            fprintf(stderr, "specmip render: a .spectral.exr output is not supported under "
                            "mpirun yet; render it in one process\n");
        spm_mpi_end(&mpi, 0);
        return SPM_EXIT_INPUT;
    }
    refuse_scene_files(&mpi);
    /* from here on a signal is acted on (interrupt.h), until the outputs are written */
    spm_catch_interrupts();
    if (mpi.rank > 0) { /* renders what rank 0 sends (and ends MPI); rank 0 alone reports and writes */
        rc = spm_mpi_worker(&mpi, &o.cfg);
        spm_release_interrupts();
        return rc;
    }
    /* from here on one way out: every step's failure ends at `out` */
    spm_render_setup s;
    spm_film film;
    spm_run_result res;
    memset(&s, 0, sizeof s);
    memset(&film, 0, sizeof film);
    int torn_down = 0, rendered = 0;
    /* an output we cannot write is reported before any work, not after */
    if (spm_output_check_all(o.outputs, o.nout, &err)) {
        fprintf(stderr, "specmip render: %s\n", err.msg);
        rc = SPM_EXIT_INPUT;
        spm_mpi_share(&mpi, rc, &o.cfg, NULL, &err);
        goto out;
    }
    rc = spm_render_setup_open(&o.cfg, &s, &err);
    if (!rc && o.keep_film)
        rc = prepare_film(&o, &s, &film, &err);
    if ((rc = spm_mpi_share(&mpi, rc, &o.cfg, &s, &err))) {
        fprintf(stderr, "specmip render: %s%s\n", err.msg,
                rc == SPM_EXIT_INTERRUPTED ? "; nothing rendered, no image written" : "");
        goto out;
    }
    /* the other ranks wait for passes after a failure here: mpirun ends them */
    if (o.white && spm_render_white(o.white, &s.scene, &s.geom, &o.tm, o.white_desc,
                                    sizeof o.white_desc, &err)) {
        fprintf(stderr, "specmip render: %s\n", err.msg);
        rc = SPM_EXIT_INPUT;
        goto out;
    }
    if (!film.sum && (spm_film_init(&film, s.scene.width, s.scene.height, &err) ||
                      (s.plan.nspec && spm_film_spectral_init(&film, s.plan.nspec, &err)))) {
        fprintf(stderr, "specmip render: %s\n", err.msg);
        rc = SPM_EXIT_INPUT;
        goto out;
    }
    rc = render_film(&o, &mpi, &s, &film, &res, &torn_down, &err);
    rendered = 1;
out:
    spm_release_interrupts();
    if (rendered) {
        /* both: the JSON keeps stdout to itself, the text goes to stderr */
        if (o.json)
            spm_render_stats_json(stdout, &o.cfg, &s, &res);
        if (o.stats)
            spm_render_stats_text(o.json ? stderr : stdout, &o.cfg, &s, &res);
    }
    spm_film_free(&film);
    spm_render_setup_close(&s);
    spm_mpi_end(&mpi, torn_down);
    return rc;
}
