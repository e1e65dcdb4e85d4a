/* The OpenCL render backend (render_cl.h): device buffers, kernel set per
 * mode, the pass pipeline trace -> bucket -> shade -> accumulate. */
#include "render_cl.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cl_resources.h"
#include "colour.h"
#include "refcpu.h"

/* Shade kernels: levels 0..3, then the modes with their own representation. */
enum { SLOT_TRUTH = SPM_NUM_LEVELS, SLOT_RGB, SLOT_HERO, NSLOTS };
static const char *slot_kernel[NSLOTS] = {"spm_shade_l0",    "spm_shade_l1",  "spm_shade_l2",
                                          "spm_shade_l3",    "spm_shade_truth", "spm_shade_rgb",
                                          "spm_shade_hero"};
/* Work-group size asked for (PoCL runs a group's work-items in one thread; 64
 * amortises the per-group cost and keeps the last group's waste small). */
#define LOCAL_SIZE 64
#define NCOUNTERS 4 /* truncated paths, BVH stack overflows, non-finite samples */

struct spm_cl_renderer {
    spm_cl_ctx cl;
    int mode;
    size_t npix;
    spm_trace_params params;
    spm_u32 init_level;
    cl_program prog;
    cl_kernel k_trace, k_accum;
    cl_kernel k_shade[NSLOTS]; /* NULL: not compiled */
    cl_mem tab[NSLOTS], cmf[NSLOTS], hero;
    cl_mem tris, nodes, emitters, mats, lvlk;
    /* per-batch buffers (room for cap paths), grown on demand */
    size_t cap;
    size_t batch_paths; /* a batch's paths, at most (SPM_CL_BATCH_PATHS; test hook) */
    cl_mem heads, verts; /* the batch's records, device layout (spm_shared.h) */
    cl_mem levels, idx, ident, xyz, pass, counters; /* pass: the batch's pixel sums */
    uint8_t *h_levels;
    spm_u32 *h_idx; /* bucket indices, the source of idx's non-blocking upload */
    size_t lhist[256]; /* ml, mlc: the pass's level bytes counted by value (bucket()) */
    spm_u32 zero[NCOUNTERS];
    long npasses;
    long fail_pass; /* SPECMIP_CL_FAIL: this pass fails (-1: never) */
    const spm_pass_ctl *ctl; /* the backend's, during its passes (NULL: none) */
};

#define CK(call, what)                     \
    do {                                   \
        if (spm_cl_check((call), what, err)) \
            return 1;                      \
    } while (0)

static int uses_levels(int mode)
{
    return mode == SPM_MODE_ML || mode == SPM_MODE_MLC;
}

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

static const uint8_t *lvlk_of(const spm_tables *t, int mode)
{
    return mode == SPM_MODE_MLC ? t->mlc_lvlk : t->lvlk;
}

/* Vectors per colour in level l's kernel: 5, plus in mlc the spike lanes
 * rounded up to whole vectors of the level's width. */
static int level_nv(const spm_tables *t, int mode, int l)
{
    int w = 16 >> l;
    return SPM_VECS_PER_LEVEL + (mode == SPM_MODE_MLC ? (t->nspikes + w - 1) / w : 0);
}

/* Which shade kernels the mode needs. ml/mlc: every level a path can get,
 * i.e. the start level and every per-occurrence level of a colour in use. */
static void need_colour(const uint8_t *lk, const spm_tables *t, spm_u32 c, spm_u32 init,
                        int need[NSLOTS])
{
    if (c == SPM_NONE || (int)c >= t->ncolours)
        return;
    for (int k = 0; k < SPM_PRETEST_KMAX; k++) {
        spm_u32 l = lk[c * SPM_PRETEST_KMAX + (spm_u32)k];
        if (l <= init)
            need[l] = 1;
    }
}

static void needed_slots(const spm_tables *t, int mode, spm_u32 init, int need[NSLOTS])
{
    memset(need, 0, NSLOTS * sizeof *need);
    if (mode == SPM_MODE_TRUTH)
        need[SLOT_TRUTH] = 1;
    else if (mode == SPM_MODE_RGB)
        need[SLOT_RGB] = 1;
    else if (mode == SPM_MODE_HERO)
        need[SLOT_HERO] = 1;
    else if (mode == SPM_MODE_REF)
        need[0] = 1;
    if (!uses_levels(mode))
        return;
    const uint8_t *lk = lvlk_of(t, mode);
    need[init] = 1;
    need_colour(lk, t, t->bg_up, init, need);
    need_colour(lk, t, t->bg_down, init, need);
    for (int m = 0; m < t->nmaterials; m++) {
        need_colour(lk, t, t->materials[m].refl, init, need);
        need_colour(lk, t, t->materials[m].emit, init, need);
    }
}

