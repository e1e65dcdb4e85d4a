/* The OpenCL backend's test hooks (backend_cl.h): a pass traced only or
 * shaded only, with the records and level bytes read back or given; and
 * failure injection for the multi-device tests. */
#include <stdlib.h>
#include <string.h>
#include "cl_renderer.h"

/* The handle's pass with SPECMIP_CL_FAIL naming its device: pass fail_pass
 * fails as an enqueue would, the others render. */
static int failing_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                        spm_pass_stats *st, spm_error *err)
{
    if (r->npasses++ == r->fail_pass) {
        spm_errorf(err, "clEnqueueNDRangeKernel(spm_trace): injected failure (SPECMIP_CL_FAIL)");
        return 1;
    }
    return spm_clr_render_pass(r, first_sample, spp, pass_xyz, st, err);
}

void spm_clr_fail_init(spm_cl_renderer *r, int device)
{
    r->fail_pass = -1;
    const char *s = getenv("SPECMIP_CL_FAIL");
    int dev;
    long pass;
    if (s && sscanf(s, "%d:%ld", &dev, &pass) == 2 && dev == device) {
        r->fail_pass = pass;
        r->run_pass = failing_pass;
    }
}

void spm_cl_set_batch_paths(spm_cl_renderer *r, size_t paths)
{
    r->batch_paths = paths ? paths : spm_plan_batch_paths(SPM_CL_BATCH_PATHS, r->pix_ch, r->vertex_bytes);
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

/* The n records of the batch buffers (headers, the slabs some path reached,
 * the types' vertex words) into paths[0 .. n); h (room for n headers) is
 * scratch. */
static int read_records(spm_cl_renderer *r, size_t n, spm_dev_head *h, spm_path *paths,
                        spm_error *err)
{
    spm_vertex *v = NULL;
    int rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->heads, CL_TRUE, 0, n * sizeof *h, h,
                                              0, NULL, NULL),
                          "clEnqueueReadBuffer(path record headers)", err);
    size_t depth = rc ? 0 : max_nvert(h, n);
    if (depth) { /* only the slabs some path reached */
        v = spm_xcalloc(depth * n, sizeof *v);
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->verts, CL_TRUE, 0,
                                              depth * n * sizeof *v, v, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path records)", err);
    }
    spm_vertex_ext *x = NULL; /* the types' vertex words, when the scene has some */
    if (!rc && depth && r->vertex_bytes > sizeof(spm_vertex)) {
        x = spm_xcalloc(depth * n, sizeof *x);
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->verts, CL_TRUE,
                                              SPM_MAX_DEPTH * n * sizeof *v, depth * n * sizeof *x,
                                              x, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path records' vertex words)", err);
    }
    for (size_t i = 0; !rc && i < n; i++) {
        memset(&paths[i], 0, sizeof paths[i]);
        paths[i].h = spm_dev_head_unpack(&h[i]);
        for (spm_u32 j = 0; j < paths[i].h.nvert && j < SPM_MAX_DEPTH; j++) {
            paths[i].v[j] = v[(size_t)j * n + i];
            if (x)
                paths[i].x[j] = x[(size_t)j * n + i];
        }
    }
    free(v);
    free(x);
    return rc;
}

/* Trace one batch and read its records into paths[0 .. b->n) and levels;
 * h (room for b->n headers) is scratch. */
static int trace_batch(spm_cl_renderer *r, const batch *b, spm_dev_head *h, spm_path *paths,
                       uint8_t *levels, spm_error *err)
{
    cl_event ev = NULL;
    int rc = spm_clr_run_trace(r, b, &ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, b->n, levels, 0,
                                              NULL, NULL),
                          "clEnqueueReadBuffer(level bytes)", err) ||
             read_records(r, b->n, h, paths, err);
    clFinish(r->cl.queue);
    spm_clr_release_events(&ev, 1, NULL);
    return rc;
}

typedef struct {
    spm_dev_head *h; /* scratch: a batch's headers */
    spm_path *paths;
    uint8_t *levels;
} trace_ctx;

static int trace_one(spm_cl_renderer *r, const batch *b, void *ctx, spm_error *err)
{
    trace_ctx *c = ctx;
    size_t i0 = (size_t)b->first_pixel * b->spp;
    if (!c->h)
        c->h = spm_xcalloc(r->cap, sizeof *c->h);
    return trace_batch(r, b, c->h, &c->paths[i0], &c->levels[i0], err);
}

