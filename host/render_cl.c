/* The OpenCL render backend (render_cl.h): device buffers, kernel set per
 * mode, the pass pipeline trace -> bucket -> shade -> accumulate. */
#include "render_cl.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cl_resources.h"
#include "spm_kernel_args.h"

/* Kernels and shade tables by slot: a levelled mode's levels, else slot 0
 * (modes.h). */
#define NSLOTS SPM_NUM_LEVELS
/* Work-group size asked for (PoCL runs a group's work-items in one thread; 64
 * amortises the per-group cost and keeps the last group's waste small). */
#define LOCAL_SIZE 64

/* Host mirrors of the kernels' parameter lists (spm_kernel_args.h). */
#define ARG_FIELD(dev, host, name) host name;
typedef struct { SPM_TRACE_ARGS(ARG_FIELD, ) } trace_args;
typedef struct { SPM_SHADE_ARGS(ARG_FIELD, ) } shade_args;
typedef struct { SPM_SHADE_PATH_ARGS(ARG_FIELD, ) } shade_path_args;
typedef struct { SPM_ACCUM_ARGS(ARG_FIELD, ) } accum_args;

struct spm_cl_renderer {
    spm_cl_ctx cl;
    const spm_mode_desc *mode;
    size_t npix;
    spm_trace_params params;
    spm_u32 init_level;
    cl_program prog;
    cl_kernel k_trace, k_accum;
    cl_kernel k_shade[NSLOTS]; /* NULL: not compiled */
    char kname[NSLOTS][64];
    cl_mem tab[NSLOTS], cmf[NSLOTS], extra;
    cl_mem tris, nodes, emitters, mats, lvlk;
    /* per-batch buffers (room for cap paths), grown on demand */
    size_t cap;
    size_t batch_paths; /* a batch's paths, at most (SPM_CL_BATCH_PATHS; test hook) */
    cl_mem heads, verts; /* the batch's records, device layout (spm_shared.h) */
    cl_mem levels, idx, ident, xyz, pass, counters; /* pass: the batch's pixel sums */
    uint8_t *h_levels;
    spm_u32 *h_idx; /* bucket indices, the source of idx's non-blocking upload */
    size_t lhist[256]; /* levelled modes: the pass's level bytes counted by value (bucket()) */
    spm_u32 zero[SPM_NCOUNTERS];
    long npasses;
    long fail_pass; /* SPECMIP_CL_FAIL: this pass fails (-1: never) */
};

#define CK(call, what)                     \
    do {                                   \
        if (spm_cl_check((call), what, err)) \
            return 1;                      \
    } while (0)

static int new_buffer(spm_cl_renderer *r, cl_mem *m, cl_mem_flags fl, size_t bytes,
                      const void *host, const char *what, spm_error *err)
{
    cl_int rc;
    if (bytes > r->cl.dev.max_alloc) {
        spm_errorf(err, "%s needs %.1f MB in one buffer; device '%s' allows %.1f MB", what,
                   (double)bytes / 1048576.0, r->cl.dev.name, (double)r->cl.dev.max_alloc / 1048576.0);
        return 1;
    }
    /* zero-sized buffers are invalid in OpenCL: an empty table gets a few bytes */
    if (!bytes)
        host = NULL;
    *m = clCreateBuffer(r->cl.ctx, fl | (host ? CL_MEM_COPY_HOST_PTR : 0), bytes ? bytes : 16,
                        (void *)host, &rc);
    char buf[160];
    snprintf(buf, sizeof buf, "clCreateBuffer(%s)", what);
    return spm_cl_check(rc, buf, err);
}

/* One slot's shade table (modes.h), in the layout shade_body.clh reads; a
 * mode with per-path weights gets a placeholder weight buffer (its kernel
 * never reads it) and its extra table. */
static int upload_slot(spm_cl_renderer *r, const spm_shade_table *tab, int slot, spm_error *err)
{
    static const float no_weights[4];
    size_t rows = (size_t)tab->ncolours * (size_t)tab->stride;
    size_t nw = tab->w ? 3 * (size_t)tab->stride : 4;
    return new_buffer(r, &r->tab[slot], CL_MEM_READ_ONLY, rows * sizeof(float), tab->rows,
                      "colour table", err) ||
           new_buffer(r, &r->cmf[slot], CL_MEM_READ_ONLY, nw * sizeof(float),
                      tab->w ? tab->w : no_weights, "XYZ weights", err) ||
           (tab->extra && !r->extra &&
            new_buffer(r, &r->extra, CL_MEM_READ_ONLY, tab->nextra * sizeof(float), tab->extra,
                       "hero tables", err));
}

