/* The OpenCL backend's device layout (cl_renderer.h): the scene's buffers
 * and the mode's shade tables, uploaded once, and the per-batch buffers. */
#include <stdlib.h>
#include <string.h>
#include "cl_renderer.h"

int spm_clr_new_buffer(spm_cl_renderer *r, cl_mem *m, cl_mem_flags fl, size_t bytes,
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
    if (!host)
        fl &= ~(cl_mem_flags)CL_MEM_USE_HOST_PTR;
    else if (!(fl & CL_MEM_USE_HOST_PTR))
        fl |= CL_MEM_COPY_HOST_PTR;
    *m = clCreateBuffer(r->cl.ctx, fl, bytes ? bytes : 16,
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
    size_t rows = (size_t)tab->ncolours * (size_t)tab->stride + tab->fluor_floats;
    size_t nw = tab->w ? 3 * (size_t)tab->stride : 4;
    return spm_clr_new_buffer(r, &r->tab[slot], CL_MEM_READ_ONLY, rows * sizeof(float),
                              tab->rows, "colour table", err) ||
           spm_clr_new_buffer(r, &r->cmf[slot], CL_MEM_READ_ONLY, nw * sizeof(float),
                              tab->w ? tab->w : no_weights, "XYZ weights", err) ||
           (tab->extra && !r->extra &&
            spm_clr_new_buffer(r, &r->extra, CL_MEM_READ_ONLY, tab->nextra * sizeof(float),
                               tab->extra, "per-path tables", err));
}

int spm_clr_upload(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err)
{
    const spm_geometry *g = plan->geom;
    const spm_tables *t = plan->tables;
    const uint8_t *lvlk = plan->lvlk;
    int rc = 0;
    /* A CPU device reads the host's triangles and BVH where they are rather
     * than a copy of them (the largest buffers: a million triangles are 100 MB);
     * the plan's geometry outlives its backends. */
    int cpu = spm_cl_device_kind(r->cl.dev.type) == SPM_CL_CPU;
#define SHARED(host) \
    (cpu && ((const void *)(host) == g->tris || (const void *)(host) == g->wide) \
         ? CL_MEM_USE_HOST_PTR : 0)
#define UPLOAD(field, what, bytes, host) \
    rc = rc || spm_clr_new_buffer(r, &r->field, CL_MEM_READ_ONLY | SHARED(host), bytes, host, \
                                  what, err);
    SPM_CL_SCENE_BUFFERS(UPLOAD)
    for (int s = 0; s < plan->nslots && !rc; s++)
        if (plan->used[s]) {
            rc = upload_slot(r, &plan->shade[s], s, err);
            const spm_spec_map *m = &plan->spec[s];
            if (!rc && plan->nspec)
                rc = spm_clr_new_buffer(r, &r->smap[s], CL_MEM_READ_ONLY,
                                        m->idx ? ((size_t)m->nbins + 1 + (size_t)m->nnz) *
                                                     sizeof(spm_u32) : 0,
                                        m->idx, "spectral bin map", err) ||
                     spm_clr_new_buffer(r, &r->sfac[s], CL_MEM_READ_ONLY,
                                        m->fac ? (size_t)m->nnz * sizeof(float) : 0, m->fac,
                                        "spectral bin factors", err);
        }
    return rc || spm_clr_new_buffer(r, &r->counters, CL_MEM_READ_WRITE, sizeof r->zero, NULL,
                                    "counters", err);
}

static void release(cl_mem *m)
{
    if (*m)
        clReleaseMemObject(*m);
    *m = NULL;
}

int spm_clr_reserve(spm_cl_renderer *r, size_t n, spm_error *err)
{
    if (n <= r->cap)
        return 0;
#define RELEASE(field, what, per_path, flags, init) release(&r->field);
    SPM_CL_BATCH_BUFFERS(RELEASE)
    r->cap = 0;
    r->h_idx = spm_xrealloc(r->h_idx, n * sizeof *r->h_idx);
    for (size_t i = 0; i < n; i++)
        r->h_idx[i] = (spm_u32)i;
#define INIT_NONE NULL
#define INIT_IDENTITY r->h_idx
    int rc = 0;
    size_t pix_ch = (size_t)r->pix_ch, vertex_bytes = r->vertex_bytes;
#define CREATE(field, what, per_path, flags, init) \
    rc = rc || spm_clr_new_buffer(r, &r->field, flags, n * (per_path), INIT_##init, what, err);
    SPM_CL_BATCH_BUFFERS(CREATE)
    if (rc)
        return 1;
    r->h_levels = spm_xrealloc(r->h_levels, n);
    r->cap = n;
    return 0;
}

void spm_clr_release_buffers(spm_cl_renderer *r)
{
    for (int s = 0; s < NSLOTS; s++) {
        release(&r->tab[s]);
        release(&r->cmf[s]);
        release(&r->smap[s]);
        release(&r->sfac[s]);
    }
    release(&r->extra);
    release(&r->counters);
#define RELEASE_SCENE(field, what, bytes, host) release(&r->field);
    SPM_CL_SCENE_BUFFERS(RELEASE_SCENE)
    SPM_CL_BATCH_BUFFERS(RELEASE)
}
