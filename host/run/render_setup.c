#include "render_setup.h"
#include "scene_build.h"
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "film_spectral.h"
#include "interrupt.h"
#include "light_tree.h"
#include "render_hints.h"
#include "scene_hints.h"

typedef struct {
    int device;
    char name[256];
    const spm_render_config *c;
    const spm_render_plan *plan;
    spm_backend *b;
    spm_error err;
} device_open;

static void *open_one(void *arg)
{
    device_open *d = arg;
    spm_test_pause("build");
    d->b = (d->c->open_device ? d->c->open_device : d->c->backend->create)(d->device, d->plan,
                                                                          &d->err);
    return NULL;
}

int spm_render_spp(const spm_render_config *c, const spm_scene *sc)
{
    return c->spp ? c->spp : (sc->spp > 0 ? sc->spp : 16);
}

/* The device indices to open, checked: unknown or repeated ones are input
 * errors, and so is a render too large for a device's memory (said before any
 * buffer or program exists). A backend kind without devices opens index 0. */
static int device_list(const spm_render_config *c, const spm_render_setup *s, device_open *opens,
                       int *n, spm_error *err)
{
    const spm_backend_kind *k = c->backend;
    size_t npix = (size_t)s->scene.width * (size_t)s->scene.height;
    size_t paths_per_pass = npix * spm_spp_per_pass(npix, spm_render_spp(c, &s->scene));
    int list[SPM_MAX_BACKENDS];
    *n = 0;
    if (k->per_device && c->all_devices) {
        if (k->all_devices(list, n, SPM_MAX_BACKENDS, err))
            return SPM_EXIT_RUNTIME;
    } else if (k->per_device && c->ndevices) {
        for (int i = 0; i < c->ndevices && i < SPM_MAX_BACKENDS; i++)
            list[(*n)++] = c->devices[i];
    } else {
        list[(*n)++] = 0;
    }
    for (int i = 0; i < *n; i++) {
        for (int j = 0; j < i; j++)
            if (list[j] == list[i]) {
                spm_errorf(err, "device %d is listed twice", list[i]);
                return SPM_EXIT_INPUT;
            }
        memset(&opens[i], 0, sizeof opens[i]);
        opens[i].device = list[i];
        if (k->check && k->check(list[i], &s->plan, s->scene.width, s->scene.height,
                                 paths_per_pass, opens[i].name, err))
            return SPM_EXIT_INPUT;
    }
    return 0;
}

/* Each device builds its program in its own thread: builds run concurrently
 * (a thread that cannot be started opens its device in this one). */
static int open_devices(const spm_render_config *c, const spm_render_plan *plan,
                        spm_render_setup *s, spm_error *err)
{
    device_open opens[SPM_MAX_BACKENDS];
    int n, rc = device_list(c, s, opens, &n, err);
    if (rc)
        return rc;
    pthread_t th[SPM_MAX_BACKENDS];
    int threaded[SPM_MAX_BACKENDS];
    for (int i = 0; i < n; i++) {
        opens[i].c = c;
        opens[i].plan = plan;
        threaded[i] = n > 1 && pthread_create(&th[i], NULL, open_one, &opens[i]) == 0;
        if (!threaded[i])
            open_one(&opens[i]);
    }
    for (int i = 0; i < n; i++)
        if (threaded[i])
            pthread_join(th[i], NULL);
    for (int i = 0; i < n; i++) {
        if (opens[i].b) {
            s->device[s->nb] = opens[i].device;
            s->b[s->nb++] = opens[i].b;
        }
        else if (n > 1)
            fprintf(stderr, "specmip: device %d '%s' left out: %s\n", opens[i].device,
                    opens[i].name, opens[i].err.msg);
        else
            *err = opens[i].err;
    }
    if (!s->nb) {
        if (n > 1)
            spm_errorf(err, "none of the %d devices could be opened", n);
        return SPM_EXIT_RUNTIME;
    }
    return 0;
}

/* The exit code of a failed preparation step: the steps stop early, with an
 * error saying so, when interrupted. */
static int failed(void)
{
    return spm_stop_requested() ? SPM_EXIT_INTERRUPTED : SPM_EXIT_INPUT;
}

/* A signal during a step that cannot be interrupted is acted on right after it. */
static int interrupted_after(const char *what, spm_error *err)
{
    if (!spm_stop_requested())
        return 0;
    spm_errorf(err, "interrupted while %s", what);
    return 1;
}

/* The image size from --width/--height: both given, both used; one given, the
 * other follows the scene's aspect ratio, rounded, at least 1 and at most
 * SPM_SCENE_MAX_SIDE (other = given * scene_other / scene_given). */
void spm_render_size(int want_w, int want_h, int *w, int *h)
{
    if (want_w > 0 && want_h > 0) {
        *w = want_w;
        *h = want_h;
        return;
    }
    int *given = want_w > 0 ? w : h, *other = want_w > 0 ? h : w;
    int want = want_w > 0 ? want_w : want_h;
    if (want <= 0)
        return;
    double o = (double)want * *other / *given + 0.5;
    *other = o < 1 ? 1 : o > SPM_SCENE_MAX_SIDE ? SPM_SCENE_MAX_SIDE : (int)o;
    *given = want;
}