/* Row-major table of ncolours rows: each row's `src_n` floats copied to a row of
 * `dst_n` floats (rest zero). Also used for the XYZ weights (3 rows). */
static float *repack(const float *src, int rows, int src_stride, int src_n, int dst_n)
{
    float *o = spm_xcalloc((size_t)rows * (size_t)dst_n + 1, sizeof *o);
    for (int r = 0; r < rows; r++)
        memcpy(&o[(size_t)r * dst_n], &src[(size_t)r * src_stride], (size_t)src_n * sizeof *o);
    return o;
}

/* The shade tables of one slot: colour rows and XYZ weight rows in the
 * layout shade_body.clh reads (rows of nv vectors). */
static int upload_slot(spm_cl_renderer *r, const spm_tables *t, int slot, spm_error *err)
{
    int nc = t->ncolours, mode = r->mode;
    float *tab = NULL, *cmf = NULL;
    size_t tab_n = 0, cmf_n = 0;
    if (slot < SPM_NUM_LEVELS) {
        int l = slot, bins = SPM_LEVEL_BINS(l), nv = level_nv(t, mode, l), row = nv * (16 >> l);
        if (mode == SPM_MODE_MLC) {
            int ns = t->nspikes;
            tab = repack(t->mlc_lvl[l], nc, SPM_MLC_STRIDE(l), bins + ns, row);
            float w[3 * (SPM_L0_BINS + SPM_MAX_SPIKES)];
            for (int ch = 0; ch < 3; ch++) {
                memcpy(&w[ch * row], t->cmf_lvl[l][ch], (size_t)bins * sizeof *w);
                memset(&w[ch * row + bins], 0, (size_t)(row - bins) * sizeof *w);
                memcpy(&w[ch * row + bins], t->spike_cmf[ch], (size_t)ns * sizeof *w);
            }
            cmf = repack(w, 3, row, row, row);
        } else {
            tab = repack(t->lvl[l], nc, bins, bins, row);
            cmf = repack(&t->cmf_lvl[l][0][0], 3, SPM_L0_BINS, bins, row);
        }
        tab_n = (size_t)nc * row;
        cmf_n = 3 * (size_t)row;
    } else if (slot == SLOT_TRUTH) {
        tab = repack(t->truth, nc, SPM_TRUTH_BINS, SPM_TRUTH_BINS, SPM_TRUTH_BINS);
        cmf = repack(&t->cmf_truth[0][0], 3, SPM_TRUTH_BINS, SPM_TRUTH_BINS, SPM_TRUTH_BINS);
        tab_n = (size_t)nc * SPM_TRUTH_BINS;
        cmf_n = 3 * SPM_TRUTH_BINS;
    } else if (slot == SLOT_RGB) {
        /* XYZ from linear sRGB with the colour module's own matrix */
        tab = repack(t->rgb, nc, 4, 3, 4);
        cmf = spm_xcalloc(12, sizeof *cmf);
        for (int c = 0; c < 3; c++) {
            double rgb[3] = {c == 0, c == 1, c == 2}, xyz[3];
            spm_linear_srgb_to_xyz(rgb, xyz);
            for (int ch = 0; ch < 3; ch++)
                cmf[ch * 4 + c] = (float)xyz[ch];
        }
        tab_n = (size_t)nc * 4;
        cmf_n = 12;
    } else { /* hero: level-0 values, gathered per wavelength */
        tab = repack(t->lvl[0], nc, SPM_L0_BINS, SPM_L0_BINS, SPM_L0_BINS);
        tab_n = (size_t)nc * SPM_L0_BINS;
        cmf = spm_xcalloc(4, sizeof *cmf); /* unused: the weights are per wavelength */
        cmf_n = 4;
        /* kernels/shade.cl HERO_*: CDF, density per nm, CMF at 380..780 nm */
        size_t hn = (SPM_TRUTH_BINS + 1) + SPM_TRUTH_BINS + 3 * (SPM_TRUTH_BINS + 1);
        float *h = spm_xcalloc(hn, sizeof *h);
        memcpy(h, t->hero_cdf, sizeof t->hero_cdf);
        memcpy(h + SPM_TRUTH_BINS + 1, t->hero_pdf, sizeof t->hero_pdf);
        memcpy(h + 2 * SPM_TRUTH_BINS + 1, t->cmf_point, sizeof t->cmf_point);
        int rc = new_buffer(r, &r->hero, CL_MEM_READ_ONLY, hn * sizeof *h, h, "hero tables", err);
        free(h);
        if (rc) {
            free(tab);
            free(cmf);
            return 1;
        }
    }
    int rc = new_buffer(r, &r->tab[slot], CL_MEM_READ_ONLY, tab_n * sizeof *tab, tab,
                        "colour table", err) ||
             new_buffer(r, &r->cmf[slot], CL_MEM_READ_ONLY, cmf_n * sizeof *cmf, cmf,
                        "XYZ weights", err);
    free(tab);
    free(cmf);
    return rc;
}