static int build(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err)
{
    char defs[512];
    int n = 0;
    defs[0] = '\0';
    for (int s = 0; s < plan->nslots; s++)
        if (plan->used[s]) {
            char define[96];
            spm_mode_kernel(r->mode, plan->tables, s, r->kname[s], sizeof r->kname[s], define,
                            sizeof define);
            n += snprintf(defs + n, sizeof defs - (size_t)n, "-D%s ", define);
        }
    /* The device's index makes each device's program text distinct: PoCL
     * otherwise shares one compiled kernel between same-kind devices, and two
     * devices launching it at once can break its reference counts (an
     * assertion in pocl_release_dlhandle_cache). */
    n += snprintf(defs + n, sizeof defs - (size_t)n, "-DSPM_DEVICE_INDEX=%d", r->cl.dev.index);
    const char *files[] = {"kernels/trace.cl", "kernels/shade.cl"};
    if (spm_cl_build(&r->cl, files, 2, defs, &r->prog, err))
        return 1;
    cl_int rc;
    r->k_trace = clCreateKernel(r->prog, "spm_trace", &rc);
    CK(rc, "clCreateKernel(spm_trace)");
    r->k_accum = clCreateKernel(r->prog, "spm_accumulate", &rc);
    CK(rc, "clCreateKernel(spm_accumulate)");
    for (int s = 0; s < plan->nslots; s++)
        if (plan->used[s]) {
            char what[96];
            snprintf(what, sizeof what, "clCreateKernel(%s)", r->kname[s]);
            r->k_shade[s] = clCreateKernel(r->prog, r->kname[s], &rc);
            CK(rc, what);
        }
    return 0;
}

static int upload_scene(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err)
{
    const spm_geometry *g = plan->geom;
    const spm_tables *t = plan->tables;
    size_t nlk = (size_t)t->ncolours * SPM_PRETEST_KMAX;
    return new_buffer(r, &r->tris, CL_MEM_READ_ONLY, (size_t)g->ntris * sizeof(spm_tri), g->tris,
                      "triangles", err) ||
           new_buffer(r, &r->nodes, CL_MEM_READ_ONLY, (size_t)g->nnodes * sizeof(spm_bvh_node),
                      g->nodes, "BVH", err) ||
           new_buffer(r, &r->emitters, CL_MEM_READ_ONLY, (size_t)g->nemitters * sizeof(spm_u32),
                      g->emitters, "emitters", err) ||
           new_buffer(r, &r->mats, CL_MEM_READ_ONLY, (size_t)t->nmaterials * sizeof(spm_material),
                      t->materials, "materials", err) ||
           new_buffer(r, &r->lvlk, CL_MEM_READ_ONLY, nlk, plan->lvlk, "level table", err);
}

static void parse_fail_env(spm_cl_renderer *r, int device)
{
    r->fail_pass = -1;
    const char *s = getenv("SPECMIP_CL_FAIL");
    int dev;
    long pass;
    if (s && sscanf(s, "%d:%ld", &dev, &pass) == 2 && dev == device)
        r->fail_pass = pass;
}

