/* The OpenCL backend's light integrator (cl_renderer.h; docs/ARCHITECTURE.md
 * "Light subpaths"): a pass's subpaths in chunks of SPM_SPLAT_CHUNK by their
 * index in the pass, as the CPU reference cuts them. Per chunk: trace
 * (spm_light_trace), bucket by level, shade into the chunk's splat list (the
 * shade kernels' _lt twins, which also count the splats and keep their
 * largest exponent), then the fixed-point sums at the unit
 * film_splat.c's spm_splat_shift gives (spm_splat_add, 64-bit integer
 * atomics: the order of the adds does not matter) and their conversion into
 * the device's pass image (spm_splat_convert, in double as the host's). */
#include <stdlib.h>
#include <string.h>
#include "cl_renderer.h"
#include "film_splat.h"

const char *const spm_cl_light_program_files[SPM_CL_LIGHT_PROGRAM_NFILES] = {
    "kernels/trace.cl", "kernels/shade.cl", "kernels/lighttrace.cl"};

/* What the fixed-point film needs of a device: 64-bit integer atomics for
 * the sums, doubles for their conversion. */
int spm_clr_splat_device_check(spm_cl_renderer *r, const char *integrator, spm_error *err)
{
    char ext[8192] = "";
    clGetDeviceInfo(r->cl.dev.device, CL_DEVICE_EXTENSIONS, sizeof ext - 1, ext, NULL);
    const char *need[] = {"cl_khr_int64_base_atomics", "cl_khr_fp64"};
    for (int i = 0; i < 2; i++)
        if (!strstr(ext, need[i])) {
            spm_errorf(err,
                       "--integrator %s needs %s on the device ('%s' has not): the splats' "
                       "fixed-point sums need it (--backend cpu renders it)",
                       integrator, need[i], r->cl.dev.name);
            return 1;
        }
    return 0;
}

int spm_clr_splat_build(spm_cl_renderer *r, const spm_render_plan *plan, const char *integrator,
                        const char *const *files, int nfiles, const char *defs,
                        const spm_clr_named_kernel *ks, int nks, const char *suffix,
                        spm_error *err)
{
    r->light = 1;
    if (spm_clr_splat_device_check(r, integrator, err) ||
        spm_cl_build(&r->cl, files, nfiles, defs, &r->prog, err))
        return 1;
    cl_int rc;
    for (int i = 0; i < nks; i++) {
        *ks[i].k = clCreateKernel(r->prog, ks[i].name, &rc);
        CK(rc, ks[i].name);
    }
    for (int s = 0; s < plan->nslots; s++)
        if (plan->used[s]) {
            size_t n = strlen(r->kname[s]);
            snprintf(r->kname[s] + n, sizeof r->kname[s] - n, "%s", suffix);
            r->k_shade[s] = clCreateKernel(r->prog, r->kname[s], &rc);
            CK(rc, r->kname[s]);
        }
    return 0;
}

int spm_clr_light_build(spm_cl_renderer *r, const spm_render_plan *plan, const char *defs,
                        spm_error *err)
{
    const spm_clr_named_kernel ks[] = {{&r->k_ltrace, "spm_light_trace"},
                                       {&r->k_sadd, "spm_splat_add"},
                                       {&r->k_sconv, "spm_splat_convert"}};
    return spm_clr_splat_build(r, plan, "light", spm_cl_light_program_files,
                               SPM_CL_LIGHT_PROGRAM_NFILES, defs, ks, 3, "_lt", err);
}

static void release_mem(cl_mem *m)
{
    if (*m)
        clReleaseMemObject(*m);
    *m = NULL;
}

void spm_clr_light_release(spm_cl_renderer *r)
{
    cl_kernel *ks[] = {&r->k_ltrace, &r->k_sadd, &r->k_sconv};
    for (int i = 0; i < 3; i++)
        if (*ks[i]) {
            clReleaseKernel(*ks[i]);
            *ks[i] = NULL;
        }
    cl_mem *ms[] = {&r->lpx, &r->spx, &r->sval, &r->lstat, &r->acc, &r->lpass};
    for (int i = 0; i < 6; i++)
        release_mem(ms[i]);
}

