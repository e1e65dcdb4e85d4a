/* The CPU reference as a backend: trace and shade in plain scalar C, a pass
 * in batches of whole pixels (backend_cpu.h). */
#include "backend_cpu.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "refcpu.h"
#include "refcpu_bdpt.h"

typedef struct {
    const spm_render_plan *plan;
    size_t batch_paths;
    spm_path *paths; /* one batch's records, level bytes and XYZ */
    uint8_t *levels;
    float *xyz;
    size_t cap;
    int ch; /* floats a path record and a pass pixel hold (render_plan.h pix_ch) */
    /* the light integrator's: one chunk's subpaths, their splats, the
     * fixed-point sums (film_splat.h) */
    spm_light_path *lpaths;
    uint8_t *llevels;
    spm_splats splats;
    spm_splat_acc acc;
} cpu_impl;

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
    c->xyz = spm_xmalloc(n * (size_t)c->ch * sizeof(float));
    c->cap = n;
}

/* A pass of the light or bidirectional integrator: npix spp subpaths (or
 * samples) in chunks of SPM_SPLAT_CHUNK (film_splat.h), each traced, shaded
 * into its splats and added to the pass image in fixed point. */
static int cpu_light_pass(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                          spm_pass_stats *st)
{
    cpu_impl *c = b->impl;
    const spm_render_plan *pl = c->plan;
    size_t n = pl->npix * spp;
    if (!c->lpaths) {
        c->lpaths = spm_xmalloc(SPM_SPLAT_CHUNK * sizeof *c->lpaths);
        c->llevels = spm_xmalloc(SPM_SPLAT_CHUNK);
        spm_splats_init(&c->splats, c->ch);
        spm_splat_acc_init(&c->acc, pl->npix, c->ch);
    }
    memset(pass_xyz, 0, pl->npix * (size_t)c->ch * sizeof *pass_xyz);
    spm_trace_params p = spm_plan_pass_params(pl, first_sample, spp);
    for (size_t c0 = 0; c0 < n; c0 += SPM_SPLAT_CHUNK) {
        size_t nb = n - c0 < SPM_SPLAT_CHUNK ? n - c0 : SPM_SPLAT_CHUNK;
        double t0 = spm_now(), t1 = t0;
        size_t hist[256] = {0}, ncount = nb;
        c->splats.n = 0;
        if (pl->integrator == SPM_INTEGRATOR_BDPT) { /* traced and shaded per sample */
            spm_ref_bdpt_range(pl->geom, pl->tables->materials, pl->lvlk, (int)pl->start_level,
                               pl->mode, pl->shade, pl->spec, c->ch, &p, c0, c0 + nb, &c->splats,
                               hist);
            ncount = c->splats.n;
        } else {
            spm_ref_light_trace_range(pl->geom, pl->tables->materials, pl->lvlk,
                                      (int)pl->start_level, &p, c0, c0 + nb, c->lpaths, c->llevels);
            t1 = spm_now();
            spm_ref_shade_splats(pl->mode, pl->shade, pl->spec, c->ch, &p, c0, c->lpaths,
                                 c->llevels, nb, &c->splats);
            for (size_t i = 0; i < nb; i++) {
                hist[c->llevels[i]]++;
                st->truncated += c->lpaths[i].p.h.end == SPM_END_TRUNCATED;
            }
        }
        double t2 = spm_now();
        spm_splats_add_chunk(&c->acc, &c->splats, pass_xyz, &st->nonfinite);
        spm_count_levels_hist(pl->mode, hist, ncount, st);
        st->trace_s += t1 - t0;
        st->shade_s += t2 - t1;
        st->accum_s += spm_now() - t2;
        if (c0 + nb < n && spm_pass_batch_end(&b->ctl, c0 + nb))
            return SPM_PASS_STOPPED;
    }
    return 0;
}

static int cpu_pass(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                    spm_pass_stats *st, spm_error *err)
{
    (void)err;
    cpu_impl *c = b->impl;
    if (c->plan->integrator != SPM_INTEGRATOR_PATH)
        return spp ? cpu_light_pass(b, first_sample, spp, pass_xyz, st) : 0;
    const spm_render_plan *pl = c->plan;
    size_t npix = pl->npix;
    if (spp == 0)
        return 0;
    size_t batch = c->batch_paths;
    size_t bpix = spm_batch_pixels(npix, spp, batch); /* pixels a batch */
    reserve(c, spm_batch_room(npix, spp, batch));
    spm_trace_params p = spm_plan_pass_params(pl, first_sample, spp);
    for (size_t p0 = 0; p0 < npix; p0 += bpix) {
        size_t nb = npix - p0 < bpix ? npix - p0 : bpix, n = nb * spp;
        double t0 = spm_now();
        spm_ref_trace_range(pl->geom, pl->tables->materials, pl->lvlk, (int)pl->start_level, &p,
                            p0 * spp, p0 * spp + n, c->paths, c->levels);
        double t1 = spm_now();
        spm_ref_shade_spectral(pl->mode, pl->shade, pl->spec, c->ch, &p, p0 * spp, c->paths,
                               c->levels, n, c->xyz);
        double t2 = spm_now();
        spm_accumulate_pass_ch(c->xyz, nb, spp, c->ch, &pass_xyz[(size_t)c->ch * p0], st);
        spm_count_levels(pl->mode, c->paths, c->levels, n, st);
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
    c->batch_paths = paths ? paths : spm_plan_batch_paths(SPM_CPU_BATCH_PATHS, c->ch, c->plan->vertex_bytes);
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
    free(c->lpaths);
    free(c->llevels);
    spm_splats_free(&c->splats);
    spm_splat_acc_free(&c->acc);
    free(c);
    free(b);
}

spm_backend *spm_backend_cpu_create(const spm_render_plan *plan, spm_error *err)
{
    (void)err;
    spm_backend *b = spm_xcalloc(1, sizeof *b);
    cpu_impl *c = spm_xcalloc(1, sizeof *c);
    c->plan = plan;
    c->ch = plan->pix_ch;
    c->batch_paths = spm_plan_batch_paths(SPM_CPU_BATCH_PATHS, c->ch, c->plan->vertex_bytes);
    b->impl = c;
    b->pass = cpu_pass;
    b->destroy = cpu_destroy;
    snprintf(b->name, sizeof b->name, "cpu-reference");
    return b;
}

static spm_backend *create_kind(int device, const spm_render_plan *plan, spm_error *err)
{
    (void)device;
    return spm_backend_cpu_create(plan, err);
}

const spm_backend_kind spm_backend_kind_cpu = {.name = "cpu", .light = 1, .bdpt = 1, .create = create_kind};