int spm_cl_create_plan(int device, const spm_render_plan *plan, spm_cl_renderer **out,
                       spm_error *err)
{
    *out = NULL;
    spm_cl_renderer *r = spm_xcalloc(1, sizeof *r);
    r->mode = plan->mode;
    r->npix = plan->npix;
    r->batch_paths = SPM_CL_BATCH_PATHS;
    parse_fail_env(r, device);
    r->params = plan->params;
    r->init_level = plan->start_level;
    int rc = spm_cl_ctx_create(device, &r->cl, err) || upload_scene(r, plan, err);
    for (int s = 0; s < plan->nslots && !rc; s++)
        if (plan->used[s])
            rc = upload_slot(r, &plan->shade[s], s, err);
    rc = rc || new_buffer(r, &r->counters, CL_MEM_READ_WRITE, sizeof r->zero, NULL, "counters",
                          err) ||
         build(r, plan, err);
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

static void release(cl_mem *m)
{
    if (*m)
        clReleaseMemObject(*m);
    *m = NULL;
}

void spm_cl_destroy(spm_cl_renderer *r)
{
    if (!r)
        return;
    if (r->cl.queue)
        clFinish(r->cl.queue);
    for (int s = 0; s < NSLOTS; s++) {
        if (r->k_shade[s])
            clReleaseKernel(r->k_shade[s]);
        release(&r->tab[s]);
        release(&r->cmf[s]);
    }
    if (r->k_trace)
        clReleaseKernel(r->k_trace);
    if (r->k_accum)
        clReleaseKernel(r->k_accum);
    if (r->prog)
        clReleaseProgram(r->prog);
    cl_mem *ms[] = {&r->extra, &r->tris,  &r->nodes, &r->emitters, &r->mats, &r->lvlk,
                    &r->heads, &r->verts, &r->levels, &r->idx, &r->ident, &r->xyz, &r->pass,
                    &r->counters};
    for (size_t i = 0; i < sizeof ms / sizeof *ms; i++)
        release(ms[i]);
    spm_cl_ctx_release(&r->cl);
    free(r->h_levels);
    free(r->h_idx);
    free(r);
}

const spm_cl_device *spm_cl_renderer_device(const spm_cl_renderer *r)
{
    return &r->cl.dev;
}

/* Per-batch buffers for n paths (and up to n pixels); only grows. */
static int reserve(spm_cl_renderer *r, size_t n, spm_error *err)
{
    if (n <= r->cap)
        return 0;
    release(&r->heads);
    release(&r->verts);
    release(&r->levels);
    release(&r->idx);
    release(&r->ident);
    release(&r->xyz);
    release(&r->pass);
    r->cap = 0;
    r->h_idx = spm_xrealloc(r->h_idx, n * sizeof *r->h_idx);
    for (size_t i = 0; i < n; i++)
        r->h_idx[i] = (spm_u32)i;
    /* the vertex slabs have room for every depth; only those reached are touched */
    if (new_buffer(r, &r->heads, CL_MEM_READ_WRITE, n * sizeof(spm_dev_head), NULL,
                   "path record headers", err) ||
        new_buffer(r, &r->verts, CL_MEM_READ_WRITE, n * SPM_MAX_DEPTH * sizeof(spm_vertex), NULL,
                   "path records", err) ||
        new_buffer(r, &r->levels, CL_MEM_READ_WRITE, n, NULL, "level bytes", err) ||
        new_buffer(r, &r->ident, CL_MEM_READ_ONLY, n * sizeof(spm_u32), r->h_idx,
                   "identity indices", err) ||
        new_buffer(r, &r->idx, CL_MEM_READ_ONLY, n * sizeof(spm_u32), NULL, "bucket indices",
                   err) ||
        new_buffer(r, &r->xyz, CL_MEM_READ_WRITE, n * 3 * sizeof(float), NULL, "path XYZ", err) ||
        new_buffer(r, &r->pass, CL_MEM_WRITE_ONLY, n * 3 * sizeof(float), NULL, "batch image",
                   err))
        return 1;
    r->h_levels = spm_xrealloc(r->h_levels, n);
    r->cap = n;
    return 0;
}

static size_t round_up(size_t n)
{
    return (n + LOCAL_SIZE - 1) / LOCAL_SIZE * LOCAL_SIZE;
}

static int set_arg(cl_kernel k, const char *name, cl_uint i, size_t size, const void *val,
                   spm_error *err)
{
    cl_int rc = clSetKernelArg(k, i, size, val);
    if (rc == CL_SUCCESS)
        return 0;
    char what[128];
    snprintf(what, sizeof what, "clSetKernelArg(%s, %u)", name, i);
    return spm_cl_check(rc, what, err);
}

/* Sets kernel k's arguments from *a, a struct of one of the lists of
 * spm_kernel_args.h, from argument *i on; *i is left past them. */
#define SET_ARG(dev, host, name) rc = rc || set_arg(k, kname, (*i)++, sizeof a->name, &a->name, err);
#define DEFINE_SETTER(fn, type, LIST)                                                      \
    static int fn(cl_kernel k, const char *kname, const type *a, cl_uint *i, spm_error *err) \
    {                                                                                      \
        int rc = 0;                                                                        \
        LIST(SET_ARG, )                                                                    \
        return rc;                                                                         \
    }
DEFINE_SETTER(set_trace_args, trace_args, SPM_TRACE_ARGS)
DEFINE_SETTER(set_shade_args, shade_args, SPM_SHADE_ARGS)
DEFINE_SETTER(set_shade_path_args, shade_path_args, SPM_SHADE_PATH_ARGS)
DEFINE_SETTER(set_accum_args, accum_args, SPM_ACCUM_ARGS)

static int enqueue(spm_cl_renderer *r, cl_kernel k, const char *name, size_t offset, size_t n,
                   cl_event *ev, spm_error *err)
{
    size_t off = offset, global = round_up(n), local = LOCAL_SIZE;
    char what[128];
    snprintf(what, sizeof what, "clEnqueueNDRangeKernel(%s)", name);
    return spm_cl_check(clEnqueueNDRangeKernel(r->cl.queue, k, 1, &off, &global, &local, 0, NULL, ev),
                        what, err);
}

/* One batch of a pass: pixels first_pixel .. first_pixel + npix - 1, spp
 * samples each from first_sample, n = npix * spp paths whose records are
 * indexed from 0. Every trace and shade launch of a pass has `launch`
 * work-items, a full batch (see run_shade), and every accumulate launch
 * launch / spp. */
typedef struct {
    spm_u32 first_sample, spp, first_pixel, npix;
    size_t n, launch;
} batch;

/* A pass's batch size in pixels (cl_resources.h), with the buffers for it. */
static int plan_pass(spm_cl_renderer *r, spm_u32 spp, size_t *bpix, spm_error *err)
{
    *bpix = spm_batch_pixels(r->npix, spp, r->batch_paths);
    return reserve(r, spm_batch_room(r->npix, spp, r->batch_paths), err);
}

/* The batch of a pass cut into batches of bpix pixels that starts at pixel p0. */
static batch batch_at(const spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t p0,
                      size_t bpix)
{
    size_t np = r->npix - p0 < bpix ? r->npix - p0 : bpix;
    batch b = {first_sample, spp, (spm_u32)p0, (spm_u32)np, np * spp, bpix * spp};
    return b;
}

static int zero_counters(spm_cl_renderer *r, spm_error *err)
{
    CK(clEnqueueWriteBuffer(r->cl.queue, r->counters, CL_FALSE, 0, sizeof r->zero, r->zero, 0,
                            NULL, NULL),
       "clEnqueueWriteBuffer(counters)");
    return 0;
}

static int run_trace(spm_cl_renderer *r, const batch *b, cl_event *ev, spm_error *err)
{
    r->params.first_sample = b->first_sample;
    r->params.spp_per_pass = b->spp;
    trace_args a = {r->tris,  r->nodes, r->emitters,     r->mats, r->lvlk,
                    r->params, r->init_level, (spm_u32)b->n, r->heads, r->verts,
                    r->levels, r->counters, b->first_pixel};
    cl_uint i = 0;
    return set_trace_args(r->k_trace, "spm_trace", &a, &i, err) ||
           enqueue(r, r->k_trace, "spm_trace", 0, b->launch, ev, err);
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
 * reserve(): no sort and no upload. Otherwise a stable counting sort goes to
 * r->idx (a non-blocking upload: h_idx is not rewritten before the batch's
 * blocking read-back). */
static int bucket(spm_cl_renderer *r, size_t n, const uint8_t *levels, size_t off[NSLOTS + 1],
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

/* Enqueue the shade kernel of every non-empty bucket; events in ev[slot]. */
static int run_shade(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1], cl_mem ids,
                     cl_event ev[NSLOTS], spm_error *err)
{
    for (int s = 0; s < NSLOTS; s++) {
        ev[s] = NULL;
        size_t cnt = off[s + 1] - off[s];
        if (!cnt)
            continue;
        /* Every launch has offset 0 and a full batch's size, the bucket being
         * arguments (items past its end return at once): PoCL 3.1 compiles a
         * kernel once per offset class and per larger grid, but matches a
         * finished launch to those versions by local size only, so launches
         * of two versions in flight at once (two devices) corrupt their
         * reference counts (an assertion in pocl_release_dlhandle_cache).
         * build() now keeps devices from sharing kernels (SPM_DEVICE_INDEX);
         * this stays as the second guard because its cost, empty work-groups
         * when ml splits a pass, was below the noise on cornell_spiky (two
         * buckets a pass: shade time the same launched either way). The last
         * batch of a pass is launched at full size too, for the same reason. */
        shade_args a = {r->heads, r->verts,  (spm_u32)b->n, ids,     (spm_u32)off[s],
                        (spm_u32)off[s + 1], r->tab[s], r->cmf[s], r->xyz};
        shade_path_args pa = {r->extra, r->params.seed, b->spp, b->first_sample, b->first_pixel};
        cl_uint i = 0;
        int rc = set_shade_args(r->k_shade[s], r->kname[s], &a, &i, err) ||
                 (r->mode->per_path && set_shade_path_args(r->k_shade[s], r->kname[s], &pa, &i, err));
        if (rc || enqueue(r, r->k_shade[s], r->kname[s], 0, b->launch, &ev[s], err))
            return 1;
    }
    return 0;
}

static double release_events(cl_event *ev, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        if (ev[i]) {
            s += spm_cl_event_seconds(ev[i]);
            clReleaseEvent(ev[i]);
            ev[i] = NULL;
        }
    return s;
}

/* One batch through trace -> bucket -> shade -> accumulate, its pixel sums
 * read into batch_xyz (b->npix * 3 floats). The read waits for the batch, so
 * its stage times can be taken from the events, and the bucket indices'
 * upload (bucket()) is done before the next batch rewrites them. */
static int pass_batch(spm_cl_renderer *r, const batch *b, float *batch_xyz, spm_pass_stats *st,
                      spm_error *err)
{
    cl_event ev_t = NULL, ev_s[NSLOTS] = {NULL}, ev_a = NULL;
    int rc = run_trace(r, b, &ev_t, err);
    if (!rc && r->mode->levelled)
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, b->n,
                                              r->h_levels, 1, &ev_t, NULL),
                          "clEnqueueReadBuffer(level bytes)", err);
    double t0 = spm_now();
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    rc = rc || bucket(r, b->n, r->h_levels, off, &ids, err);
    double bucket_s = spm_now() - t0;
    rc = rc || run_shade(r, b, off, ids, ev_s, err);
    if (!rc) {
        accum_args a = {r->xyz, b->npix, b->spp, r->pass, r->counters};
        cl_uint i = 0;
        rc = set_accum_args(r->k_accum, "spm_accumulate", &a, &i, err) ||
             enqueue(r, r->k_accum, "spm_accumulate", 0, b->launch / b->spp, &ev_a, err);
    }
    rc = rc || spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->pass, CL_TRUE, 0,
                                                (size_t)b->npix * 3 * sizeof(float), batch_xyz, 0,
                                                NULL, NULL),
                            "clEnqueueReadBuffer(batch image)", err);
    if (rc)
        clFinish(r->cl.queue);
    else /* bucket() checked the levels and counted them by value */
        spm_count_levels_hist(r->mode, r->lhist, b->n, st);
    st->trace_s += release_events(&ev_t, 1);
    st->shade_s += release_events(ev_s, NSLOTS) + bucket_s;
    st->accum_s += release_events(&ev_a, 1);
    return rc;
}

