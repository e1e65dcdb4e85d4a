/* The OpenCL render backend (backend_cl.h): the handle, and the pass
 * pipeline trace -> bucket -> shade -> accumulate, batch by batch. Its other
 * parts are listed in cl_renderer.h. */
#include <stdlib.h>
#include <string.h>
#include "cl_renderer.h"
#include "cl_resources.h"

int spm_cl_create_plan(int device, const spm_render_plan *plan, spm_cl_renderer **out,
                       spm_error *err)
{
    *out = NULL;
    spm_cl_renderer *r = spm_xcalloc(1, sizeof *r);
    r->mode = plan->mode;
    r->npix = plan->npix;
    r->pix_ch = plan->pix_ch;
    r->ndisp = plan->geom->ndisp;
    r->vertex_bytes = plan->vertex_bytes;
    if (plan->integrator == SPM_INTEGRATOR_BDPT) /* every vertex has its words (-DSPM_BDPT) */
        r->vertex_bytes = sizeof(spm_vertex) + sizeof(spm_vertex_ext);
    r->batch_paths = spm_plan_batch_paths(SPM_CL_BATCH_PATHS, r->pix_ch, r->vertex_bytes);
    r->run_pass = spm_clr_render_pass;
    spm_clr_fail_init(r, device);
    r->params = plan->params;
    r->init_level = plan->start_level;
    int rc = spm_cl_ctx_create(device, &r->cl, err) || spm_clr_upload(r, plan, err) ||
             spm_clr_build(r, plan, err) || spm_clr_warm_up(r, err);
    if (rc) {
        spm_cl_destroy(r);
        return 1;
    }
    *out = r;
    return 0;
}

int spm_cl_create(int device, const spm_geometry *g, const spm_tables *t, int mode, spm_u32 seed,
                  spm_cl_renderer **out, spm_error *err)
{
    spm_render_plan plan;
    *out = NULL;
    if (spm_render_plan_init(&plan, g, t, mode, seed, err))
        return 1;
    int rc = spm_cl_create_plan(device, &plan, out, err);
    spm_render_plan_free(&plan);
    return rc;
}

void spm_cl_destroy(spm_cl_renderer *r)
{
    if (!r)
        return;
    if (r->cl.queue)
        clFinish(r->cl.queue);
    for (int s = 0; s < NSLOTS; s++)
        if (r->k_shade[s])
            clReleaseKernel(r->k_shade[s]);
    if (r->k_trace)
        clReleaseKernel(r->k_trace);
    if (r->k_accum)
        clReleaseKernel(r->k_accum);
    spm_clr_light_release(r);
    spm_clr_bdpt_release(r);
    if (r->prog)
        clReleaseProgram(r->prog);
    spm_clr_release_buffers(r);
    spm_cl_ctx_release(&r->cl);
    free(r->h_levels);
    free(r->h_idx);
    free(r);
}

int spm_clr_each_batch(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, int zero_counters,
                       spm_clr_batch_fn fn, void *ctx, spm_error *err)
{
    if (spp == 0)
        return 0;
    size_t bpix = spm_batch_pixels(r->npix, spp, r->batch_paths); /* pixels a batch */
    if (spm_clr_reserve(r, spm_batch_room(r->npix, spp, r->batch_paths), err) ||
        (zero_counters && spm_clr_zero_counters(r, err)))
        return 1;
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        size_t np = r->npix - p0 < bpix ? r->npix - p0 : bpix;
        batch b = {first_sample, spp, (spm_u32)p0, (spm_u32)np, np * spp, bpix * spp};
        rc = fn(r, &b, ctx, err);
    }
    return rc;
}

int spm_clr_zero_counters(spm_cl_renderer *r, spm_error *err)
{
    CK(clEnqueueWriteBuffer(r->cl.queue, r->counters, CL_FALSE, 0, sizeof r->zero, r->zero, 0,
                            NULL, NULL),
       "clEnqueueWriteBuffer(counters)");
    return 0;
}

/* h[b] = how many of the n bytes equal b. Four partial counts: with one, a run
 * of equal bytes (every path at one level) chains each increment to the last
 * through memory, 3.5x slower (measured). */
static void byte_histogram(const uint8_t *v, size_t n, size_t h[256])
{
    size_t part[4][256] = {{0}};
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        part[0][v[i]]++;
        part[1][v[i + 1]]++;
        part[2][v[i + 2]]++;
        part[3][v[i + 3]]++;
    }
    for (; i < n; i++)
        part[0][v[i]]++;
    for (int b = 0; b < 256; b++)
        h[b] = part[0][b] + part[1][b] + part[2][b] + part[3][b];
}

