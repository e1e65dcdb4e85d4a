/* The OpenCL backend's kernel launches (cl_renderer.h): each kernel's
 * arguments from a struct laid out by its parameter list in
 * spm_kernel_args.h, then the launch for one batch. */
#include "cl_renderer.h"
#include "spm_bdpt.h"

/* Host mirrors of the kernels' parameter lists. */
#define ARG_FIELD(dev, host, name) host name;
typedef struct { SPM_TRACE_ARGS(ARG_FIELD, ) } trace_args;
typedef struct { SPM_SHADE_ARGS(ARG_FIELD, ) } shade_args;
typedef struct { SPM_SHADE_PATH_ARGS(ARG_FIELD, ) } shade_path_args;
typedef struct { SPM_SHADE_SPEC_ARGS(ARG_FIELD, ) } shade_spec_args;
typedef struct { SPM_SHADE_DISP_ARGS(ARG_FIELD, ) } shade_disp_args;
typedef struct { SPM_ACCUM_ARGS(ARG_FIELD, ) } accum_args;
typedef struct { SPM_LIGHT_TRACE_ARGS(ARG_FIELD, ) } light_trace_args;
typedef struct { SPM_SPLAT_SHADE_ARGS(ARG_FIELD, ) } splat_shade_args;
typedef struct { SPM_SPLAT_ADD_ARGS(ARG_FIELD, ) } splat_add_args;
typedef struct { SPM_SPLAT_CONVERT_ARGS(ARG_FIELD, ) } splat_convert_args;
typedef struct { SPM_BDPT_TRACE_ARGS(ARG_FIELD, ) } bdpt_trace_args;
typedef struct { SPM_BDPT_EXP_ARGS(ARG_FIELD, ) } bdpt_exp_args;
typedef struct { SPM_BDPT_SHADE_ARGS(ARG_FIELD, ) } bdpt_shade_args;

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
DEFINE_SETTER(set_shade_spec_args, shade_spec_args, SPM_SHADE_SPEC_ARGS)
DEFINE_SETTER(set_shade_disp_args, shade_disp_args, SPM_SHADE_DISP_ARGS)
DEFINE_SETTER(set_accum_args, accum_args, SPM_ACCUM_ARGS)
DEFINE_SETTER(set_light_trace_args, light_trace_args, SPM_LIGHT_TRACE_ARGS)
DEFINE_SETTER(set_splat_shade_args, splat_shade_args, SPM_SPLAT_SHADE_ARGS)
DEFINE_SETTER(set_splat_add_args, splat_add_args, SPM_SPLAT_ADD_ARGS)
DEFINE_SETTER(set_splat_convert_args, splat_convert_args, SPM_SPLAT_CONVERT_ARGS)
DEFINE_SETTER(set_bdpt_trace_args, bdpt_trace_args, SPM_BDPT_TRACE_ARGS)
DEFINE_SETTER(set_bdpt_exp_args, bdpt_exp_args, SPM_BDPT_EXP_ARGS)
DEFINE_SETTER(set_bdpt_shade_args, bdpt_shade_args, SPM_BDPT_SHADE_ARGS)

static int enqueue(spm_cl_renderer *r, cl_kernel k, const char *name, size_t offset, size_t n,
                   cl_event *ev, spm_error *err)
{
    size_t off = offset, global = round_up(n), local = LOCAL_SIZE;
    char what[128];
    snprintf(what, sizeof what, "clEnqueueNDRangeKernel(%s)", name);
    return spm_cl_check(clEnqueueNDRangeKernel(r->cl.queue, k, 1, &off, &global, &local, 0, NULL, ev),
                        what, err);
}

/* The trace stage's arguments, for spm_trace or spm_light_trace (k). */
static int set_trace(spm_cl_renderer *r, cl_kernel k, const char *name, const batch *b,
                     cl_uint *i, spm_error *err)
{
    r->params.first_sample = b->first_sample;
    r->params.spp_per_pass = b->spp;
    trace_args a = {r->tris,  r->nodes, r->emitters,     r->mats, r->lvlk, r->light_pdf, r->vnormals,
                    r->disp, r->tex, r->uvs, r->envmap, r->params, r->init_level, (spm_u32)b->n, r->heads, r->verts,
                    r->levels, r->counters, b->first_pixel};
    return set_trace_args(k, name, &a, i, err);
}

int spm_clr_run_trace(spm_cl_renderer *r, const batch *b, cl_event *ev, spm_error *err)
{
    cl_uint i = 0;
    return set_trace(r, r->k_trace, "spm_trace", b, &i, err) ||
           enqueue(r, r->k_trace, "spm_trace", 0, b->launch, ev, err);
}

int spm_clr_run_light_trace(spm_cl_renderer *r, const batch *b, size_t first, cl_event *ev,
                            spm_error *err)
{
    light_trace_args la = {(spm_u32)first, r->lpx};
    cl_uint i = 0;
    return set_trace(r, r->k_ltrace, "spm_light_trace", b, &i, err) ||
           set_light_trace_args(r->k_ltrace, "spm_light_trace", &la, &i, err) ||
           enqueue(r, r->k_ltrace, "spm_light_trace", 0, b->launch, ev, err);
}

