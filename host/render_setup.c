#include "render_setup.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *mode_names[SPM_MODE_COUNT] = {"truth", "ref", "ml", "mlc", "hero", "rgb"};

const char *spm_mode_name(int mode)
{
    return mode >= 0 && mode < SPM_MODE_COUNT ? mode_names[mode] : "?";
}

int spm_mode_parse(const char *s)
{
    for (int m = 0; m < SPM_MODE_COUNT; m++)
        if (!strcmp(s, mode_names[m]))
            return m;
    return -1;
}

void spm_render_config_defaults(spm_render_config *c)
{
    memset(c, 0, sizeof *c);
    c->mode = SPM_MODE_ML;
    c->seed = 1;
    spm_pretest_defaults(&c->pretest);
}

int spm_render_setup_open(const spm_render_config *c, spm_render_setup *s, spm_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = c->scene_path ? spm_scene_load(c->scene_path, &s->scene, err)
                           : spm_scene_default(&s->scene, err);
    if (rc)
        return SPM_EXIT_INPUT;
    if (c->width > 0)
        s->scene.width = c->width;
    if (c->height > 0)
        s->scene.height = c->height;
    if (spm_geometry_build(&s->scene, &s->geom, err))
        return SPM_EXIT_INPUT;
    if (spm_tables_build(&s->scene, &c->pretest, &s->tables, err))
        return SPM_EXIT_INPUT;
    if (c->verbose) {
        const char **names = spm_xcalloc((size_t)s->scene.ncolours + 1, sizeof *names);
        for (int i = 0; i < s->scene.ncolours; i++)
            names[i] = s->scene.colours[i].name;
        spm_pretest_print(stderr, names, s->tables.pretest, s->scene.ncolours, &c->pretest);
        free((void *)names);
    }
    spm_backend_input in = {&s->geom, &s->tables, c->mode, c->seed};
    if (c->use_cpu) {
        s->b[s->nb++] = spm_backend_cpu_create(&in, err);
        return 0;
    }
    int ndev = c->ndevices ? c->ndevices : 1;
    int dev0 = 0;
    for (int i = 0; i < ndev; i++) {
        int d = c->ndevices ? c->devices[i] : dev0;
        spm_backend *b = spm_backend_cl_create(d, &in, err);
        if (!b)
            return SPM_EXIT_RUNTIME;
        s->b[s->nb++] = b;
    }
    return 0;
}

void spm_render_setup_close(spm_render_setup *s)
{
    for (int i = 0; i < s->nb; i++)
        s->b[i]->destroy(s->b[i]);
    spm_tables_free(&s->tables);
    spm_geometry_free(&s->geom);
    spm_scene_free(&s->scene);
    memset(s, 0, sizeof *s);
}
