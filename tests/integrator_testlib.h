/* What the integrator tests share (test_light_integrator.c, test_bdpt_converge.c):
 * a scene loaded at a square size, one pass of a CPU-reference render as
 * XYZ per pixel, and variants of a scene file made by replacing lines. */
#ifndef SPM_INTEGRATOR_TESTLIB_H
#define SPM_INTEGRATOR_TESTLIB_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "backend_cpu.h"
#include "render_plan.h"
#include "scene.h"
#include "tables.h"
#include "testutil.h"

typedef struct {
    spm_scene sc;
    spm_geometry g;
    spm_tables t;
} it_scene;

static inline int it_load(it_scene *s, const char *path, int side)
{
    spm_error err;
    spm_pretest_opts po;
    spm_pretest_defaults(&po);
    if (spm_scene_load(path, &s->sc, &err)) {
        CHECK(0, "%s", err.msg);
        return 1;
    }
    s->sc.width = s->sc.height = side;
    if (spm_geometry_build(&s->sc, &s->g, &err) || spm_tables_build(&s->sc, &po, &s->t, &err)) {
        CHECK(0, "%s", err.msg);
        return 1;
    }
    return 0;
}

static inline void it_free(it_scene *s)
{
    spm_tables_free(&s->t);
    spm_geometry_free(&s->g);
    spm_scene_free(&s->sc);
}

static inline int it_plan(spm_render_plan *p, const it_scene *s, int mode, int integrator,
                          spm_u32 seed)
{
    spm_error err;
    if (spm_render_plan_init(p, &s->g, &s->t, mode, seed, &err) ||
        spm_render_plan_integrator(p, integrator, &err)) {
        CHECK(0, "%s", err.msg);
        return 1;
    }
    return 0;
}

/* One pass of spp samples per pixel on the CPU reference: XYZ per pixel into
 * y (the pass's sum over spp, divided by spp). */
static inline int it_render_xyz(const it_scene *s, int mode, int integrator, spm_u32 seed,
                                int spp, double *y)
{
    spm_render_plan p;
    spm_error err;
    if (it_plan(&p, s, mode, integrator, seed))
        return 1;
    spm_backend *b = spm_backend_cpu_create(&p, &err);
    float *img = calloc(p.npix * 3, sizeof *img);
    spm_pass_stats st;
    memset(&st, 0, sizeof st);
    int rc = b->pass(b, 0, (spm_u32)spp, img, &st, &err);
    CHECK(rc == 0, "pass: %s", err.msg);
    for (size_t i = 0; i < 3 * p.npix; i++)
        y[i] = img[i] / (double)spp;
    free(img);
    b->destroy(b);
    spm_render_plan_free(&p);
    return rc;
}

/* A variant of scene file src into path: each line starting with sub[k][0]
 * replaced by sub[k][1] (n of them, each once). */
static inline int it_write_variant(const char *src, const char *path, const char *const (*sub)[2],
                                   int n)
{
    FILE *in = fopen(src, "r"), *out = fopen(path, "w");
    char line[1024];
    int done = 0;
    while (in && out && fgets(line, sizeof line, in)) {
        int k = 0;
        while (k < n && strncmp(line, sub[k][0], strlen(sub[k][0])))
            k++;
        done += k < n;
        fputs(k < n ? sub[k][1] : line, out);
    }
    if (in)
        fclose(in);
    if (out)
        fclose(out);
    CHECK(done == n, "%s: %d of the %d lines replaced", src, done, n);
    return done != n;
}
#endif