/* Room for a splat list of n splats; only grows. */
int spm_clr_reserve_splats(spm_cl_renderer *r, size_t n, spm_error *err)
{
    if (n <= r->scap)
        return 0;
    release_mem(&r->spx);
    release_mem(&r->sval);
    r->scap = 0;
    if (spm_clr_new_buffer(r, &r->spx, CL_MEM_READ_WRITE, n * sizeof(spm_u32), NULL,
                           "splat pixels", err) ||
        spm_clr_new_buffer(r, &r->sval, CL_MEM_READ_WRITE, n * (size_t)r->pix_ch * sizeof(float),
                           NULL, "splat values", err))
        return 1;
    r->scap = n;
    return 0;
}

int spm_clr_reserve_light(spm_cl_renderer *r, size_t n, spm_error *err)
{
    if (spm_clr_reserve(r, n, err))
        return 1;
    if (n > r->lcap) {
        release_mem(&r->lpx);
        r->lcap = 0;
        if (spm_clr_new_buffer(r, &r->lpx, CL_MEM_READ_WRITE,
                               n * (SPM_MAX_DEPTH + 1) * sizeof(spm_u32), NULL, "splat pixel words",
                               err))
            return 1;
        r->lcap = n;
    }
    return spm_clr_reserve_splats(r, 2 * n, err) || spm_clr_reserve_film(r, err);
}

int spm_clr_reserve_film(spm_cl_renderer *r, spm_error *err)
{
    if (r->acc)
        return 0;
    size_t cells = r->npix * (size_t)r->pix_ch;
    int64_t *zero = spm_xcalloc(cells, sizeof *zero);
    int rc = spm_clr_new_buffer(r, &r->acc, CL_MEM_READ_WRITE, cells * sizeof *zero, zero,
                                "splat sums", err) ||
             spm_clr_new_buffer(r, &r->lpass, CL_MEM_READ_WRITE, cells * sizeof(float), NULL,
                                "pass image", err) ||
             spm_clr_new_buffer(r, &r->lstat, CL_MEM_READ_WRITE, 2 * sizeof(cl_int), NULL,
                                "splat count", err);
    free(zero);
    return rc;
}

/* lstat to (0 splats, no exponent), then the shade kernels over the chunk's buckets. */
static int shade_splats(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1],
                        cl_mem ids, cl_event ev[NSLOTS], spm_error *err)
{
    static const cl_int none[2] = {0, -1074};
    CK(clEnqueueWriteBuffer(r->cl.queue, r->lstat, CL_TRUE, 0, sizeof none, none, 0, NULL, NULL),
       "clEnqueueWriteBuffer(splat count)");
    return spm_clr_run_shade(r, b, off, ids, 0, ev, err);
}

int spm_clr_light_splats(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1],
                         cl_mem ids, cl_event ev_s[NSLOTS], cl_int stat[2], uint64_t *untimed,
                         spm_error *err)
{
    int rc = shade_splats(r, b, off, ids, ev_s, err);
    for (int again = 0; !rc && again < 2; again++) {
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->lstat, CL_TRUE, 0,
                                              2 * sizeof *stat, stat, 0, NULL, NULL),
                          "clEnqueueReadBuffer(splat count)", err);
        if (rc || (size_t)(spm_u32)stat[0] <= r->scap)
            break;
        /* more splats than room: room for them all, and the chunk shaded again */
        spm_clr_release_events(ev_s, NSLOTS, untimed);
        rc = spm_clr_reserve_splats(r, (size_t)(spm_u32)stat[0], err) ||
             shade_splats(r, b, off, ids, ev_s, err);
    }
    return rc;
}

