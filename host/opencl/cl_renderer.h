/* The OpenCL backend's parts (backend_cl.h), shared by its files:
 *   backend_cl.c         the handle and the pass pipeline trace -> bucket ->
 *                        shade -> accumulate
 *   cl_buffers.c         the device layout: scene buffers, shade tables, batch
 *                        buffers (cl_buffers.h)
 *   cl_render_program.c  the renderer's program: which kernels, with which
 *                        defines (built through cl_core.h)
 *   cl_kernels.c         kernel arguments (spm_kernel_args.h) and launches
 *   cl_light.c           the light integrator's program and passes (chunks of
 *                        subpaths, their splats summed in fixed point)
 *   cl_test_hooks.c      trace-only and shade-only passes for the tests (camera
 *                        paths, and light subpaths with their pixel words and
 *                        splats), and failure injection */
#ifndef SPM_CL_RENDERER_H
#define SPM_CL_RENDERER_H
#include <stdio.h>
#include "cl_buffers.h"
#include "cl_resources.h"
#include "backend_cl.h"
#include "spm_kernel_args.h"

/* Kernels and shade tables by slot: a levelled mode's levels, else slot 0
 * (modes.h). */
#define NSLOTS SPM_NUM_LEVELS
/* Work-group size asked for (PoCL runs a group's work-items in one thread; 64
 * amortises the per-group cost and keeps the last group's waste small). */
#define LOCAL_SIZE SPM_LOCAL_SIZE

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
    int pix_ch;                          /* floats a path record holds (render_plan.h) */
    size_t vertex_bytes;                 /* bytes of a path vertex's record (render_plan.h) */
    cl_mem smap[NSLOTS], sfac[NSLOTS];   /* spectral records: lanes to bins (pix_ch > 3) */
    int ndisp; /* dispersive glasses: the shade kernels take SPM_SHADE_DISP_ARGS */
#define SCENE_FIELD(field, what, bytes, host) cl_mem field;
    SPM_CL_SCENE_BUFFERS(SCENE_FIELD)
#undef SCENE_FIELD
    /* per-batch buffers (room for cap paths), grown on demand; pass: the
     * batch's pixel sums */
    size_t cap;
    size_t batch_paths; /* a batch's paths, at most (SPM_CL_BATCH_PATHS; test hook) */
#define BATCH_FIELD(field, what, per_path, flags, init) cl_mem field;
    SPM_CL_BATCH_BUFFERS(BATCH_FIELD)
#undef BATCH_FIELD
    cl_mem counters;
    uint8_t *h_levels;
    spm_u32 *h_idx; /* bucket indices, the source of idx's non-blocking upload */
    size_t lhist[256]; /* levelled modes: the pass's level bytes counted by value (bucket()) */
    spm_u32 zero[SPM_NCOUNTERS];
    /* the light integrator's (cl_light.c; light set: the program is
     * kernels/lighttrace.cl's, k_shade the shade kernels' _lt twins): the
     * pixel words of lcap subpaths, the chunk's splat list of room scap
     * (pixels, values), lstat (count, largest exponent), the fixed-point
     * sums and the pass image of npix pixels; pofs the chunk's offset in its
     * first pixel (SPM_SPLAT_SHADE_ARGS) */
    int light;
    cl_kernel k_ltrace, k_sadd, k_sconv;
    cl_mem lpx, spx, sval, lstat, acc, lpass;
    size_t lcap, scap;
    spm_u32 pofs;
    /* the bidirectional integrator's (cl_bdpt.c; bdpt set, light too for the
     * splat film: spx the records' pixels, lstat (records, largest exponent)) */
    int bdpt;
    cl_kernel k_btrace, k_bexp;
    cl_mem bsam; /* each record's sample in the pass (SPM_BDPT_TRACE_ARGS rsam), bcap of them */
    size_t bcap;
    /* spm_clr_render_pass, or with SPECMIP_CL_FAIL the test hook around it */
    int (*run_pass)(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                    spm_pass_stats *st, spm_error *err);
    long npasses;
    long fail_pass; /* SPECMIP_CL_FAIL: this pass fails (-1: never) */
    const spm_pass_ctl *ctl; /* the backend's, during its passes (NULL: none) */
};

#define CK(call, what)                     \
    do {                                   \
        if (spm_cl_check((call), what, err)) \
            return 1;                      \
    } while (0)