/* Bucket the n paths by shade kernel: slot s shades entries off[s] ..
 * off[s+1] of the index list *ids. When one kernel takes every path (modes
 * without levels: slot 0, and ml scenes whose paths all get one level, like the
 * default Cornell box) the list is the identity, on the device since
 * spm_clr_reserve(): no sort and no upload. Otherwise a stable counting sort
 * goes to r->idx (a non-blocking upload: h_idx is not rewritten before the batch's
 * blocking read-back). */
int spm_clr_bucket(spm_cl_renderer *r, size_t n, const uint8_t *levels, size_t off[NSLOTS + 1],
                   cl_mem *ids, spm_error *err)
{
    size_t cnt[NSLOTS] = {0};
    if (!r->mode->levelled) {
        cnt[0] = n;
    } else {
        size_t lc[SPM_LEVEL_MASK + 1] = {0};
        byte_histogram(levels, n, r->lhist);
        for (int b = 0; b < 256; b++)
            lc[b & SPM_LEVEL_MASK] += r->lhist[b];
        for (int l = 0; l <= (int)SPM_LEVEL_MASK; l++) {
            if (lc[l] && (l >= SPM_NUM_LEVELS || !r->k_shade[l])) {
                spm_errorf(err, "%zu paths need level %d, which this scene's program does not have",
                           lc[l], l);
                return 1;
            }
            if (l < SPM_NUM_LEVELS)
                cnt[l] = lc[l];
        }
    }
    int used = 0;
    off[0] = 0;
    for (int s = 0; s < NSLOTS; s++) {
        off[s + 1] = off[s] + cnt[s];
        used += cnt[s] > 0;
    }
    *ids = r->ident;
    if (used <= 1)
        return 0;
    size_t pos[SPM_NUM_LEVELS];
    memcpy(pos, off, sizeof pos);
    for (size_t i = 0; i < n; i++)
        r->h_idx[pos[levels[i] & SPM_LEVEL_MASK]++] = (spm_u32)i;
    *ids = r->idx;
    CK(clEnqueueWriteBuffer(r->cl.queue, r->idx, CL_FALSE, 0, n * sizeof(spm_u32), r->h_idx, 0,
                            NULL, NULL),
       "clEnqueueWriteBuffer(bucket indices)");
    return 0;
}

double spm_clr_release_events(cl_event *ev, int n, uint64_t *untimed)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        if (ev[i]) {
            double t = spm_cl_event_seconds(ev[i]);
            if (t >= 0)
                s += t;
            else if (untimed)
                (*untimed)++;
            clReleaseEvent(ev[i]);
            ev[i] = NULL;
        }
    return s;
}

/* One batch through trace -> bucket -> shade -> accumulate, its pixel sums
 * read into batch_xyz (b->npix * pix_ch floats). The read waits for the batch, so
 * its stage times can be taken from the events, and the bucket indices'
 * upload (bucket()) is done before the next batch rewrites them. */
static int pass_batch(spm_cl_renderer *r, const batch *b, float *batch_xyz, spm_pass_stats *st,
                      spm_error *err)
{
    cl_event ev_t = NULL, ev_s[NSLOTS] = {NULL}, ev_a = NULL;
    int rc = spm_clr_run_trace(r, b, &ev_t, err);
    if (!rc && r->mode->levelled)
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, b->n,
                                              r->h_levels, 1, &ev_t, NULL),
                          "clEnqueueReadBuffer(level bytes)", err);
    double t0 = spm_now();
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    rc = rc || spm_clr_bucket(r, b->n, r->h_levels, off, &ids, err);
    double bucket_s = spm_now() - t0;
    rc = rc || spm_clr_run_shade(r, b, off, ids, 0, ev_s, err) ||
         spm_clr_run_accumulate(r, b, &ev_a, err);
    rc = rc || spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->pass, CL_TRUE, 0,
                                                (size_t)b->npix * (size_t)r->pix_ch * sizeof(float), batch_xyz, 0,
                                                NULL, NULL),
                            "clEnqueueReadBuffer(batch image)", err);
    if (rc)
        clFinish(r->cl.queue);
    else /* bucket() checked the levels and counted them by value */
        spm_count_levels_hist(r->mode, r->lhist, b->n, st);
    st->trace_s += spm_clr_release_events(&ev_t, 1, &st->untimed);
    st->shade_s += spm_clr_release_events(ev_s, NSLOTS, &st->untimed) + bucket_s;
    st->accum_s += spm_clr_release_events(&ev_a, 1, &st->untimed);
    return rc;
}

/* The pass image is the concatenation of its batches' pixel sums: a pixel's
 * samples are summed in sample order within one batch, so the image is the
 * same however the pass is cut. */
typedef struct {
    float *pass_xyz;
    spm_pass_stats *st;
} pass_ctx;