/* The pass image is the concatenation of its batches' pixel sums: a pixel's
 * samples are summed in sample order within one batch, so the image is the
 * same however the pass is cut. */
int spm_cl_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                spm_pass_stats *st, spm_error *err)
{
    if (r->npasses++ == r->fail_pass) {
        spm_errorf(err, "clEnqueueNDRangeKernel(spm_trace): injected failure (SPECMIP_CL_FAIL)");
        return 1;
    }
    size_t bpix;
    if (spp == 0)
        return 0;
    if (plan_pass(r, spp, &bpix, err) || zero_counters(r, err))
        return 1;
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        batch b = batch_at(r, first_sample, spp, p0, bpix);
        rc = pass_batch(r, &b, &pass_xyz[3 * p0], st, err);
    }
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

void spm_cl_set_batch_paths(spm_cl_renderer *r, size_t paths)
{
    r->batch_paths = paths ? paths : SPM_CL_BATCH_PATHS;
}

size_t spm_cl_batch_capacity(const spm_cl_renderer *r)
{
    return r->cap;
}

/* The test hooks speak spm_path arrays; the device keeps the layout of
 * spm_shared.h ("path records on the device"). Vertices past a path's nvert
 * come back zero. */
static spm_u32 max_nvert(const spm_dev_head *h, size_t n)
{
    spm_u32 m = 0;
    for (size_t i = 0; i < n; i++) {
        spm_u32 nv = h[i].nvert_end & 0xFFFFu;
        m = nv > m ? nv : m;
    }
    return m < SPM_MAX_DEPTH ? m : SPM_MAX_DEPTH;
}