/* One batch of a pass: pixels first_pixel .. first_pixel + npix - 1, spp
 * samples each from first_sample, n = npix * spp paths whose records are
 * indexed from 0. Every trace and shade launch of a pass has `launch`
 * work-items, a full batch (see run_shade), and every accumulate launch
 * launch / spp. */
typedef struct {
    spm_u32 first_sample, spp, first_pixel, npix;
    size_t n, launch;
} batch;

/* cl_buffers.c */
int spm_clr_new_buffer(spm_cl_renderer *r, cl_mem *m, cl_mem_flags fl, size_t bytes,
                       const void *host, const char *what, spm_error *err);
/* The scene's buffers, the shade tables of the slots the plan uses, the counters. */
int spm_clr_upload(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err);
/* Per-batch buffers for n paths (and up to n pixels); only grows. */
int spm_clr_reserve(spm_cl_renderer *r, size_t n, spm_error *err);
void spm_clr_release_buffers(spm_cl_renderer *r);

/* cl_render_program.c: builds the program with the plan's kernels, creates them and
 * launches each once (spm_clr_warm_up). */
int spm_clr_build(spm_cl_renderer *r, const spm_render_plan *plan, spm_error *err);
int spm_clr_warm_up(spm_cl_renderer *r, spm_error *err);

/* cl_kernels.c: set a kernel's arguments and enqueue it for one batch. */
int spm_clr_run_trace(spm_cl_renderer *r, const batch *b, cl_event *ev, spm_error *err);
/* The shade kernel of every non-empty bucket (slot s: entries off[s] ..
 * off[s+1] of ids; every kernel the program has, when `all`); events in
 * ev[slot]. */
int spm_clr_run_shade(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1],
                      cl_mem ids, int all, cl_event ev[NSLOTS], spm_error *err);
int spm_clr_run_accumulate(spm_cl_renderer *r, const batch *b, cl_event *ev, spm_error *err);

/* cl_kernels.c, the light integrator's: spm_light_trace for the n subpaths
 * of b from subpath `first` of the pass; the splats' sums (n splats) at the
 * unit 2^-shift, and their conversion into the pass image. */
int spm_clr_run_light_trace(spm_cl_renderer *r, const batch *b, size_t first, cl_event *ev,
                            spm_error *err);
int spm_clr_run_splat_add(spm_cl_renderer *r, size_t n, int shift, size_t launch, cl_event *ev,
                          spm_error *err);
/* cl_kernels.c, the bidirectional integrator's: spm_bdpt_trace for samples
 * first .. first + nsamples - 1 of the pass into records of stride b->n;
 * spm_bdpt_exponent over the n records' values (xyz) */
int spm_clr_run_bdpt_trace(spm_cl_renderer *r, const batch *b, size_t first, size_t nsamples,
                           cl_event *ev, spm_error *err);
int spm_clr_run_bdpt_exponent(spm_cl_renderer *r, size_t n, size_t launch, cl_event *ev,
                              spm_error *err);
/* the same over the n values of sval (pixels in spx), the bidirectional's records */
int spm_clr_run_splat_add_of(spm_cl_renderer *r, cl_mem sval, size_t n, int shift, size_t launch,
                             cl_event *ev, spm_error *err);
int spm_clr_run_splat_convert(spm_cl_renderer *r, int shift, cl_event *ev, spm_error *err);

/* cl_light.c: the light integrator's program (after spm_cl_program_defines'
 * defs), its warm-up, and a pass of it: subpaths in chunks of
 * SPM_SPLAT_CHUNK, each traced, shaded into splats and summed in fixed point
 * on the device, the pass image read into pass_xyz. */
int spm_clr_light_build(spm_cl_renderer *r, const spm_render_plan *plan, const char *defs,
                        spm_error *err);
int spm_clr_light_warm_up(spm_cl_renderer *r, spm_error *err);
int spm_clr_light_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                       spm_pass_stats *st, spm_error *err);
void spm_clr_light_release(spm_cl_renderer *r);
/* cl_light.c: what the fixed-point film needs of the device (integrator: the
 * name in the error); room for n splats, and the film (sums, pass image,
 * lstat) once. */
int spm_clr_splat_device_check(spm_cl_renderer *r, const char *integrator, spm_error *err);
/* A program of the splat film (cl_light.c; r->light set): that check, the
 * build of files with defs, the named kernels, and each used slot's shade
 * kernel, its name with suffix appended. */
