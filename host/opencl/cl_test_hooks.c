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

/* Trace one batch and read its records into paths[0 .. b->n) and levels;
 * h (room for b->n headers) is scratch. */
static int trace_batch(spm_cl_renderer *r, const batch *b, spm_dev_head *h, spm_path *paths,
                       uint8_t *levels, spm_error *err)
{
    size_t n = b->n;
    cl_event ev = NULL;
    spm_vertex *v = NULL;
    int rc = spm_clr_run_trace(r, b, &ev, err) ||
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
    spm_vertex_ext *x = NULL; /* the types' vertex words, when the scene has some */
    if (!rc && depth && r->vertex_bytes > sizeof(spm_vertex)) {
        x = spm_xcalloc(depth * n, sizeof *x);
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->verts, CL_TRUE,
                                              SPM_MAX_DEPTH * n * sizeof *v, depth * n * sizeof *x,
                                              x, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path records' vertex words)", err);
    }
    clFinish(r->cl.queue);
    spm_clr_release_events(&ev, 1, NULL);
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
    int ext = r->vertex_bytes > sizeof(spm_vertex);
    spm_vertex_ext *x = spm_xcalloc(ext ? depth * n + 1 : 1, sizeof *x);
    for (size_t i = 0; i < n; i++)
        for (spm_u32 j = 0; j < paths[i].h.nvert && j < SPM_MAX_DEPTH; j++) {
            v[(size_t)j * n + i] = paths[i].v[j];
            if (ext)
                x[(size_t)j * n + i] = paths[i].x[j];
        }
    cl_event ev[NSLOTS] = {NULL};
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    int rc = spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->heads, CL_FALSE, 0, n * sizeof *h,
                                               h, 0, NULL, NULL),
                          "clEnqueueWriteBuffer(path record headers)", err) ||
             (depth && spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->verts, CL_FALSE, 0,
                                                         depth * n * sizeof *v, v, 0, NULL, NULL),
                                    "clEnqueueWriteBuffer(path records)", err)) ||
             (depth && ext &&
              spm_cl_check(clEnqueueWriteBuffer(r->cl.queue, r->verts, CL_FALSE,
                                                SPM_MAX_DEPTH * n * sizeof *v, depth * n * sizeof *x,
                                                x, 0, NULL, NULL),
                           "clEnqueueWriteBuffer(path records' vertex words)", err)) ||
             spm_clr_bucket(r, n, levels, off, &ids, err) || spm_clr_run_shade(r, b, off, ids, 0, ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->xyz, CL_TRUE, 0,
                                              n * (size_t)r->pix_ch * sizeof(float), xyz, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path XYZ)", err);
    clFinish(r->cl.queue);
    spm_clr_release_events(ev, NSLOTS, NULL);
    free(h);
    free(v);
    free(x);
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
