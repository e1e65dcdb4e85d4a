/* The CPU reference as a backend: trace and shade in plain scalar C, a pass
 * in batches of whole pixels (backend_cpu.h). */
#include "backend_cpu.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cl_resources.h"
#include "interrupt.h"
#include "refcpu.h"

typedef struct {
    spm_backend_input in;
    size_t batch_paths;
    spm_path *paths; /* one batch's records, level bytes and XYZ */
    uint8_t *levels;
    float *xyz;
    size_t cap;
} cpu_impl;

void spm_pass_stats_add(spm_pass_stats *a, const spm_pass_stats *s)
{
    a->trace_s += s->trace_s;
    a->shade_s += s->shade_s;
    a->accum_s += s->accum_s;
    a->paths += s->paths;
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        for (int k = 0; k < 3; k++)
            a->level_paths[l][k] += s->level_paths[l][k];
    a->truncated += s->truncated;
    a->nonfinite += s->nonfinite;
    a->untimed += s->untimed;
}

int spm_pass_batch_end(const spm_pass_ctl *c, uint64_t paths_so_far)
{
    if (c && c->batch_done)
        c->batch_done(c->ctx, paths_so_far);
    spm_test_pause("pass");
    return c && c->stop && *c->stop;
}

void spm_count_levels(int mode, const spm_path *paths, const uint8_t *levels, size_t n,
                      spm_pass_stats *st)
{
    int per_path = mode == SPM_MODE_ML || mode == SPM_MODE_MLC;
    for (size_t i = 0; i < n; i++) {
        int lvl = per_path ? (int)(levels[i] & SPM_LEVEL_MASK) : 0;
        int by = per_path ? (int)((levels[i] >> SPM_SETBY_SHIFT) & 3u) : SPM_SETBY_NONE;
        if (lvl >= SPM_NUM_LEVELS)
            lvl = SPM_NUM_LEVELS - 1;
        st->level_paths[lvl][by > 2 ? 0 : by]++;
        st->truncated += paths[i].h.end == SPM_END_TRUNCATED;
    }
    st->paths += n;
}

void spm_accumulate_pass(const float *xyz, size_t npix, spm_u32 spp, float *pass_xyz,
                         spm_pass_stats *st)
{
    for (size_t p = 0; p < npix; p++) {
        float s[3] = {0.0f, 0.0f, 0.0f};
        for (spm_u32 k = 0; k < spp; k++) {
            const float *x = &xyz[(p * spp + k) * 3];
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) {
                st->nonfinite++;
                continue;
            }
            s[0] += x[0];
            s[1] += x[1];
            s[2] += x[2];
        }
        memcpy(&pass_xyz[p * 3], s, sizeof s);
    }
}

/* Room for n paths; only grows. */
static void reserve(cpu_impl *c, size_t n)
{
    if (n <= c->cap)
        return;
    free(c->paths);
    free(c->levels);
    free(c->xyz);
    c->paths = spm_xmalloc(n * sizeof *c->paths);
    c->levels = spm_xmalloc(n);
    c->xyz = spm_xmalloc(n * 3 * sizeof(float));
    c->cap = n;
}

/* Paths [i0, i0 + n) of the pass into the batch buffers. */
static void trace_batch(cpu_impl *c, const spm_trace_params *p, int start_level, size_t i0,
                        size_t n)
{
    const spm_tables *t = c->in.tables;
    const uint8_t *lvlk = c->in.mode == SPM_MODE_MLC ? t->mlc_lvlk : t->lvlk;
    spm_ref_trace_range(c->in.geom, t->materials, lvlk, start_level, p, i0, i0 + n,
                        c->paths, c->levels);
}

static int cpu_pass(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                    spm_pass_stats *st, spm_error *err)
{
    (void)err;
    cpu_impl *c = b->impl;
    const spm_geometry *g = c->in.geom;
    const spm_tables *t = c->in.tables;
    size_t npix = (size_t)g->cam.width * (size_t)g->cam.height;
    if (spp == 0)
        return 0;
    size_t batch = c->batch_paths;
    size_t bpix = spm_cl_batch_pixels(npix, spp, batch);
    reserve(c, spm_cl_batch_room(npix, spp, batch));
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.cam = g->cam;
    p.ntris = (spm_u32)g->ntris;
    p.nemitters = (spm_u32)g->nemitters;
    p.bg_up = t->bg_up;
    p.bg_down = t->bg_down;
    p.seed = c->in.seed;
    p.spp_per_pass = spp;
    p.first_sample = first_sample;
    int start = spm_ref_level_start(g, t->materials,
                                    c->in.mode == SPM_MODE_MLC ? t->mlc_lvlk : t->lvlk, &p);
    for (size_t p0 = 0; p0 < npix; p0 += bpix) {
        size_t nb = npix - p0 < bpix ? npix - p0 : bpix, n = nb * spp;
        double t0 = spm_now();
        trace_batch(c, &p, start, p0 * spp, n);
        double t1 = spm_now();
        spm_ref_shade(t, c->in.mode, &p, p0 * spp, c->paths, c->levels, n, c->xyz);
        double t2 = spm_now();
        spm_accumulate_pass(c->xyz, nb, spp, &pass_xyz[3 * p0], st);
        spm_count_levels(c->in.mode, c->paths, c->levels, n, st);
        st->trace_s += t1 - t0;
        st->shade_s += t2 - t1;
        st->accum_s += spm_now() - t2;
        if (p0 + nb < npix && spm_pass_batch_end(&b->ctl, (p0 + nb) * spp))
            return SPM_PASS_STOPPED;
    }
    return 0;
}

void spm_backend_cpu_set_batch_paths(spm_backend *b, size_t paths)
{
    cpu_impl *c = b->impl;
    c->batch_paths = paths ? paths : SPM_CPU_BATCH_PATHS;
}

size_t spm_backend_cpu_batch_capacity(const spm_backend *b)
{
    const cpu_impl *c = b->impl;
    return c->cap;
}

static void cpu_destroy(spm_backend *b)
{
    cpu_impl *c = b->impl;
    free(c->paths);
    free(c->levels);
    free(c->xyz);
    free(c);
    free(b);
}

spm_backend *spm_backend_cpu_create(const spm_backend_input *in, spm_error *err)
{
    (void)err;
    spm_backend *b = spm_xcalloc(1, sizeof *b);
    cpu_impl *c = spm_xcalloc(1, sizeof *c);
    c->in = *in;
    c->batch_paths = SPM_CPU_BATCH_PATHS;
    b->impl = c;
    b->pass = cpu_pass;
    b->destroy = cpu_destroy;
    snprintf(b->name, sizeof b->name, "cpu-reference");
    return b;
}