int spm_cl_trace(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, spm_path *paths,
                 uint8_t *levels, spm_error *err)
{
    trace_ctx c = {NULL, paths, levels}; /* h: sized at the first batch, as the buffers */
    int rc = spm_clr_each_batch(r, first_sample, spp, 1, trace_one, &c, err);
    free(c.h);
    return rc;
}

/* The n given records into the batch buffers (headers, the slabs some path
 * reached, the types' vertex words; enqueued, not waited for: the staging
 * copies are freed after a finish). */
typedef struct {
    spm_dev_head *h;
    spm_vertex *v;
    spm_vertex_ext *x;
} staged;

static int write_records(spm_cl_renderer *r, size_t n, const spm_path *paths, staged *st,
                         spm_error *err)
{
    spm_dev_head *h = st->h = spm_xcalloc(n, sizeof *h);
    for (size_t i = 0; i < n; i++)
        h[i] = spm_dev_head_pack(&paths[i].h);
    size_t depth = max_nvert(h, n);
    spm_vertex *v = st->v = spm_xcalloc(depth * n + 1, sizeof *v);
    int ext = r->vertex_bytes > sizeof(spm_vertex);
    spm_vertex_ext *x = st->x = spm_xcalloc(ext ? depth * n + 1 : 1, sizeof *x);
    for (size_t i = 0; i < n; i++)
        for (spm_u32 j = 0; j < paths[i].h.nvert && j < SPM_MAX_DEPTH; j++) {
            v[(size_t)j * n + i] = paths[i].v[j];
            if (ext)
                x[(size_t)j * n + i] = paths[i].x[j];
        }
    return spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->heads, CL_FALSE, 0, n * sizeof *h,
                                             h, 0, NULL, NULL),
                        "clEnqueueWriteBuffer(path record headers)", err) ||
           (depth && spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->verts, CL_FALSE, 0,
                                                       depth * n * sizeof *v, v, 0, NULL, NULL),
                                  "clEnqueueWriteBuffer(path records)", err)) ||
           (depth && ext &&
            spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->verts, CL_FALSE,
                                              SPM_MAX_DEPTH * n * sizeof *v, depth * n * sizeof *x,
                                              x, 0, NULL, NULL),
                         "clEnqueueWriteBuffer(path records' vertex words)", err));
}

static void staged_free(staged *st)
{
    free(st->h);
    free(st->v);
    free(st->x);
}

/* Shade one batch's given records (b->n of them) into xyz. */
static int shade_batch(spm_cl_renderer *r, const batch *b, const spm_path *paths,
                       const uint8_t *levels, float *xyz, spm_error *err)
{
    size_t n = b->n;
    staged sg = {NULL, NULL, NULL};
    cl_event ev[NSLOTS] = {NULL};
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    int rc = write_records(r, n, paths, &sg, err) ||
             spm_clr_bucket(r, n, levels, off, &ids, err) || spm_clr_run_shade(r, b, off, ids, 0, ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->xyz, CL_TRUE, 0,
                                              n * (size_t)r->pix_ch * sizeof(float), xyz, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path XYZ)", err);
    clFinish(r->cl.queue);
    spm_clr_release_events(ev, NSLOTS, NULL);
    staged_free(&sg);
    return rc;
}

typedef struct {
    const spm_path *paths;
    const uint8_t *levels;
    float *xyz;
} shade_ctx;

static int shade_one(spm_cl_renderer *r, const batch *b, void *ctx, spm_error *err)
{
    shade_ctx *c = ctx;
    size_t i0 = (size_t)b->first_pixel * b->spp;
    return shade_batch(r, b, &c->paths[i0], &c->levels[i0], &c->xyz[(size_t)r->pix_ch * i0], err);
}

int spm_cl_shade(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, const spm_path *paths,
                 const uint8_t *levels, float *xyz, spm_error *err)
{
    shade_ctx c = {paths, levels, xyz};
    return spm_clr_each_batch(r, first_sample, spp, 0, shade_one, &c, err);
}

/* ---- the light integrator's: subpaths with their pixel words and splats --- */

#define SLABS (SPM_MAX_DEPTH + 1) /* pixel words a subpath: its light's, then a vertex's */

/* A chunk of subpaths [first, first + n) of a pass: its batch, the buffers
 * reserved. */
