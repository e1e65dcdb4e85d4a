/* The OpenCL backend's bidirectional integrator (cl_renderer.h;
 * docs/ARCHITECTURE.md "Connected paths"): a pass's samples in chunks of
 * SPM_BDPT_CHUNK by their index in the pass. Per chunk: trace
 * (spm_bdpt_trace: both subpaths of each sample, every strategy's connected
 * path a record in the next free slot, its pixel in spx; more records than
 * room: room for them all and the chunk traced again, the same paths),
 * bucket the records by level, shade them with the mode's own kernels
 * (a connected path's record is a camera path's), then their largest
 * exponent (spm_bdpt_exponent), the fixed-point sums of the records' values
 * in their pixels (kernels/lighttrace.cl spm_splat_add: the order of the
 * adds does not matter, so the record slots' order does not either) and
 * their conversion into the device's pass image. */
#include <string.h>
#include "cl_renderer.h"
#include "film_splat.h"

const char *const spm_cl_bdpt_program_files[SPM_CL_BDPT_PROGRAM_NFILES] = {
    "kernels/trace.cl", "kernels/shade.cl", "kernels/lighttrace.cl", "kernels/bdpt.cl"};

int spm_clr_bdpt_build(spm_cl_renderer *r, const spm_render_plan *plan, const char *defs,
                       spm_error *err)
{
    const spm_clr_named_kernel ks[] = {{&r->k_btrace, "spm_bdpt_trace"},
                                       {&r->k_bexp, "spm_bdpt_exponent"},
                                       {&r->k_sadd, "spm_splat_add"},
                                       {&r->k_sconv, "spm_splat_convert"}};
    r->bdpt = 1;
    return spm_clr_splat_build(r, plan, "bdpt", spm_cl_bdpt_program_files,
                               SPM_CL_BDPT_PROGRAM_NFILES, defs, ks, 4, "", err);
}

void spm_clr_bdpt_release(spm_cl_renderer *r)
{
    cl_kernel *ks[] = {&r->k_btrace, &r->k_bexp};
    for (int i = 0; i < 2; i++)
        if (*ks[i]) {
            clReleaseKernel(*ks[i]);
            *ks[i] = NULL;
        }
    spm_cl_release_mem(r->bsam);
    r->bsam = NULL;
    r->bcap = 0;
}

/* Room for n records: the batch buffers, their pixels and their samples. */
static int reserve_records(spm_cl_renderer *r, size_t n, spm_error *err)
{
    if (spm_clr_reserve(r, n, err) || spm_clr_reserve_splats(r, n, err))
        return 1;
    if (n <= r->bcap)
        return 0;
    spm_cl_release_mem(r->bsam);
    r->bsam = NULL;
    r->bcap = 0;
    if (spm_clr_new_buffer(r, &r->bsam, CL_MEM_READ_WRITE, n * sizeof(spm_u32), NULL,
                           "record samples", err))
        return 1;
    r->bcap = n;
    return 0;
}

/* lstat to (count, exponent) = (0, none) */
static int reset_stat(spm_cl_renderer *r, spm_error *err)
{
    static const cl_int none[2] = {0, -1074};
    CK(clEnqueueWriteBuffer(r->cl.queue, r->lstat, CL_TRUE, 0, sizeof none, none, 0, NULL, NULL),
       "clEnqueueWriteBuffer(record count)");
    return 0;
}

static int read_stat(spm_cl_renderer *r, cl_int stat[2], spm_error *err)
{
    CK(clEnqueueReadBuffer(r->cl.queue, r->lstat, CL_TRUE, 0, 2 * sizeof(cl_int), stat, 0, NULL,
                           NULL),
       "clEnqueueReadBuffer(record count)");
    return 0;
}