int spm_clr_run_bdpt_trace(spm_cl_renderer *r, const batch *b, size_t first, size_t nsamples,
                           cl_event *ev, spm_error *err)
{
    bdpt_trace_args ba = {(spm_u32)first, (spm_u32)nsamples, r->spx, r->lstat, r->bsam};
    cl_uint i = 0;
    return set_trace(r, r->k_btrace, "spm_bdpt_trace", b, &i, err) ||
           set_bdpt_trace_args(r->k_btrace, "spm_bdpt_trace", &ba, &i, err) ||
           enqueue(r, r->k_btrace, "spm_bdpt_trace", 0, b->launch, ev, err);
}

int spm_clr_run_bdpt_exponent(spm_cl_renderer *r, size_t n, size_t launch, cl_event *ev,
                              spm_error *err)
{
    bdpt_exp_args a = {r->xyz, (spm_u32)n, r->lstat};
    cl_uint i = 0;
    return set_bdpt_exp_args(r->k_bexp, "spm_bdpt_exponent", &a, &i, err) ||
           enqueue(r, r->k_bexp, "spm_bdpt_exponent", 0, launch, ev, err);
}

int spm_clr_run_splat_add(spm_cl_renderer *r, size_t n, int shift, size_t launch, cl_event *ev,
                          spm_error *err)
{
    return spm_clr_run_splat_add_of(r, r->sval, n, shift, launch, ev, err);
}

int spm_clr_run_splat_add_of(spm_cl_renderer *r, cl_mem sval, size_t n, int shift, size_t launch,
                             cl_event *ev, spm_error *err)
{
    splat_add_args a = {r->spx, sval, (spm_u32)n, shift, r->acc, r->counters};
    cl_uint i = 0;
    return set_splat_add_args(r->k_sadd, "spm_splat_add", &a, &i, err) ||
           enqueue(r, r->k_sadd, "spm_splat_add", 0, launch, ev, err);
}

int spm_clr_run_splat_convert(spm_cl_renderer *r, int shift, cl_event *ev, spm_error *err)
{
    splat_convert_args a = {r->acc, (spm_u32)r->npix, shift, r->lpass};
    cl_uint i = 0;
    return set_splat_convert_args(r->k_sconv, "spm_splat_convert", &a, &i, err) ||
           enqueue(r, r->k_sconv, "spm_splat_convert", 0, r->npix, ev, err);
}

int spm_clr_run_shade(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1],
                      cl_mem ids, int all, cl_event ev[NSLOTS], spm_error *err)
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
         * spm_clr_build() keeps devices from sharing kernels
         * (SPM_DEVICE_INDEX); this is a second guard, kept because its cost,
         * empty work-groups when ml splits a pass, was below the noise on
         * cornell_spiky (two buckets a pass: shade time the same launched
         * either way). The last batch of a pass is launched at full size too,
         * for the same reason. */
        shade_args a = {r->heads, r->verts,  (spm_u32)b->n, ids,     (spm_u32)off[s],
                        (spm_u32)off[s + 1], r->tab[s], r->cmf[s],
                        r->light && !r->bdpt ? r->sval : r->xyz};
        splat_shade_args la = {r->lpx, r->spx, r->lstat, (spm_u32)r->scap, r->pofs};
        shade_path_args pa = {r->extra, r->params.seed, spm_divisor_make(b->spp), b->first_sample,
                              b->first_pixel};
        shade_spec_args sa = {r->smap[s], r->sfac[s]};
        shade_disp_args da = {r->dtab, r->dcmf};
        bdpt_shade_args ba = {r->bsam};
        cl_uint i = 0;
        int rc = set_shade_args(r->k_shade[s], r->kname[s], &a, &i, err) ||
                 (r->mode->per_path && set_shade_path_args(r->k_shade[s], r->kname[s], &pa, &i, err)) ||
                 (r->mode->per_path && r->bdpt && set_bdpt_shade_args(r->k_shade[s], r->kname[s], &ba, &i, err)) ||
                 (r->pix_ch > 3 && set_shade_spec_args(r->k_shade[s], r->kname[s], &sa, &i, err)) ||
                 (r->light && !r->bdpt && set_splat_shade_args(r->k_shade[s], r->kname[s], &la, &i, err)) ||
                 (r->ndisp && set_shade_disp_args(r->k_shade[s], r->kname[s], &da, &i, err));
        if (rc || enqueue(r, r->k_shade[s], r->kname[s], 0, b->launch, &ev[s], err))
            return 1;
    }
    return 0;
}

int spm_clr_run_accumulate(spm_cl_renderer *r, const batch *b, cl_event *ev, spm_error *err)
{
    accum_args a = {r->xyz, b->npix, b->spp, r->pass, r->counters};
    cl_uint i = 0;
    return set_accum_args(r->k_accum, "spm_accumulate", &a, &i, err) ||
           enqueue(r, r->k_accum, "spm_accumulate", 0, b->launch / b->spp, ev, err);
}