static int light_hook_batch(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                            size_t n, batch *b, spm_error *err)
{
    if (!r->light || r->bdpt || n == 0 || n > SPM_SPLAT_CHUNK || first + n > r->npix * spp) {
        spm_errorf(err, "light subpath hook: subpaths %zu..%zu of a pass of %zu (a chunk of at "
                   "most %zu, a light integrator's handle)", first, first + n, r->npix * spp,
                   SPM_SPLAT_CHUNK);
        return 1;
    }
    size_t all = r->npix * spp;
    *b = spm_clr_light_batch(r, first_sample, spp, first, n);
    return spm_clr_reserve_light(r, all < SPM_SPLAT_CHUNK ? all : SPM_SPLAT_CHUNK, err);
}

int spm_cl_light_trace(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                       size_t n, spm_path *paths, spm_u32 *px, uint8_t *levels, spm_error *err)
{
    batch b;
    if (light_hook_batch(r, first_sample, spp, first, n, &b, err))
        return 1;
    cl_event ev = NULL;
    spm_dev_head *h = spm_xcalloc(n, sizeof *h);
    spm_u32 *w = spm_xcalloc(SLABS * n, sizeof *w);
    int rc = spm_clr_zero_counters(r, err) || spm_clr_run_light_trace(r, &b, first, &ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, n, levels, 0,
                                              NULL, NULL),
                          "clEnqueueReadBuffer(level bytes)", err) ||
             read_records(r, n, h, paths, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->lpx, CL_TRUE, 0,
                                              SLABS * n * sizeof *w, w, 0, NULL, NULL),
                          "clEnqueueReadBuffer(splat pixel words)", err);
    clFinish(r->cl.queue);
    spm_clr_release_events(&ev, 1, NULL);
    for (size_t i = 0; !rc && i < n; i++) /* the slabs past the record were not written */
        for (spm_u32 s = 0; s < SLABS; s++)
            px[i * SLABS + s] = s <= paths[i].h.nvert ? w[(size_t)s * n + i] : SPM_NO_PIXEL;
    free(h);
    free(w);
    return rc;
}

/* The chunk's splat list (count of them) appended to out. */
static int read_splats(spm_cl_renderer *r, size_t count, spm_splats *out, spm_error *err)
{
    size_t ch = (size_t)r->pix_ch;
    spm_u32 *spx = spm_xcalloc(count + 1, sizeof *spx);
    float *sval = spm_xcalloc(ch * count + 1, sizeof *sval);
    int rc = count &&
             (spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->spx, CL_TRUE, 0,
                                               count * sizeof *spx, spx, 0, NULL, NULL),
                           "clEnqueueReadBuffer(splat pixels)", err) ||
              spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->sval, CL_TRUE, 0,
                                               ch * count * sizeof *sval, sval, 0, NULL, NULL),
                           "clEnqueueReadBuffer(splat values)", err));
    for (size_t k = 0; !rc && k < count; k++)
        memcpy(spm_splats_push(out, spx[k]), &sval[ch * k], ch * sizeof *sval);
    free(spx);
    free(sval);
    return rc;
}

int spm_cl_light_shade(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                       size_t n, const spm_path *paths, const spm_u32 *px, const uint8_t *levels,
                       spm_splats *out, spm_error *err)
{
    batch b;
    if (light_hook_batch(r, first_sample, spp, first, n, &b, err))
        return 1;
    if (out->ch != r->pix_ch) {
        spm_errorf(err, "light subpath hook: a splat list of %d floats for records of %d",
                   out->ch, r->pix_ch);
        return 1;
    }
    spm_u32 *w = spm_xcalloc(SLABS * n, sizeof *w);
    for (size_t i = 0; i < n; i++)
        for (spm_u32 s = 0; s < SLABS; s++)
            w[(size_t)s * n + i] = px[i * SLABS + s];
    staged sg = {NULL, NULL, NULL};
    cl_event ev[NSLOTS] = {NULL};
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    cl_int stat[2] = {0, 0};
    int rc = write_records(r, n, paths, &sg, err) ||
             spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->lpx, CL_TRUE, 0,
                                               SLABS * n * sizeof *w, w, 0, NULL, NULL),
                          "clEnqueueWriteBuffer(splat pixel words)", err) ||
             spm_clr_bucket(r, n, levels, off, &ids, err) ||
             spm_clr_light_splats(r, &b, off, ids, ev, stat, NULL, err) ||
             read_splats(r, (size_t)(spm_u32)stat[0], out, err);
    clFinish(r->cl.queue);
    spm_clr_release_events(ev, NSLOTS, NULL);
    staged_free(&sg);
    free(w);
    return rc;
}