int spm_light_sampler_parse(const char *name)
{
    return !strcmp(name, "power") ? SPM_LIGHT_SAMPLER_POWER
           : !strcmp(name, "tree") ? SPM_LIGHT_SAMPLER_TREE : -1;
}

/* The tree where it wins: on many lights with a place (measured in
 * docs/LIGHT_TREE.md); by power on a few, whose images it keeps. */
static int use_tree(int sampler, const spm_geometry *g)
{
    int placed = 0;
    for (int i = 0; i < g->nemitters; i++)
        placed += spm_light_placed(g->emitters[i].kind);
    return sampler == SPM_LIGHT_SAMPLER_TREE ||
           (sampler == SPM_LIGHT_SAMPLER_AUTO && placed >= SPM_LIGHT_TREE_AUTO_MIN);
}

int spm_render_setup_levels(const spm_render_config *c, spm_render_setup *s, spm_error *err)
{
    const spm_mode_desc *m = &spm_modes[c->mode];
    return m->levelled && spm_tables_levels(&s->scene, &c->pretest, &s->tables, m->composite, err);
}

int spm_render_setup_open(const spm_render_config *c, spm_render_setup *s, spm_error *err)
{
    memset(s, 0, sizeof *s);
    double t0 = spm_now();
    int rc = c->scene_path ? spm_scene_load(c->scene_path, &s->scene, err)
                           : spm_scene_default(&s->scene, err);
    if (!rc)
        rc = spm_scene_camera_override(&s->scene, &c->cam, err);
    if (rc)
        return failed();
    spm_render_size(c->width, c->height, &s->scene.width, &s->scene.height);
    double t1 = spm_now();
    s->times.load_s = t1 - t0;
    /* the hint reads the triangles beside their conversion, before they are freed */
    rc = spm_geometry_build_consume(&s->scene, spm_scene_hints, &s->geom, err);
    double t2 = spm_now();
    s->times.bvh_s = t2 - t1;
    if (rc)
        return failed();
    spm_render_hint_emitters(&s->scene, &s->geom);
    rc = spm_tables_prepare(&s->scene, &c->pretest, &s->tables, err);
    if (!rc)
        rc = spm_render_setup_levels(c, s, err);
    if (!rc && use_tree(c->light_sampler, &s->geom))
        spm_light_tree_attach(&s->geom, s->tables.materials);
    s->times.tables_s = spm_now() - t2;
    if (rc)
        return failed();
    if (interrupted_after("preparing the scene", err))
        return SPM_EXIT_INTERRUPTED;
    if (c->verbose && spm_modes[c->mode].levelled) {
        const char **names = spm_xcalloc((size_t)s->scene.ncolours + 1, sizeof *names);
        for (int i = 0; i < s->scene.ncolours; i++)
            names[i] = s->scene.colours[i].name;
        /* mlc's levels come from its own pretest (the composite representation) */
        int composite = spm_modes[c->mode].composite;
        spm_pretest_print(stderr, names, composite ? s->tables.mlc_pretest : s->tables.pretest,
                          s->scene.ncolours, &c->pretest);
        free((void *)names);
    }
    return spm_render_setup_backends(c, s, err);
}

int spm_render_setup_backends(const spm_render_config *c, spm_render_setup *s, spm_error *err)
{
    int rc;
    if (spm_render_plan_init(&s->plan, &s->geom, &s->tables, c->mode, c->seed, err))
        return SPM_EXIT_INPUT;
    if ((c->integrator == SPM_INTEGRATOR_LIGHT && !c->backend->light) ||
        (c->integrator == SPM_INTEGRATOR_BDPT && !c->backend->bdpt)) {
        spm_errorf(err, "--integrator %s runs on the CPU reference only so far (--backend cpu)",
                   spm_integrator_name(c->integrator));
        return SPM_EXIT_INPUT;
    }
    if (spm_render_plan_integrator(&s->plan, c->integrator, err))
        return SPM_EXIT_INPUT;
    if (c->spec_nm) {
        int nb = !c->backend->per_device ? 1
                 : c->all_devices        ? SPM_MAX_BACKENDS
                 : c->ndevices           ? c->ndevices
                                         : 1;
        if (spm_render_plan_spectral(&s->plan, c->spec_nm, err) ||
            spm_film_spectral_check(s->scene.width, s->scene.height, s->plan.nspec, nb, err))
            return SPM_EXIT_INPUT;
    }
    double t3 = spm_now();
    rc = open_devices(c, &s->plan, s, err);
    s->times.kernels_s = spm_now() - t3;
    if (!rc && interrupted_after("building the OpenCL programs (a build cannot be interrupted)",
                                 err))
        return SPM_EXIT_INTERRUPTED;
    return rc;
}

void spm_render_setup_close(spm_render_setup *s)
{
    for (int i = 0; i < s->nb; i++)
        s->b[i]->destroy(s->b[i]);
    spm_render_plan_free(&s->plan);
    spm_tables_free(&s->tables);
    spm_geometry_free(&s->geom);
    spm_scene_free(&s->scene);
    memset(s, 0, sizeof *s);
}