static int build(spm_cl_renderer *r, const spm_tables *t, const int need[NSLOTS], spm_error *err)
{
    char defs[512];
    int n = snprintf(defs, sizeof defs, "-DSPM_BVH_STACK=%d", SPM_BVH_STACK);
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        if (need[l])
            n += snprintf(defs + n, sizeof defs - (size_t)n, " -DSPM_SHADE_L%d_NV=%d", l,
                          level_nv(t, r->mode, l));
    if (need[SLOT_TRUTH])
        n += snprintf(defs + n, sizeof defs - (size_t)n, " -DSPM_SHADE_TRUTH");
    if (need[SLOT_RGB])
        n += snprintf(defs + n, sizeof defs - (size_t)n, " -DSPM_SHADE_RGB");
    if (need[SLOT_HERO])
        n += snprintf(defs + n, sizeof defs - (size_t)n, " -DSPM_SHADE_HERO");
    /* The device's index makes each device's program text distinct: PoCL
     * otherwise shares one compiled kernel between same-kind devices, and two
     * devices launching it at once can break its reference counts (an
     * assertion in pocl_release_dlhandle_cache). */
    n += snprintf(defs + n, sizeof defs - (size_t)n, " -DSPM_DEVICE_INDEX=%d", r->cl.dev.index);
    const char *files[] = {"kernels/trace.cl", "kernels/shade.cl"};
    if (spm_cl_build(&r->cl, files, 2, defs, &r->prog, err))
        return 1;
    cl_int rc;
    r->k_trace = clCreateKernel(r->prog, "spm_trace", &rc);
    CK(rc, "clCreateKernel(spm_trace)");
    r->k_accum = clCreateKernel(r->prog, "spm_accumulate", &rc);
    CK(rc, "clCreateKernel(spm_accumulate)");
    for (int s = 0; s < NSLOTS; s++)
        if (need[s]) {
            char what[96];
            snprintf(what, sizeof what, "clCreateKernel(%s)", slot_kernel[s]);
            r->k_shade[s] = clCreateKernel(r->prog, slot_kernel[s], &rc);
            CK(rc, what);
        }
    return 0;
}

