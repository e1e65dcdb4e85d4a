/* Shared set-up of the stability tests: render a bundled scene in-process on
 * OpenCL device 0 or a named backend (the same calls as `specmip render`), keep the image as
 * linear sRGB and the run's statistics, and compare two renders as
 * `specmip compare --blur 5` does. */
#ifndef SPM_RENDER_TESTLIB_H
#define SPM_RENDER_TESTLIB_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "colour.h"
#include "compare.h"
#include "backends.h"

/* Called with the open set-up before it is closed (tables, pretest results). */
typedef void (*rt_inspect_fn)(const spm_render_setup *s, void *ctx);

typedef struct {
    spm_image img;        /* linear sRGB, as an .exr output holds it */
    spm_run_result run;   /* timings and per-level path counts (what --stats prints) */
} rt_render_out;

typedef struct {
    const char *scene;    /* file name under scenes/ */
    int mode;
    int spp;
    spm_u32 seed;
    int size;             /* square image side */
    double threshold;     /* pretest threshold; 0: the default (2.0) */
    const char *backend;  /* backends.h's name; NULL: OpenCL device 0 */
} rt_render_job;

/* --light-sampler of every rt_render (render_setup.h SPM_LIGHT_SAMPLER_*;
 * 0: by the scene) */
static int rt_light_sampler;

/* A bundled scene's file name, or an absolute path as it is. */
static inline void rt_scene_path(const char *name, char *path, size_t n)
{
    if (name[0] == '/')
        snprintf(path, n, "%.1000s", name);
    else
        snprintf(path, n, "%s/scenes/%.200s", SPM_SOURCE_DIR, name);
}

/* Set by a test that renders one scene many times (strategies, seeds): the
 * scene, its BVH and its tables (the pretest: most of a small render's time)
 * are prepared once and kept while the scene file, size, threshold and light
 * sampler stay the same; each render opens its own backends and plan. The
 * scene file must not change under the same name while it is kept. */
static int rt_keep_scene;
static struct {
    char path[1024];
    int size, sampler, open;
    double threshold;
    spm_render_setup s;
} rt_kept;

static inline void rt_kept_free(void)
{
    if (rt_kept.open)
        spm_render_setup_close(&rt_kept.s);
    rt_kept.open = 0;
}

/* The set-up of cfg: kept (rt_keep_scene) or opened whole. */
static inline int rt_setup_open(const spm_render_config *cfg, const rt_render_job *j,
                                spm_render_setup *s, spm_error *err)
{
    if (!rt_keep_scene)
        return spm_render_setup_open(cfg, s, err);
    memset(s, 0, sizeof *s);
    if (!rt_kept.open || strcmp(rt_kept.path, cfg->scene_path) || rt_kept.size != j->size ||
        rt_kept.sampler != rt_light_sampler || rt_kept.threshold != j->threshold) {
        rt_kept_free();
        spm_render_config scene_only = *cfg;
        scene_only.backend = spm_backend_kind_find("cpu");
        if (spm_render_setup_open(&scene_only, &rt_kept.s, err)) {
            spm_render_setup_close(&rt_kept.s);
            return 1;
        }
        /* its backends and plan go; the scene, BVH and tables stay */
        for (int i = 0; i < rt_kept.s.nb; i++)
            rt_kept.s.b[i]->destroy(rt_kept.s.b[i]);
        spm_render_plan_free(&rt_kept.s.plan);
        rt_kept.s.nb = 0;
        snprintf(rt_kept.path, sizeof rt_kept.path, "%s", cfg->scene_path);
        rt_kept.size = j->size, rt_kept.sampler = rt_light_sampler;
        rt_kept.threshold = j->threshold, rt_kept.open = 1;
    }
    if (spm_render_setup_levels(cfg, &rt_kept.s, err))
        return 1;
    s->scene = rt_kept.s.scene, s->geom = rt_kept.s.geom, s->tables = rt_kept.s.tables;
    return spm_render_setup_backends(cfg, s, err);
}

static inline void rt_setup_close(spm_render_setup *s)
{
    if (!rt_keep_scene) {
        spm_render_setup_close(s);
        return;
    }
    for (int i = 0; i < s->nb; i++)
        s->b[i]->destroy(s->b[i]);
    spm_render_plan_free(&s->plan);
    memset(s, 0, sizeof *s);
}

