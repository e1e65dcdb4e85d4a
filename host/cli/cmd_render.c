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

#define MAX_OUTPUTS 4


static void usage(FILE *f)
{
    fprintf(f,
        "usage: specmip render [SCENE] [options]   (also: specmip SCENE [options])\n"
        "Options take their value as '--spp 16' or '--spp=16'.\n"
        "Renders SCENE (a .scene file, a MiniLight .ml.txt file or a pbrt-v4 .pbrt file,\n"
        "docs/PBRT.md); without SCENE the built-in Cornell box (ColorChecker walls,\n"
        "equal-energy light).\n\n");
    spm_opt_help(f, SPM_CMD_RENDER, 25);
    fprintf(f,
        "Under mpirun every rank renders passes on its own --device/--backend; rank 0 reads\n"
        "the scene, sends it to the others and alone writes outputs (README: several machines).\n"
        "Ctrl-C (or SIGTERM) stops within a batch of paths, writes the image of the passes done\n"
        "and exits 130 (nothing is written when no pass is done); a second Ctrl-C exits at once\n"
        "without writing. Existing outputs are replaced only by complete images.\n");
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
    case SPM_O_ALLOW_PATH:
        if (spm_paths_allow(v, &e)) {
            fprintf(stderr, "specmip render: %s\n", e.msg);
            return SPM_EXIT_INPUT;
        }
        return 0;
    case SPM_O_DEVICE:
        return spm_opt_devices("render", v, o->cfg.devices, SPM_MAX_BACKENDS, &o->cfg.ndevices,
                               &o->cfg.all_devices) ? SPM_EXIT_INPUT : 0;
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
        case SPM_O_QUIET: o->progress = 0; break;
        case SPM_O_VERBOSE: o->cfg.verbose = 1; break;
        case SPM_O_STRICT: spm_scene_strict = 1; break;
        default:
            if (word_option(it.opt->id, it.value, o))
                return SPM_EXIT_INPUT;
        }
    }
    if (more < 0)
        return SPM_EXIT_INPUT;
    return 0;
}

/* The outputs, by default an image and an EXR; spectral ones need a spectral
 * mode, at one of its bin widths. */
static int check_outputs(render_opts *o)
{
    if (!o->nout) {
        o->outputs[o->nout++] = "specmip.png";
        o->outputs[o->nout++] = "specmip.exr";
    }
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
 * cache that grew meanwhile is another process's). */
static void watch_compiles(const render_opts *o, spm_render_setup *s, const spm_pocl_cache *c0,
                           const spm_pocl_cache *c1)
{
    s->times.compiled_in_render = o->cfg.backend->compiles ? spm_pocl_cache_grew(c0, c1) : -1;
    if (s->times.compiled_in_render == 1) {
        char dir[4096];
        fprintf(stderr, "specmip render: WARNING: PoCL's kernel cache %s gained %lld files "
                        "during the render: kernels were compiled (by this render, unless another "
                        "process shares the cache), and the render time may include that\n",
                spm_pocl_cache_dir(dir, sizeof dir), c1->files - (c0->files > 0 ? c0->files : 0));
    }
}

/* The images of a render loop that ended without error; the exit code. */
static int write_outputs(const render_opts *o, spm_render_setup *s, const spm_run_result *res,
                         spm_film *film, spm_error *err)
{
    int rc = 0, spp = spm_render_spp(&o->cfg, &s->scene);
    spm_render_warn_dropped(res, film);
    if (!res->interrupted)
        spm_render_hint_black(film);
    /* the image so far after an interruption; a signal now is acted on
     * after the writes (an image write cannot be interrupted) */
    spm_render_meta meta;
    spm_render_meta_make(&o->cfg, s, res, s->times.render_s, &meta);
    if (o->white && meta.n < SPM_META_MAX)
        meta.a[meta.n++] = (spm_image_attr){"specmip:white", SPM_ATTR_STRING, 0, 0, o->white_desc};
    double t0 = spm_now();
    for (int i = 0; i < o->nout; i++)
        if (spm_spectral_path(o->outputs[i])
                ? spm_spectral_exr_write(o->outputs[i], film, meta.a, meta.n, err)
                : spm_output_write_film_attrs(o->outputs[i], film, &o->tm, meta.a, meta.n, err)) {
            fprintf(stderr, "specmip render: %s\n", err->msg);
            rc = SPM_EXIT_RUNTIME;
        }
    s->times.output_s = spm_now() - t0;
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

/* Rank 0's render loop over the film, then the images; the exit code.
 * *torn_down: mpirun is ending every rank (an interrupted render). */
static int render_film(const render_opts *o, spm_mpi *mpi, spm_render_setup *s, spm_film *film,
                       spm_run_result *res, int *torn_down, spm_error *err)
{
    int spp = spm_render_spp(&o->cfg, &s->scene);
    size_t npix = (size_t)s->scene.width * (size_t)s->scene.height;
    spm_run_opts ro = {spp, spm_spp_per_pass(npix, spp), &spm_stop_flag, o->progress};
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
    if (res->interrupted && res->spp_done == 0) {
        fprintf(stderr, "specmip render: interrupted in the first pass (of %d samples per pixel); "
                        "nothing rendered, no image written\n", (int)ro.spp_per_pass);
        return SPM_EXIT_INTERRUPTED;
    }
    return write_outputs(o, s, res, film, err);
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
    if (spm_film_init(&film, s.scene.width, s.scene.height, &err) ||
        (s.plan.nspec && spm_film_spectral_init(&film, s.plan.nspec, &err))) {
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