static int pass_one(spm_cl_renderer *r, const batch *b, void *ctx, spm_error *err)
{
    pass_ctx *c = ctx;
    size_t end = (size_t)b->first_pixel + b->npix;
    if (pass_batch(r, b, &c->pass_xyz[(size_t)r->pix_ch * b->first_pixel], c->st, err))
        return 1;
    /* pass_batch has waited for the batch: nothing is left in the queue */
    if (end < r->npix && spm_pass_batch_end(r->ctl, end * b->spp))
        return SPM_PASS_STOPPED;
    return 0;
}

int spm_cl_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                spm_pass_stats *st, spm_error *err)
{
    return r->run_pass(r, first_sample, spp, pass_xyz, st, err);
}

int spm_clr_render_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                        spm_pass_stats *st, spm_error *err)
{
    if (spp == 0)
        return 0;
    pass_ctx c = {pass_xyz, st};
    int rc = r->bdpt    ? spm_clr_bdpt_pass(r, first_sample, spp, pass_xyz, st, err)
             : r->light ? spm_clr_light_pass(r, first_sample, spp, pass_xyz, st, err)
                        : spm_clr_each_batch(r, first_sample, spp, 1, pass_one, &c, err);
    if (rc == SPM_PASS_STOPPED)
        return rc;
    spm_u32 counters[SPM_NCOUNTERS];
    rc = rc || spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->counters, CL_TRUE, 0,
                                                sizeof counters, counters, 0, NULL, NULL),
                            "clEnqueueReadBuffer(counters)", err);
    if (rc) {
        clFinish(r->cl.queue);
        return 1;
    }
    st->truncated += counters[SPM_COUNTER_TRUNCATED];
    st->nonfinite += counters[SPM_COUNTER_NONFINITE];
    if (counters[SPM_COUNTER_STACK]) {
        spm_errorf(err, "BVH traversal stack overflow in %u rays (kernel stack %d)",
                   counters[SPM_COUNTER_STACK], SPM_BVH_STACK);
        return 1;
    }
    return 0;
}

/* ---- as a render backend (backend.h) ----------------------------------- */
static int backend_pass(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                        spm_pass_stats *st, spm_error *err)
{
    spm_cl_renderer *r = b->impl;
    r->ctl = &b->ctl;
    int rc = spm_cl_pass(r, first_sample, spp, pass_xyz, st, err);
    r->ctl = NULL;
    return rc;
}

static void backend_destroy(spm_backend *b)
{
    spm_cl_destroy(b->impl);
    free(b);
}

spm_backend *spm_backend_cl_create(int device, const spm_render_plan *plan, spm_error *err)
{
    spm_cl_renderer *r;
    if (spm_cl_create_plan(device, plan, &r, err))
        return NULL;
    spm_backend *b = spm_xcalloc(1, sizeof *b);
    b->impl = r;
    b->pass = backend_pass;
    b->destroy = backend_destroy;
    snprintf(b->name, sizeof b->name, "%d: %.200s", device, r->cl.dev.name);
    return b;
}

static int all_devices(int *list, int *n, int max, spm_error *err)
{
    spm_cl_device *devs;
    int ndev;
    if (spm_cl_devices(&devs, &ndev, err))
        return 1;
    int nall = 0;
    *n = 0;
    for (int i = 0; i < ndev; i++)
        if (spm_cl_device_in_all(devs, ndev, i)) {
            if (*n < max)
                list[(*n)++] = i;
            nall++;
        }
    free(devs);
    if (nall > max)
        spm_warnf("%d devices; the first %d render", nall, max);
    return 0;
}

static int check_device(int device, const spm_render_plan *plan, int width, int height,
                        size_t paths_per_pass, char *name, spm_error *err)
{
    spm_cl_footprint fp;
    if (plan->integrator == SPM_INTEGRATOR_BDPT)
        spm_cl_footprint_of_bdpt(plan->geom, plan->tables, (size_t)width * (size_t)height,
                                 plan->pix_ch, &fp);
    else
        spm_cl_footprint_of_ch(plan->geom, plan->tables, (size_t)width * (size_t)height,
                               paths_per_pass, plan->pix_ch, &fp);
    if (plan->integrator == SPM_INTEGRATOR_LIGHT)
        spm_cl_footprint_add_light(&fp, (size_t)width * (size_t)height, paths_per_pass,
                                   plan->pix_ch);
    spm_cl_device d;
    if (spm_cl_device_get(device, &d, err) || /* unknown index: lists the available ones */
        spm_cl_footprint_check(&d, &fp, width, height, paths_per_pass, err))
        return 1;
    snprintf(name, 256, "%s", d.name);
    return 0;
}

const spm_backend_kind spm_backend_kind_opencl = {.name = "opencl",
                                                  .per_device = 1,
                                                  .light = 1,
                                                  .bdpt = 1,
                                                  .compiles = 1,
                                                  .all_devices = all_devices,
                                                  .check = check_device,
                                                  .create = spm_backend_cl_create};
