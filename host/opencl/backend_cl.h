/* The OpenCL render backend: one device, one scene, one mode. A pass of
 * npix * spp paths is cut into batches of whole pixels (render_plan.h;
 * SPM_CL_BATCH_PATHS paths at most, cl_resources.h); each
 * batch is traced (kernel `spm_trace`), bucketed by level on the host, shaded
 * bucket by bucket with its level's kernel (or all with the mode's kernel),
 * and its pixels' samples summed in sample order (`spm_accumulate`), so the
 * pass image does not depend on the batch size. Buffers hold one batch, live
 * as long as the handle and grow only when a pass needs more.
 * Each handle has its own context, queue and program: handles may run in
 * parallel threads (one per device); one handle must not be used by two
 * threads at once. Every function returns 0 or fills err (never exits). */
#ifndef SPM_BACKEND_CL_H
#define SPM_BACKEND_CL_H
#include <stddef.h>
#include <stdint.h>
#include "backend.h"
#include "cl_core.h"
#include "film_splat.h"

typedef struct spm_cl_renderer spm_cl_renderer;

/* Uploads the plan's geometry, level table and shade tables, and builds the
 * program with -D for exactly the shade kernels the plan uses (levelled
 * modes: the levels the scene's colours can ask for). Everything is copied to
 * the device: the caller may free the plan after. */
int spm_cl_create_plan(int device, const spm_render_plan *plan, spm_cl_renderer **out,
                       spm_error *err);
/* The same with a plan made from g, t, mode and seed for the call. */
int spm_cl_create(int device, const spm_geometry *g, const spm_tables *t, int mode, spm_u32 seed,
                  spm_cl_renderer **out, spm_error *err);
void spm_cl_destroy(spm_cl_renderer *r);
/* Device `device` (index as `specmip devices` lists them) as a render backend. */
spm_backend *spm_backend_cl_create(int device, const spm_render_plan *plan, spm_error *err);
/* As a kind of backend (backend.h): one per device, checked against its memory. */
extern const spm_backend_kind spm_backend_kind_opencl;

/* One pass: samples [first_sample, first_sample + spp) of every pixel.
 * pass_xyz (npix * 3) receives per pixel the SUM of its samples' XYZ.
 * Stats are ADDED to *st: stage times from event profiling (trace, shade,
 * accumulate; the host's bucketing counts as shade), paths, paths per level by
 * set-by (level 0 in modes without levels), truncated paths, non-finite
 * samples left out. As a backend (spm_backend_cl_create) a pass may end early
 * at a batch boundary (backend.h: SPM_PASS_STOPPED). */
int spm_cl_pass(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, float *pass_xyz,
                spm_pass_stats *st, spm_error *err);

/* Test hooks. Trace only: the pass's records and level bytes read back
 * (npix * spp of each, batch by batch). */
int spm_cl_trace(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, spm_path *paths,
                 uint8_t *levels, spm_error *err);
/* Shade given records (n = npix * spp, uploaded batch by batch) in the
 * handle's mode, with the pass parameters hero needs; per-path records read
 * back (the plan's pix_ch floats a path: XYZ, then any spectral bins). */
int spm_cl_shade(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, const spm_path *paths,
                 const uint8_t *levels, float *xyz, spm_error *err);
/* The light integrator's test hooks (a handle of a plan of
 * SPM_INTEGRATOR_LIGHT): subpaths [first, first + n) of a pass (n at most
 * SPM_SPLAT_CHUNK, film_splat.h; subpath i keyed as camera path i). Trace
 * only: their records, level bytes and pixel words read back (px: n
 * (SPM_MAX_DEPTH + 1) words, slab s of subpath i at px[i (SPM_MAX_DEPTH + 1)
 * + s]: s = 0 the light's own splat, s = j + 1 vertex j's, SPM_NONE none),
 * as refcpu.h spm_light_path. Shade only: given records, level bytes and
 * pixel words (uploaded) shaded into their splats, appended to out (a list
 * of the plan's pix_ch; film_splat.h) in the device's order, each with the
 * pixel word it was given: a caller that gives each slab a word of its own
 * knows which subpath and vertex each splat came from. */
int spm_cl_light_trace(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                       size_t n, spm_path *paths, spm_u32 *px, uint8_t *levels, spm_error *err);
int spm_cl_light_shade(spm_cl_renderer *r, spm_u32 first_sample, spm_u32 spp, size_t first,
                       size_t n, const spm_path *paths, const spm_u32 *px, const uint8_t *levels,
                       spm_splats *out, spm_error *err);
/* Batches of at most `paths` paths from the next pass on (0: the default,
 * SPM_CL_BATCH_PATHS); a batch is still at least one pixel. */
void spm_cl_set_batch_paths(spm_cl_renderer *r, size_t paths);
/* Paths the per-batch device buffers have room for now (0 before a pass). */
size_t spm_cl_batch_capacity(const spm_cl_renderer *r);

/* The program a handle builds for a plan: these source files (relative to the
 * data root) with spm_cl_program_defines' options: each used slot's shade
 * kernel define (modes.h spm_mode_kernel), the spectral output's bins and
 * record size, the device's index. kname (NULL: not wanted) receives the
 * used slots' kernel names. tests/kernel_variants.c lists the programs from
 * these for the warnings test. */
#define SPM_CL_PROGRAM_NFILES 2
extern const char *const spm_cl_program_files[SPM_CL_PROGRAM_NFILES];
void spm_cl_program_defines(const spm_render_plan *plan, int device_index, char *defs, size_t size,
                            char (*kname)[64]);
/* The light integrator's program (a plan of SPM_INTEGRATOR_LIGHT, whose
 * defines add -DSPM_LIGHT_TRACE): these files, the same defines. */
#define SPM_CL_LIGHT_PROGRAM_NFILES 3
extern const char *const spm_cl_light_program_files[SPM_CL_LIGHT_PROGRAM_NFILES];
/* The bidirectional integrator's (SPM_INTEGRATOR_BDPT, -DSPM_BDPT): these. */
#define SPM_CL_BDPT_PROGRAM_NFILES 4
extern const char *const spm_cl_bdpt_program_files[SPM_CL_BDPT_PROGRAM_NFILES];

/* Failure injection for multi-device tests: SPECMIP_CL_FAIL="DEV:PASS" makes
 * device DEV's pass number PASS (0-based, counted per handle) fail with an
 * error as an enqueue failure would. */
#endif