/* Trace one batch and read its records into paths[0 .. b->n) and levels;
 * h (room for b->n headers) is scratch. */
static int trace_batch(spm_cl_renderer *r, const batch *b, spm_dev_head *h, spm_path *paths,
                       uint8_t *levels, spm_error *err)
{
    size_t n = b->n;
    cl_event ev = NULL;
    spm_vertex *v = NULL;
    int rc = run_trace(r, b, &ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->heads, CL_FALSE, 0, n * sizeof *h,
                                              h, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path record headers)", err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, n, levels, 0,
                                              NULL, NULL),
                          "clEnqueueReadBuffer(level bytes)", err);
    size_t depth = rc ? 0 : max_nvert(h, n);
    if (depth) { /* only the slabs some path reached */
        v = spm_xcalloc(depth * n, sizeof *v);
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->verts, CL_TRUE, 0,
                                              depth * n * sizeof *v, v, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path records)", err);
    }
    clFinish(r->cl.queue);
    release_events(&ev, 1);
    for (size_t i = 0; !rc && i < n; i++) {
        memset(&paths[i], 0, sizeof paths[i]);
        paths[i].h = spm_dev_head_unpack(&h[i]);
        for (spm_u32 j = 0; j < paths[i].h.nvert && j < SPM_MAX_DEPTH; j++)
            paths[i].v[j] = v[(size_t)j * n + i];
    }
    free(v);
    return rc;
}

