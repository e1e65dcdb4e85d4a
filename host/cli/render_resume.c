/* Continuing a render from its saved film (render_resume.h). */
#include "render_resume.h"
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "image_io.h"
#include "prepared.h"

void spm_render_print(const spm_render_config *c, const spm_render_setup *s, spm_film_print *p)
{
    memset(p, 0, sizeof *p);
    const spm_mode_desc *m = spm_mode(c->mode);
    spm_film_print_add(p, 1, "scene", "%016" PRIx64, spm_prepared_hash(&s->geom, &s->tables));
    spm_film_print_add(p, 1, "mode", "%s", m->name);
    spm_film_print_add(p, 1, "integrator", "%s", spm_integrator_name(c->integrator));
    spm_film_print_add(p, 1, "size", "%dx%d", s->scene.width, s->scene.height);
    spm_film_print_add(p, 1, "seed", "%u", c->seed);
    if (s->plan.nspec)
        spm_film_print_add(p, 1, "spectral", "%d bins of %d nm", s->plan.nspec, c->spec_nm);
    else
        spm_film_print_add(p, 1, "spectral", "none");
    if (m->levelled) {
        spm_film_print_add(p, 1, "threshold", "%.9g", c->pretest.threshold);
        spm_film_print_add(p, 1, "metric", "%s",
                           c->pretest.metric == SPM_METRIC_DEAB ? "deab" : "de00");
        spm_film_print_add(p, 1, "coarsest-level", "%d", c->pretest.coarsest_level);
    }
    spm_film_print_add(p, 0, "scene-path", "%s", s->scene.path);
    spm_film_print_add(p, 0, "backend", "%s", c->backend->name);
    spm_film_print_add(p, 0, "version", "%s", SPM_VERSION);
}

/* The film file the EXR names, in the EXR's directory, into path[size]. */
static int film_of(const char *exr, char *path, size_t size, spm_error *err)
{
    char name[256];
    int has = spm_image_read_string_attr(exr, "specmip:film", name, sizeof name, err);
    if (has < 0)
        return SPM_EXIT_INPUT;
    if (!has) {
        spm_errorf(err, "%s: names no film to resume from (render with --film or --checkpoint "
                        "to keep one)", exr);
        return SPM_EXIT_INPUT;
    }
    if (!name[0] || strchr(name, '/') || !strcmp(name, ".") || !strcmp(name, "..")) {
        spm_errorf(err, "%s: its film '%s' is not a file name in its directory", exr, name);
        return SPM_EXIT_INPUT;
    }
    const char *slash = strrchr(exr, '/');
    snprintf(path, size, "%.*s%s", slash ? (int)(slash - exr + 1) : 0, exr, name);
    return 0;
}

int spm_resume_load(const char *exr, const spm_film_print *now, int spp, int pass_spp,
                    spm_film *film, spm_error *err)
{
    char path[4352];
    int rc = film_of(exr, path, sizeof path, err);
    if (rc)
        return rc;
    spm_film_print saved;
    int saved_pass = 0;
    if (spm_film_load(path, film, &saved, &saved_pass, err))
        return SPM_EXIT_INPUT;
    if (!spm_film_print_get(&saved, "integrator")) /* a film from before the light integrator */
        spm_film_print_add(&saved, 1, "integrator", "%s", spm_integrator_name(SPM_INTEGRATOR_PATH));
    char diff[2048];
    if (spm_film_print_diff(&saved, now, "scene", diff, sizeof diff)) {
        const char *was = spm_film_print_get(&saved, "scene-path");
        const char *is = spm_film_print_get(now, "scene-path");
        int scene = !strncmp(diff, "scene ", 6);
        spm_errorf(err, "%s: the film is of another render: %s%s%s%s%s%s", path,
                   scene ? "the scene's contents (its fingerprint " : "", diff, scene ? ")" : "",
                   scene && was ? ", rendered from " : "", scene && was ? was : "",
                   scene && was && is && strcmp(was, is) ? ", now another file" : "");
        goto refused;
    }
    if (film->samples >= spp) {
        spm_errorf(err, "%s: the film holds %lld samples per pixel already; ask for more to "
                        "resume (--spp, or --time alone)", path, film->samples);
        goto refused;
    }
    const char *was = spm_film_print_get(&saved, "backend");
    const char *is = spm_film_print_get(now, "backend");
    if (was && is && strcmp(was, is))
        spm_warnf("%s was rendered on backend %s, continued on %s: the image is not "
                  "bit-identical to one render on either", path, was, is);
    if (film->samples % pass_spp)
        spm_warnf("%s holds %lld samples per pixel, not a whole number of this render's passes "
                  "of %d: the image is not bit-identical to one render to %d (docs/RENDERING.md)",
                  path, film->samples, pass_spp, spp);
    return 0;
refused:
    spm_film_free(film);
    return SPM_EXIT_INPUT;
}