/* 0, or prints why and returns 1. */
static inline int rt_render(const rt_render_job *j, rt_render_out *o, rt_inspect_fn inspect,
                            void *ctx)
{
    char path[1024];
    rt_scene_path(j->scene, path, sizeof path);
    spm_render_config cfg;
    spm_render_config_defaults(&cfg);
    cfg.scene_path = path;
    cfg.mode = j->mode;
    cfg.spp = j->spp;
    cfg.seed = j->seed;
    cfg.width = cfg.height = j->size;
    cfg.light_sampler = rt_light_sampler;
    if (j->threshold > 0)
        cfg.pretest.threshold = j->threshold;
    if (j->backend && !(cfg.backend = spm_backend_kind_find(j->backend))) {
        printf("no backend %s\n", j->backend);
        return 1;
    }
    spm_quiet_warnings = 1;
    memset(o, 0, sizeof *o);
    spm_render_setup s;
    spm_error err;
    err.msg[0] = 0;
    if (rt_setup_open(&cfg, j, &s, &err)) {
        printf("%s %s: set-up: %s\n", j->scene, spm_mode_name(j->mode), err.msg);
        rt_setup_close(&s);
        return 1;
    }
    size_t npix = (size_t)j->size * (size_t)j->size;
    spm_film film;
    int rc = spm_film_init(&film, j->size, j->size, &err);
    if (!rc) {
        spm_run_opts ro = {.spp = j->spp, .spp_per_pass = spm_spp_per_pass(npix, j->spp)};
        rc = spm_render_run(s.b, s.nb, npix, &ro, &film, &o->run, &err);
    }
    if (rc) {
        printf("%s %s: render: %s\n", j->scene, spm_mode_name(j->mode), err.msg);
    } else {
        float *xyz = malloc(3 * npix * sizeof *xyz);
        o->img.width = o->img.height = j->size;
        o->img.rgb = malloc(3 * npix * sizeof *o->img.rgb);
        spm_film_resolve(&film, xyz);
        for (size_t i = 0; i < npix; i++) {
            double x[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, r[3];
            spm_xyz_to_linear_srgb(x, r);
            for (int c = 0; c < 3; c++)
                o->img.rgb[3 * i + c] = (float)r[c];
        }
        free(xyz);
        if (inspect)
            inspect(&s, ctx);
    }
    spm_film_free(&film);
    rt_setup_close(&s);
    return rc ? 1 : 0;
}

/* ΔE00 statistics of b against the reference a after a 5x5 box blur (the
 * inputs are left untouched); map (may be NULL) gets the per-pixel ΔE00, to
 * free. 0, or prints why and returns 1. */
static inline int rt_compare_map(const spm_image *a, const spm_image *b, spm_de_stats *de00,
                                 double **map)
{
    size_t n = 3 * (size_t)a->width * (size_t)a->height;
    spm_image ca = *a, cb = *b;
    ca.rgb = malloc(n * sizeof(float));
    cb.rgb = malloc(n * sizeof(float));
    memcpy(ca.rgb, a->rgb, n * sizeof(float));
    memcpy(cb.rgb, b->rgb, n * sizeof(float));
    spm_compare_opts co = {5, 0.0};
    spm_compare_result res;
    memset(&res, 0, sizeof res);
    spm_error err;
    int rc = spm_compare_images(&ca, &cb, &co, &res, &err);
    if (rc) {
        printf("compare: %s\n", err.msg);
    } else {
        *de00 = res.de00;
        if (map) {
            *map = res.de00_map;
            res.de00_map = NULL;
        }
    }
    spm_compare_result_free(&res);
    free(ca.rgb);
    free(cb.rgb);
    return rc ? 1 : 0;
}

static inline int rt_compare(const spm_image *a, const spm_image *b, spm_de_stats *de00)
{
    return rt_compare_map(a, b, de00, NULL);
}

/* Index of the scene colour whose name starts with `name` (emissions carry
 * their scale, e.g. "f11*1000"), or -1. */
static inline int rt_colour(const spm_scene *sc, const char *name)
{
    size_t n = strlen(name);
    for (int i = 0; i < sc->ncolours; i++)
        if (!strncmp(sc->colours[i].name, name, n) &&
            (sc->colours[i].name[n] == 0 || sc->colours[i].name[n] == '*'))
            return i;
    return -1;
}

/* Paths shaded at level l (all set-by reasons). */
static inline unsigned long long rt_level_paths(const spm_run_result *r, int l)
{
    const uint64_t *lp = r->total.level_paths[l];
    return (unsigned long long)(lp[0] + lp[1] + lp[2]);
}
#endif