int spm_cl_trace(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, spm_path *paths,
                 uint8_t *levels, spm_error *err)
{
    size_t bpix;
    if (spp == 0)
        return 0;
    if (plan_pass(r, spp, &bpix, err) || zero_counters(r, err))
        return 1;
    spm_dev_head *h = spm_xcalloc(r->cap, sizeof *h);
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        batch b = batch_at(r, first_sample, spp, p0, bpix);
        rc = trace_batch(r, &b, h, &paths[p0 * spp], &levels[p0 * spp], err);
    }
    free(h);
    return rc;
}

/* Shade one batch's given records (b->n of them) into xyz. */
static int shade_batch(spm_cl_renderer *r, const batch *b, const spm_path *paths,
                       const uint8_t *levels, float *xyz, spm_error *err)
{
    size_t n = b->n;
    spm_dev_head *h = spm_xcalloc(n, sizeof *h);
    for (size_t i = 0; i < n; i++)
        h[i] = spm_dev_head_pack(&paths[i].h);
    size_t depth = max_nvert(h, n);
    spm_vertex *v = spm_xcalloc(depth * n + 1, sizeof *v);
    for (size_t i = 0; i < n; i++)
        for (spm_u32 j = 0; j < paths[i].h.nvert && j < SPM_MAX_DEPTH; j++)
            v[(size_t)j * n + i] = paths[i].v[j];
    cl_event ev[NSLOTS] = {NULL};
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    int rc = spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->heads, CL_FALSE, 0, n * sizeof *h,
                                               h, 0, NULL, NULL),
                          "clEnqueueWriteBuffer(path record headers)", err) ||
             (depth && spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->verts, CL_FALSE, 0,
                                                         depth * n * sizeof *v, v, 0, NULL, NULL),
                                    "clEnqueueWriteBuffer(path records)", err)) ||
             bucket(r, n, levels, off, &ids, err) || run_shade(r, b, off, ids, ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->xyz, CL_TRUE, 0,
                                              n * 3 * sizeof(float), xyz, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path XYZ)", err);
    clFinish(r->cl.queue);
    release_events(ev, NSLOTS);
    free(h);
    free(v);
    return rc;
}

int spm_cl_shade(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, const spm_path *paths,
                 const uint8_t *levels, float *xyz, spm_error *err)
{
    size_t bpix;
    if (spp == 0)
        return 0;
    if (plan_pass(r, spp, &bpix, err))
        return 1;
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        batch b = batch_at(r, first_sample, spp, p0, bpix);
        size_t i0 = p0 * spp;
        rc = shade_batch(r, &b, &paths[i0], &levels[i0], &xyz[3 * i0], err);
    }
    return rc;
}

/* ---- as a render backend (backend.h) ----------------------------------- */
static int backend_pass(spm_backend *b, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                        spm_pass_stats *st, spm_error *err)
{
    return spm_cl_pass(b->impl, first_sample, spp, pass_xyz, st, err);
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
