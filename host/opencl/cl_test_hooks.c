/* The OpenCL backend's test hooks (render_cl.h): a pass traced only or
 * shaded only, with the records and level bytes read back or given; and
 * failure injection for the multi-device tests. */
#include <stdlib.h>
#include <string.h>
#include "cl_renderer.h"

void spm_clr_fail_init(spm_cl_renderer *r, int device)
{
    r->fail_pass = -1;
    const char *s = getenv("SPECMIP_CL_FAIL");
    int dev;
    long pass;
    if (s && sscanf(s, "%d:%ld", &dev, &pass) == 2 && dev == device)
        r->fail_pass = pass;
}

int spm_clr_fail_now(spm_cl_renderer *r, spm_error *err)
{
    if (r->npasses++ != r->fail_pass)
        return 0;
    spm_errorf(err, "clEnqueueNDRangeKernel(spm_trace): injected failure (SPECMIP_CL_FAIL)");
    return 1;
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
    clFinish(r->cl.queue);
    spm_clr_release_events(&ev, 1, NULL);
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
    if (spm_clr_plan_pass(r, spp, &bpix, err) || spm_clr_zero_counters(r, err))
        return 1;
    spm_dev_head *h = spm_xcalloc(r->cap, sizeof *h);
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        batch b = spm_clr_batch_at(r, first_sample, spp, p0, bpix);
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
             spm_clr_bucket(r, n, levels, off, &ids, err) || spm_clr_run_shade(r, b, off, ids, 0, ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->xyz, CL_TRUE, 0,
                                              n * 3 * sizeof(float), xyz, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path XYZ)", err);
    clFinish(r->cl.queue);
    spm_clr_release_events(ev, NSLOTS, NULL);
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
    if (spm_clr_plan_pass(r, spp, &bpix, err))
        return 1;
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        batch b = spm_clr_batch_at(r, first_sample, spp, p0, bpix);
        size_t i0 = p0 * spp;
        rc = shade_batch(r, &b, &paths[i0], &levels[i0], &xyz[3 * i0], err);
    }
    return rc;
}

