#include "render_meta.h"
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "scene_build.h"

static spm_image_attr *add(spm_render_meta *m, const char *name, spm_attr_type type)
{
    spm_image_attr *a = &m->a[m->n++];
    memset(a, 0, sizeof *a);
    a->name = name;
    a->type = type;
    return a;
}

static void add_int(spm_render_meta *m, const char *name, int v)
{
    add(m, name, SPM_ATTR_INT)->i = v;
}

static void add_string(spm_render_meta *m, const char *name, const char *v)
{
    add(m, name, SPM_ATTR_STRING)->s = v;
}

void spm_render_meta_make(const spm_render_config *c, const spm_render_setup *s,
                          const spm_run_result *r, double render_s, spm_render_meta *m)
{
    memset(m, 0, sizeof *m);
    int spp = spm_render_spp(c, &s->scene);
    const char *mode = spm_mode_name(c->mode);
    int levelled = spm_mode(c->mode)->levelled;
    snprintf(m->software, sizeof m->software, "specmip %s", SPM_VERSION);
    snprintf(m->description, sizeof m->description,
             "specmip %s render of %.900s: mode %s, %d of %d samples per pixel, seed %u",
             SPM_VERSION, s->scene.path, mode, r->spp_done, spp, c->seed);
    if (c->time_s > 0 && spp == SPM_SCENE_MAX_SPP) /* no --spp: the budget alone decides */
        snprintf(m->description, sizeof m->description,
                 "specmip %s render of %.900s: mode %s, %d samples per pixel in a %g s budget, "
                 "seed %u", SPM_VERSION, s->scene.path, mode, r->spp_done, c->time_s, c->seed);
    size_t used = 0;
    for (int i = 0; i < s->nb && used + 1 < sizeof m->devices; i++) {
        int w = snprintf(m->devices + used, sizeof m->devices - used, "%s%s", i ? "; " : "",
                         s->b[i]->name);
        used += w > 0 ? (size_t)w : 0;
    }
    time_t now = time(NULL);
    struct tm tm;
    if (localtime_r(&now, &tm))
        strftime(m->datetime, sizeof m->datetime, "%Y:%m:%d %H:%M:%S", &tm);

    add_string(m, "Software", m->software);
    add_string(m, "ImageDescription", m->description);
    if (m->datetime[0])
        add_string(m, "DateTime", m->datetime);
    add_string(m, "specmip:version", SPM_VERSION);
    add_string(m, "specmip:scene", s->scene.path);
    add_string(m, "specmip:mode", mode);
    if (c->integrator != SPM_INTEGRATOR_PATH)
        add_string(m, "specmip:integrator", spm_integrator_name(c->integrator));
    add_int(m, "samplesPerPixel", r->spp_done);
    if (!(c->time_s > 0 && spp == SPM_SCENE_MAX_SPP))
        add_int(m, "specmip:samplesPerPixelRequested", spp);
    /* text: EXR has no unsigned integer, and seeds go up to 2^32 - 1 */
    snprintf(m->seed, sizeof m->seed, "%u", c->seed);
    add_string(m, "specmip:seed", m->seed);
    if (levelled) {
        add(m, "specmip:threshold", SPM_ATTR_FLOAT)->f = (float)c->pretest.threshold;
        add_string(m, "specmip:metric", c->pretest.metric == SPM_METRIC_DEAB ? "deab" : "de00");
        add_int(m, "specmip:coarsestLevel", c->pretest.coarsest_level);
    }
    add(m, "renderTimeSeconds", SPM_ATTR_FLOAT)->f = (float)render_s;
    if (c->time_s > 0)
        add(m, "specmip:timeBudgetSeconds", SPM_ATTR_FLOAT)->f = (float)c->time_s;
    if (c->film_name)
        add_string(m, "specmip:film", c->film_name);
    add_string(m, "specmip:devices", m->devices);
}