/* The chunk's records traced until they fit: *nrec of them. */
static int trace_records(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                         size_t nb, size_t *nrec, spm_pass_stats *st, spm_error *err)
{
    for (;;) {
        cl_event ev = NULL;
        cl_int stat[2];
        batch b = {first_sample, spp, 0, 0, r->cap, SPM_BDPT_CHUNK};
        int rc = reset_stat(r, err) || spm_clr_run_bdpt_trace(r, &b, first, nb, &ev, err) ||
                 read_stat(r, stat, err);
        st->trace_s += spm_clr_release_events(&ev, 1, &st->untimed);
        if (rc)
            return 1;
        *nrec = (size_t)(spm_u32)stat[0];
        if (*nrec <= r->cap)
            return 0;
        if (reserve_records(r, *nrec + *nrec / 4, err))
            return 1;
    }
}

/* One chunk: samples [first, first + nb) of the pass. */
static int bdpt_chunk(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                      size_t nb, spm_pass_stats *st, spm_error *err)
{
    cl_event ev_s[NSLOTS] = {NULL}, ev_a[3] = {NULL};
    size_t off[NSLOTS + 1], n;
    cl_mem ids = NULL;
    cl_int stat[2] = {0, 0};
    if (trace_records(r, first_sample, spp, first, nb, &n, st, err))
        return 1;
    if (!n)
        return 0;
    batch b = {first_sample, spp, 0, 0, r->cap, r->cap};
    int rc = 0;
    if (r->mode->levelled)
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, n, r->h_levels,
                                              0, NULL, NULL),
                          "clEnqueueReadBuffer(level bytes)", err);
    rc = rc || spm_clr_bucket(r, n, r->h_levels, off, &ids, err) ||
         spm_clr_run_shade(r, &b, off, ids, 0, ev_s, err) ||
         spm_clr_run_bdpt_exponent(r, n, r->cap, &ev_a[0], err) || read_stat(r, stat, err);
    if (!rc) {
        int shift = spm_splat_shift(stat[1], n);
        rc = spm_clr_run_splat_add_of(r, r->xyz, n, shift, r->cap, &ev_a[1], err) ||
             spm_clr_run_splat_convert(r, shift, &ev_a[2], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(splats)", err);
    }
    if (rc)
        clFinish(r->cl.queue);
    else if (r->mode->levelled)
        spm_count_levels_hist(r->mode, r->lhist, n, st);
    st->shade_s += spm_clr_release_events(ev_s, NSLOTS, &st->untimed);
    st->accum_s += spm_clr_release_events(ev_a, 3, &st->untimed);
    return rc;
}

int spm_clr_bdpt_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                      spm_pass_stats *st, spm_error *err)
{
    if (reserve_records(r, SPM_BDPT_CHUNK * SPM_BDPT_ROOM_PER_SAMPLE, err) ||
        spm_clr_reserve_film(r, err))
        return 1;
    return spm_clr_splat_pass(r, first_sample, spp, SPM_BDPT_CHUNK, bdpt_chunk, pass_xyz, st, err);
}

/* Each kernel launched once per launch class with nothing to do
 * (spm_clr_warm_up says why). */
int spm_clr_bdpt_warm_up(spm_cl_renderer *r, spm_error *err)
{
    const size_t sizes[2] = {LOCAL_SIZE, 65536};
    int nsizes = strstr(r->cl.dev.platform_name, "Portable Computing Language") ? 2 : 1;
    int rc = reserve_records(r, SPM_BDPT_CHUNK * SPM_BDPT_ROOM_PER_SAMPLE, err) ||
             spm_clr_reserve_film(r, err);
    for (int k = 0; k < nsizes && !rc; k++) {
        batch b = {0, 1, 0, 0, r->cap, sizes[k]};
        cl_event ev[NSLOTS + 4] = {NULL};
        size_t off[NSLOTS + 1] = {0};
        rc = spm_clr_run_bdpt_trace(r, &b, 0, 0, &ev[NSLOTS], err) ||
             spm_clr_run_shade(r, &b, off, r->ident, 1, ev, err) ||
             spm_clr_run_bdpt_exponent(r, 0, sizes[k], &ev[NSLOTS + 1], err) ||
             spm_clr_run_splat_add_of(r, r->xyz, 0, 0, sizes[k], &ev[NSLOTS + 2], err) ||
             spm_clr_run_splat_convert(r, 0, &ev[NSLOTS + 3], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(warm-up)", err);
        spm_clr_release_events(ev, NSLOTS + 4, NULL);
    }
    return rc;
}