typedef struct {
    cl_kernel *k;
    const char *name;
} spm_clr_named_kernel;
int spm_clr_splat_build(spm_cl_renderer *r, const spm_render_plan *plan, const char *integrator,
                        const char *const *files, int nfiles, const char *defs,
                        const spm_clr_named_kernel *ks, int nks, const char *suffix,
                        spm_error *err);
int spm_clr_reserve_splats(spm_cl_renderer *r, size_t n, spm_error *err);
int spm_clr_reserve_film(spm_cl_renderer *r, spm_error *err);
/* cl_light.c, a chunk's steps (its pass and the test hooks): the batch
 * buffers and the pixel words for n subpaths, the splat list, and (once) the
 * sums, zeroed, the pass image and lstat; the batch of subpaths
 * [first, first + nb) of a pass (nb <= SPM_SPLAT_CHUNK), launched at the full
 * chunk's size (cl_kernels.c run_shade says why), r->pofs its offset in its
 * first pixel; the chunk's records bucketed (off, ids) shaded into the splat
 * list, shaded again with room for all when they overflow it: stat the
 * splats' count and largest exponent. */
int spm_clr_reserve_light(spm_cl_renderer *r, size_t n, spm_error *err);
batch spm_clr_light_batch(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                          size_t nb);
int spm_clr_light_splats(spm_cl_renderer *r, const batch *b, const size_t off[NSLOTS + 1],
                         cl_mem ids, cl_event ev_s[NSLOTS], cl_int stat[2], uint64_t *untimed,
                         spm_error *err);

/* cl_light.c: a pass of the splat film: its pass image zeroed, its
 * npix spp items in chunks [first, first + n) of `chunk`, each given to fn
 * (which adds its splats into the image), the image read into pass_xyz;
 * SPM_PASS_STOPPED between chunks when the pass control says so. */
typedef int (*spm_clr_chunk_fn)(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp,
                                size_t first, size_t n, spm_pass_stats *st, spm_error *err);
int spm_clr_splat_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t chunk,
                       spm_clr_chunk_fn fn, float *pass_xyz, spm_pass_stats *st, spm_error *err);

/* cl_bdpt.c: the bidirectional integrator's program, warm-up and pass (samples
 * in chunks of SPM_BDPT_CHUNK, their connected paths' records shaded by the
 * mode's kernels and splatted into the fixed-point film). */
int spm_clr_bdpt_build(spm_cl_renderer *r, const spm_render_plan *plan, const char *defs,
                       spm_error *err);
int spm_clr_bdpt_warm_up(spm_cl_renderer *r, spm_error *err);
int spm_clr_bdpt_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                      spm_pass_stats *st, spm_error *err);
void spm_clr_bdpt_release(spm_cl_renderer *r);

/* backend_cl.c: the pipeline's steps the test hooks reuse. */
/* Samples [first_sample, first_sample + spp) of every pixel, batch by batch
 * (render_plan.h's cut into whole pixels), each batch given to fn: 0, or
 * fn's first non-zero return (1 with err filled, or SPM_PASS_STOPPED). The
 * device counters are zeroed first when zero_counters is set. */
typedef int (*spm_clr_batch_fn)(spm_cl_renderer *r, const batch *b, void *ctx, spm_error *err);
int spm_clr_each_batch(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, int zero_counters,
                       spm_clr_batch_fn fn, void *ctx, spm_error *err);
int spm_clr_zero_counters(spm_cl_renderer *r, spm_error *err);
int spm_clr_bucket(spm_cl_renderer *r, size_t n, const uint8_t *levels, size_t off[NSLOTS + 1],
                   cl_mem *ids, spm_error *err);
/* The events' kernel seconds; those without a time are counted in *untimed
 * (if not NULL). */
double spm_clr_release_events(cl_event *ev, int n, uint64_t *untimed);

/* cl_test_hooks.c: SPECMIP_CL_FAIL (backend_cl.h) for device `device`: the
 * handle's passes then go through a pass that fails at the named one. */
void spm_clr_fail_init(spm_cl_renderer *r, int device);
/* The pass itself (backend_cl.c), which spm_cl_pass runs unless a failure is injected. */
int spm_clr_render_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                        spm_pass_stats *st, spm_error *err);
#endif