static int upload_scene(spm_cl_renderer *r, const spm_geometry *g, const spm_tables *t,
                        spm_error *err)
{
    size_t nlk = (size_t)t->ncolours * SPM_PRETEST_KMAX;
    return new_buffer(r, &r->tris, CL_MEM_READ_ONLY, (size_t)g->ntris * sizeof(spm_tri), g->tris,
                      "triangles", err) ||
           new_buffer(r, &r->nodes, CL_MEM_READ_ONLY, (size_t)g->nnodes * sizeof(spm_bvh_node),
                      g->nodes, "BVH", err) ||
           new_buffer(r, &r->emitters, CL_MEM_READ_ONLY, (size_t)g->nemitters * sizeof(spm_u32),
                      g->emitters, "emitters", err) ||
           new_buffer(r, &r->mats, CL_MEM_READ_ONLY, (size_t)t->nmaterials * sizeof(spm_material),
                      t->materials, "materials", err) ||
           new_buffer(r, &r->lvlk, CL_MEM_READ_ONLY, nlk, lvlk_of(t, r->mode), "level table", err);
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

static int warm_up(spm_cl_renderer *r, spm_error *err);

int spm_cl_create(int device, const spm_geometry *g, const spm_tables *t, int mode, spm_u32 seed,
                  spm_cl_renderer **out, spm_error *err)
{
    *out = NULL;
    if (mode < 0 || mode >= SPM_MODE_COUNT) {
        spm_errorf(err, "unknown render mode %d", mode);
        return 1;
    }
    if (g->nnodes < 1 || g->cam.width < 1 || g->cam.height < 1) {
        spm_errorf(err, "nothing to render (empty BVH or image size %dx%d)", g->cam.width,
                   g->cam.height);
        return 1;
    }
    if (mode == SPM_MODE_MLC && !t->mlc_lvlk) {
        spm_errorf(err, "mlc mode needs the Composite Model tables");
        return 1;
    }
    spm_cl_renderer *r = spm_xcalloc(1, sizeof *r);
    r->mode = mode;
    r->npix = (size_t)g->cam.width * (size_t)g->cam.height;
    r->batch_paths = SPM_CL_BATCH_PATHS;
    parse_fail_env(r, device);
    spm_trace_params *p = &r->params;
    p->cam = g->cam;
    p->ntris = (spm_u32)g->ntris;
    p->nemitters = (spm_u32)g->nemitters;
    p->bg_up = t->bg_up;
    p->bg_down = t->bg_down;
    p->seed = seed;
    r->init_level = (spm_u32)spm_ref_level_start(g, t->materials, lvlk_of(t, mode), p);
    if (r->init_level >= SPM_NUM_LEVELS)
        r->init_level = SPM_NUM_LEVELS - 1;
    int need[NSLOTS];
    needed_slots(t, mode, r->init_level, need);
    int rc = spm_cl_ctx_create(device, &r->cl, err) || upload_scene(r, g, t, err);
    for (int s = 0; s < NSLOTS && !rc; s++)
        if (need[s])
            rc = upload_slot(r, t, s, err);
    rc = rc || new_buffer(r, &r->counters, CL_MEM_READ_WRITE, sizeof r->zero, NULL, "counters",
                          err) ||
         build(r, t, need, err) || warm_up(r, err);
    if (rc) {
        spm_cl_destroy(r);
        return 1;
    }
    *out = r;
    return 0;
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
    cl_mem *ms[] = {&r->hero, &r->tris,  &r->nodes, &r->emitters, &r->mats, &r->lvlk,
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

static int set_args(cl_kernel k, const char *name, int nargs, const size_t *sizes,
                    const void *const *vals, spm_error *err)
{
    for (int i = 0; i < nargs; i++) {
        cl_int rc = clSetKernelArg(k, (cl_uint)i, sizes[i], vals[i]);
        if (rc != CL_SUCCESS) {
            char what[128];
            snprintf(what, sizeof what, "clSetKernelArg(%s, %d)", name, i);
            return spm_cl_check(rc, what, err);
        }
    }
    return 0;
}

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
static int plan(spm_cl_renderer *r, spm_u32 spp, size_t *bpix, spm_error *err)
{
    *bpix = spm_cl_batch_pixels(r->npix, spp, r->batch_paths);
    return reserve(r, spm_cl_batch_room(r->npix, spp, r->batch_paths), err);
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
    spm_u32 npaths = (spm_u32)b->n;
    const size_t m = sizeof(cl_mem), u = sizeof(spm_u32);
    const size_t sz[] = {m, m, m, m, m, sizeof r->params, u, u, m, m, m, m, u};
    const void *val[] = {&r->tris,  &r->nodes, &r->emitters, &r->mats,     &r->lvlk,
                         &r->params, &r->init_level, &npaths, &r->heads, &r->verts,
                         &r->levels, &r->counters, &b->first_pixel};
    if (set_args(r->k_trace, "spm_trace", 13, sz, val, err))
        return 1;
    return enqueue(r, r->k_trace, "spm_trace", 0, b->launch, ev, err);
}

/* Which shade kernel a mode without levels uses for every path. */
static int mode_slot(int mode)
{
    return mode == SPM_MODE_TRUTH ? SLOT_TRUTH
           : mode == SPM_MODE_RGB ? SLOT_RGB
           : mode == SPM_MODE_HERO ? SLOT_HERO
                                   : 0;
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
 * without levels, and ml scenes whose paths all get one level, like the
 * default Cornell box) the list is the identity, on the device since
 * reserve(): no sort and no upload. Otherwise a stable counting sort goes to
 * r->idx (a non-blocking upload: h_idx is not rewritten before the batch's
 * blocking read-back). */
static int bucket(spm_cl_renderer *r, size_t n, const uint8_t *levels, size_t off[NSLOTS + 1],
                  cl_mem *ids, spm_error *err)
{
    size_t cnt[NSLOTS] = {0};
    if (!uses_levels(r->mode)) {
        cnt[mode_slot(r->mode)] = n;
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

/* Enqueue the shade kernel of every non-empty bucket (every kernel the
 * program has, when `all`); events in ev[slot]. */
static int run_shade(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1], cl_mem ids,
                     int all, cl_event ev[NSLOTS], spm_error *err)
{
    for (int s = 0; s < NSLOTS; s++) {
        ev[s] = NULL;
        size_t cnt = off[s + 1] - off[s];
        if (!cnt && !(all && r->k_shade[s]))
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
        spm_u32 begin = (spm_u32)off[s], end = (spm_u32)off[s + 1];
        spm_u32 npaths = (spm_u32)b->n, seed = r->params.seed;
        /* shade_body.clh: (heads, verts, npaths, idx, begin, end, tab, cmf [, hero,
         * seed, spp, first_sample, first_pixel], xyz) */
        const size_t m = sizeof(cl_mem), u = sizeof(spm_u32);
        const size_t sz_hero[] = {m, m, u, m, u, u, m, m, m, u, u, u, u, m};
        const void *val_hero[] = {&r->heads, &r->verts,  &npaths,    &ids,
                                  &begin,    &end,       &r->tab[s], &r->cmf[s],
                                  &r->hero,  &seed,      &b->spp,    &b->first_sample,
                                  &b->first_pixel, &r->xyz};
        const size_t sz[] = {m, m, u, m, u, u, m, m, m};
        const void *val[] = {&r->heads, &r->verts, &npaths,    &ids,    &begin,
                             &end,      &r->tab[s], &r->cmf[s], &r->xyz};
        int rc = s == SLOT_HERO ? set_args(r->k_shade[s], slot_kernel[s], 14, sz_hero, val_hero, err)
                                : set_args(r->k_shade[s], slot_kernel[s], 9, sz, val, err);
        if (rc || enqueue(r, r->k_shade[s], slot_kernel[s], 0, b->launch, &ev[s], err))
            return 1;
    }
    return 0;
}

/* The events' kernel seconds; those without a time are counted in *untimed. */
static double release_events(cl_event *ev, int n, uint64_t *untimed)
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

/* Paths per level and set-by (as spm_count_levels: level 0, none, in modes
 * without levels), from bucket()'s histogram; it checked the levels. */
static void count_levels(const spm_cl_renderer *r, size_t n, spm_pass_stats *st)
{
    st->paths += n;
    if (!uses_levels(r->mode)) {
        st->level_paths[0][SPM_SETBY_NONE] += n;
        return;
    }
    for (int b = 0; b < 256; b++) {
        spm_u32 by = ((spm_u32)b >> SPM_SETBY_SHIFT) & 3u;
        st->level_paths[b & SPM_LEVEL_MASK][by > 2 ? 0 : by] += r->lhist[b];
    }
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
    if (!rc && uses_levels(r->mode))
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, b->n,
                                              r->h_levels, 1, &ev_t, NULL),
                          "clEnqueueReadBuffer(level bytes)", err);
    double t0 = spm_now();
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    rc = rc || bucket(r, b->n, r->h_levels, off, &ids, err);
    double bucket_s = spm_now() - t0;
    rc = rc || run_shade(r, b, off, ids, 0, ev_s, err);
    if (!rc) {
        const size_t m = sizeof(cl_mem), u = sizeof(spm_u32);
        const size_t sz[] = {m, u, u, m, m};
        const void *val[] = {&r->xyz, &b->npix, &b->spp, &r->pass, &r->counters};
        rc = set_args(r->k_accum, "spm_accumulate", 5, sz, val, err) ||
             enqueue(r, r->k_accum, "spm_accumulate", 0, b->launch / b->spp, &ev_a, err);
    }
    rc = rc || spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->pass, CL_TRUE, 0,
                                                (size_t)b->npix * 3 * sizeof(float), batch_xyz, 0,
                                                NULL, NULL),
                            "clEnqueueReadBuffer(batch image)", err);
    if (rc)
        clFinish(r->cl.queue);
    else
        count_levels(r, b->n, st);
    st->trace_s += release_events(&ev_t, 1, &st->untimed);
    st->shade_s += release_events(ev_s, NSLOTS, &st->untimed) + bucket_s;
    st->accum_s += release_events(&ev_a, 1, &st->untimed);
    return rc;
}