/* One chunk: subpaths [first, first + b->n) of the pass. */
static int light_chunk(spm_cl_renderer *r, const batch *b, size_t first, spm_pass_stats *st,
                       spm_error *err)
{
    cl_event ev_t = NULL, ev_s[NSLOTS] = {NULL}, ev_a[2] = {NULL};
    size_t off[NSLOTS + 1];
    cl_mem ids = NULL;
    cl_int stat[2] = {0, 0};
    int rc = spm_clr_run_light_trace(r, b, first, &ev_t, err);
    if (!rc && r->mode->levelled)
        rc = spm_cl_check(clEnqueueReadBuffer(r->cl.queue, r->levels, CL_TRUE, 0, b->n,
                                              r->h_levels, 1, &ev_t, NULL),
                          "clEnqueueReadBuffer(level bytes)", err);
    rc = rc || spm_clr_bucket(r, b->n, r->h_levels, off, &ids, err) ||
         spm_clr_light_splats(r, b, off, ids, ev_s, stat, &st->untimed, err);
    size_t n = (size_t)(spm_u32)stat[0];
    if (!rc && n) {
        int shift = spm_splat_shift(stat[1], n);
        rc = spm_clr_run_splat_add(r, n, shift, n, &ev_a[0], err) ||
             spm_clr_run_splat_convert(r, shift, &ev_a[1], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(splats)", err);
    }
    if (rc)
        clFinish(r->cl.queue);
    else if (r->mode->levelled)
        spm_count_levels_hist(r->mode, r->lhist, b->n, st);
    st->trace_s += spm_clr_release_events(&ev_t, 1, &st->untimed);
    st->shade_s += spm_clr_release_events(ev_s, NSLOTS, &st->untimed);
    st->accum_s += spm_clr_release_events(ev_a, 2, &st->untimed);
    return rc;
}

int spm_clr_splat_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t chunk,
                       spm_clr_chunk_fn fn, float *pass_xyz, spm_pass_stats *st, spm_error *err)
{
    size_t n = r->npix * spp;
    static const float zero = 0.0f;
    size_t bytes = r->npix * (size_t)r->pix_ch * sizeof(float);
    if (spm_clr_zero_counters(r, err))
        return 1;
    CK(clEnqueueFillBuffer(r->cl.queue, r->lpass, &zero, sizeof zero, 0, bytes, 0, NULL, NULL),
       "clEnqueueFillBuffer(pass image)");
    for (size_t c0 = 0; c0 < n; c0 += chunk) {
        size_t nb = n - c0 < chunk ? n - c0 : chunk;
        if (fn(r, first_sample, spp, c0, nb, st, err))
            return 1;
        if (c0 + nb < n && spm_pass_batch_end(r->ctl, c0 + nb))
            return SPM_PASS_STOPPED;
    }
    CK(clEnqueueReadBuffer(r->cl.queue, r->lpass, CL_TRUE, 0, bytes, pass_xyz, 0, NULL, NULL),
       "clEnqueueReadBuffer(pass image)");
    return 0;
}

batch spm_clr_light_batch(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                          size_t nb)
{
    size_t n = r->npix * spp, room = n < SPM_SPLAT_CHUNK ? n : SPM_SPLAT_CHUNK;
    r->pofs = (spm_u32)(first % spp);
    return (batch){first_sample, spp, (spm_u32)(first / spp), 0, nb, room};
}

static int light_chunk_of(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                          size_t nb, spm_pass_stats *st, spm_error *err)
{
    batch b = spm_clr_light_batch(r, first_sample, spp, first, nb);
    return light_chunk(r, &b, first, st, err);
}

int spm_clr_light_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                       spm_pass_stats *st, spm_error *err)
{
    size_t n = r->npix * spp, room = n < SPM_SPLAT_CHUNK ? n : SPM_SPLAT_CHUNK;
    if (spm_clr_reserve_light(r, room, err))
        return 1;
    return spm_clr_splat_pass(r, first_sample, spp, SPM_SPLAT_CHUNK, light_chunk_of, pass_xyz, st,
                              err);
}

/* Each kernel launched once per launch class with nothing to do
 * (spm_clr_warm_up says why); the buffers exist by then. */
int spm_clr_light_warm_up(spm_cl_renderer *r, spm_error *err)
{
    const size_t sizes[2] = {LOCAL_SIZE, 65536};
    int nsizes = strstr(r->cl.dev.platform_name, "Portable Computing Language") ? 2 : 1;
    int rc = spm_clr_reserve_light(r, LOCAL_SIZE, err);
    for (int k = 0; k < nsizes && !rc; k++) {
        batch b = {0, 1, 0, 0, 0, sizes[k]};
        cl_event ev[NSLOTS + 3] = {NULL};
        size_t off[NSLOTS + 1] = {0};
        rc = spm_clr_run_light_trace(r, &b, 0, &ev[NSLOTS], err) ||
             spm_clr_run_shade(r, &b, off, r->ident, 1, ev, err) ||
             spm_clr_run_splat_add(r, 0, 0, sizes[k], &ev[NSLOTS + 1], err) ||
             spm_clr_run_splat_convert(r, 0, &ev[NSLOTS + 2], err) ||
             spm_cl_check(clFinish(r->cl.queue), "clFinish(warm-up)", err);
        spm_clr_release_events(ev, NSLOTS + 3, NULL);
    }
    return rc;
}
