/* A render plan: what a render is, prepared once from the scene's geometry
 * and spectral tables, the mode and the seed, and read by every backend that
 * renders it (each backend is created from one; a multi-device render shares
 * one): the mode's descriptor and level table, the level a path starts from,
 * which of the mode's shade tables the scene's paths can need and those
 * tables, the trace parameters, and the rules that cut a pass into batches.
 * Also the per-pass statistics helpers every backend uses. */
#ifndef SPM_RENDER_PLAN_H
#define SPM_RENDER_PLAN_H
#include <stddef.h>
#include <stdint.h>
#include "geometry.h"
#include "modes.h"
#include "tables.h"

typedef struct {
    const spm_mode_desc *mode;
    const spm_geometry *geom;   /* not owned: must outlive the plan */
    const spm_tables *tables;   /* likewise */
    const uint8_t *lvlk;        /* the level feeler's table, level by colour and k, the times a
                                   path meets the colour (tables.h; spm_mode_lvlk) */
    spm_u32 start_level;        /* spm_plan_level_start */
    spm_trace_params params;    /* the scene's; spm_plan_pass_params adds a pass's samples */
    size_t npix;
    int nslots;                      /* spm_mode_nslots */
    int used[SPM_NUM_LEVELS];        /* slots a path of this scene can be shaded in */
    spm_shade_table shade[SPM_NUM_LEVELS]; /* their shade tables (the others empty) */
    /* Spectral output (spm_render_plan_spectral): bins of spec_nm nm, nspec
     * of them (0: none); each path's record and each pixel of a pass image
     * is then pix_ch = 3 + nspec floats, XYZ then the bins. */
    int spec_nm, nspec, pix_ch;
    spm_spec_map spec[SPM_NUM_LEVELS]; /* per slot: its lanes to the bins */
    /* The material and emitter types the scene uses (materials.h): the kernel
     * options that compile in their code and nothing else, and the bytes of a
     * path vertex's record (spm_vertex plus the fields those types declare). */
    char type_defines[256];
    size_t vertex_bytes;
    int integrator; /* SPM_INTEGRATOR_* (spm_render_plan_integrator) */
} spm_render_plan;

/* The integrators: camera paths with next-event estimation (the default),
 * subpaths from the lights splatted into the pixels they are seen in
 * (docs/ARCHITECTURE.md "Light subpaths"), or both joined in every way
 * (bidirectional, "Connected paths"). */
enum { SPM_INTEGRATOR_PATH, SPM_INTEGRATOR_LIGHT, SPM_INTEGRATOR_BDPT, SPM_INTEGRATOR_COUNT };
/* the integrator's name (--integrator), and the index of a name (-1: none) */
const char *spm_integrator_name(int integrator);
int spm_integrator_parse(const char *name);

/* 0, or 1 with err filled (unknown mode, empty image or BVH, missing tables). */
int spm_render_plan_init(spm_render_plan *p, const spm_geometry *g, const spm_tables *t, int mode,
                         spm_u32 seed, spm_error *err);
void spm_render_plan_free(spm_render_plan *p);
/* Renders with integrator i (before any backend is made from the plan):
 * 0, or 1 with err saying why the scene cannot be rendered so. */
int spm_render_plan_integrator(spm_render_plan *p, int i, spm_error *err);
/* Asks for spectral output in bins of nm nm (before any backend is made from
 * the plan). 0, or 1 with err filled when the mode writes none at nm. */
int spm_render_plan_spectral(spm_render_plan *p, int nm, spm_error *err);
/* The paths of a batch: base (a backend's batch size for XYZ alone) scaled
 * down so that a batch's vertex records (vertex_bytes a vertex: the plan's,
 * with the words of the scene's types), path records and batch image
 * together take no more memory than without spectral output. */
size_t spm_plan_batch_paths(size_t base, int pix_ch, size_t vertex_bytes);
/* The trace parameters of a pass of spp samples per pixel from first_sample. */
spm_trace_params spm_plan_pass_params(const spm_render_plan *p, spm_u32 first_sample, spm_u32 spp);

/* The level a path starts from (its level when it meets no colour finer): the
 * coarsest k = 1 level among the colours the scene's triangles and background
 * (p->bg_up, p->bg_down) use, so every path's level is one the scene has
 * tables for. 0 without a level table. */
int spm_plan_level_start(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                         const spm_trace_params *p);

/* Batches: a pass is traced and shaded in batches of whole pixels (a pixel's
 * samples stay together, and are summed in sample order), so a backend's
 * memory stays bounded whatever the image size and the pass image does not
 * depend on the batch size.
 * Pixels in one batch of a pass with spp samples per pixel: as many as keep
 * the batch within batch_paths paths, at least 1, at most npix. */
size_t spm_batch_pixels(size_t npix, size_t spp, size_t batch_paths);
/* Paths the per-batch buffers need room for: one batch; once a pass is cut
 * into several, a full batch_paths, so that a pass of fewer samples per pixel
 * (the last one) needs no more room. */
size_t spm_batch_room(size_t npix, size_t spp, size_t batch_paths);

/* Per-pass statistics of a backend. */
typedef struct {
    double trace_s, shade_s, accum_s;  /* stage times: kernel (event) time or CPU time */
    uint64_t paths;
    uint64_t level_paths[SPM_NUM_LEVELS][3]; /* paths shaded at each level, by SPM_SETBY_* */
    uint64_t truncated;                      /* paths that hit SPM_MAX_DEPTH */
    uint64_t nonfinite;                      /* samples with NaN/Inf XYZ, left out of the film */
    uint64_t untimed;                        /* kernel launches the device gave no time for:
                                                the stage times are then unknown */
} spm_pass_stats;

void spm_pass_stats_add(spm_pass_stats *into, const spm_pass_stats *s);
/* Counts n paths by level and set-by from their level bytes, by value:
 * hist[b] paths have level byte b. In a mode without levels every path counts
 * at level 0, set by nothing. */
void spm_count_levels_hist(const spm_mode_desc *m, const size_t hist[256], size_t n,
                           spm_pass_stats *st);
/* The same from the paths' level bytes, and their truncated paths. */
void spm_count_levels(const spm_mode_desc *m, const spm_path *paths, const uint8_t *levels,
                      size_t n, spm_pass_stats *st);
/* Sum each pixel's samples (contiguous, in sample order) into pass_xyz,
 * leaving out and counting non-finite samples. */
void spm_accumulate_pass(const float *xyz, size_t npix, spm_u32 spp, float *pass_xyz,
                         spm_pass_stats *st);
/* The same for records of ch floats (XYZ first): a sample is left out when
 * its XYZ is not finite. */
void spm_accumulate_pass_ch(const float *rec, size_t npix, spm_u32 spp, int ch, float *pass,
                            spm_pass_stats *st);
#endif