/* PoCL compiles a kernel for the shape of its launches (local size, zero
 * offset, a grid under 2^32 items) at the first launch, not in clBuildProgram:
 * on a cold cache that is most of the build, and it would land in the first
 * pass. So every kernel is launched once here, in the shape every pass uses,
 * with nothing to do (no path, no pixel: each work-item returns at once). */
static int warm_up(spm_cl_renderer *r, spm_error *err)
{
    batch b = {0, 1, 0, 0, 0, LOCAL_SIZE};
    cl_event ev[NSLOTS + 2] = {NULL};
    size_t off[NSLOTS + 1] = {0};
    spm_u32 none = 0, one = 1;
    const size_t m = sizeof(cl_mem), u = sizeof(spm_u32);
    const size_t sz[] = {m, u, u, m, m};
    const void *val[] = {&r->xyz, &none, &one, &r->pass, &r->counters};
    int rc = run_trace(r, &b, &ev[NSLOTS], err) || run_shade(r, &b, off, r->ident, 1, ev, err) ||
             set_args(r->k_accum, "spm_accumulate", 5, sz, val, err) ||
             enqueue(r, r->k_accum, "spm_accumulate", 0, LOCAL_SIZE, &ev[NSLOTS + 1], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(warm-up)", err);
    release_events(ev, NSLOTS + 2, NULL);
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
    if (plan(r, spp, &bpix, err) || zero_counters(r, err))
        return 1;
    int rc = 0;
    for (size_t p0 = 0; !rc && p0 < r->npix; p0 += bpix) {
        batch b = batch_at(r, first_sample, spp, p0, bpix);
        rc = pass_batch(r, &b, &pass_xyz[3 * p0], st, err);
        /* pass_batch has waited for the batch: nothing is left in the queue */
        if (!rc && p0 + b.npix < r->npix && spm_pass_batch_end(r->ctl, (p0 + b.npix) * spp))
            return SPM_PASS_STOPPED;
    }
    spm_u32 counters[NCOUNTERS];
    rc = rc || spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->counters, CL_TRUE, 0,
                                                sizeof counters, counters, 0, NULL, NULL),
                            "clEnqueueReadBuffer(counters)", err);
    if (rc) {
        clFinish(r->cl.queue);
        return 1;
    }
    st->truncated += counters[0];
    st->nonfinite += counters[2];
    if (counters[1]) {
        spm_errorf(err, "BVH traversal stack overflow in %u rays (kernel stack %d)", counters[1],
                   SPM_BVH_STACK);
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
    release_events(&ev, 1, NULL);
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
    if (plan(r, spp, &bpix, err) || zero_counters(r, err))
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
             bucket(r, n, levels, off, &ids, err) || run_shade(r, b, off, ids, 0, ev, err) ||
             spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->xyz, CL_TRUE, 0,
                                              n * 3 * sizeof(float), xyz, 0, NULL, NULL),
                          "clEnqueueReadBuffer(path XYZ)", err);
    clFinish(r->cl.queue);
    release_events(ev, NSLOTS, NULL);
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
    if (plan(r, spp, &bpix, err))
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

spm_backend *spm_backend_cl_create(int device, const spm_backend_input *in, spm_error *err)
{
    spm_cl_renderer *r;
    if (spm_cl_create(device, in->geom, in->tables, in->mode, in->seed, &r, err))
        return NULL;
    spm_backend *b = spm_xcalloc(1, sizeof *b);
    b->impl = r;
    b->pass = backend_pass;
    b->destroy = backend_destroy;
    snprintf(b->name, sizeof b->name, "%d: %.200s", device, r->cl.dev.name);
    return b;
}
