/* The CPU reference: MiniLight's transport and every mode's shading in plain
 * scalar C. Shares structs, constants and the RNG with the kernels through
 * include/, never their arithmetic. */
#ifndef SPM_REFCPU_H
#define SPM_REFCPU_H
#include <stddef.h>
#include <stdint.h>
#include "geometry.h"
#include "modes.h"
#include "tables.h"
#include "film_splat.h"

/* Trace one pass: npix * p->spp_per_pass paths; path i belongs to pixel
 * i / spp_per_pass and sample p->first_sample + i % spp_per_pass. Writes the
 * records and each path's level byte (level feeler on `lvlk`, see tables.h). */
void spm_ref_trace(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                   const spm_trace_params *p, spm_path *paths, uint8_t *levels);

/* Shade n records in mode m to XYZ (3 floats per path) with the mode's shade
 * tables (tabs[slot], modes.h). A levelled mode shades each path in the slot
 * of its level byte; a mode that draws its lanes per path (hero) keys them by
 * (pixel, sample), so it needs the pass parameters and `first`, the pass
 * index of paths[0] (0 for a whole pass). */
void spm_ref_shade_tables(const spm_mode_desc *m, const spm_shade_table *tabs,
                          const spm_trace_params *p, size_t first, const spm_path *paths,
                          const uint8_t *levels, size_t n, float *xyz);
/* The same with a spectral record per path: ch floats a path (XYZ, then
 * ch - 3 spectral bins through maps[slot], modes.h spm_spec_map; a per-path
 * mode puts each lane into the 5 nm bin holding its wavelength, divided by its
 * density, the lane count and the bin width). ch 3: no bins (maps unused). */
void spm_ref_shade_spectral(const spm_mode_desc *m, const spm_shade_table *tabs,
                            const spm_spec_map *maps, int ch, const spm_trace_params *p,
                            size_t first, const spm_path *paths, const uint8_t *levels, size_t n,
                            float *rec);
/* The same in mode `mode` with shade tables built from t for the call. */
void spm_ref_shade(const spm_tables *t, int mode, const spm_trace_params *p, size_t first,
                   const spm_path *paths, const uint8_t *levels, size_t n, float *xyz);

/* Record conventions: a weight is 0 whenever its colour is SPM_NONE
 * (first_emit_c, bg_c, a vertex's c); only h.nvert vertices are written.
 * A path whose record is full (SPM_MAX_DEPTH vertices) and that survives
 * Russian roulette at the last one ends SPM_END_TRUNCATED.
 * Level feeler order: first-hit emission, then per vertex its reflectance
 * (k = its occurrences so far on the path) and its emitter (k = 1), then the
 * background (k = 1); each lowers the level only when strictly finer, and
 * records who did. lvlk may be NULL (modes that ignore levels: byte 0). */

/* Path i of a pass belongs to this pixel and sample (the RNG's key). */
static inline void spm_ref_path_key(const spm_trace_params *p, size_t i, spm_u32 *pixel,
                                    spm_u32 *sample)
{
    *pixel = (spm_u32)(i / p->spp_per_pass);
    *sample = p->first_sample + (spm_u32)(i % p->spp_per_pass);
}

/* Ray recording (`specmip bench --rays`): while set on a thread, every ray
 * that thread's reference trace casts is passed to fn as a spm_ray
 * (spm_shared.h: a shadow ray names its emitter triangle) before it is cast.
 * It only observes: the paths are the same with it or without. */
typedef struct {
    void (*fn)(void *ctx, const spm_ray *ray);
    void *ctx;
} spm_ref_ray_sink;
extern _Thread_local spm_ref_ray_sink spm_ref_rays;

/* Paths [begin, end) of the pass into paths[0 .. end-begin-1] and likewise
 * levels (a batch or a slice per thread); start_level from
 * spm_plan_level_start (render_plan.h). */
void spm_ref_trace_range(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                         int start_level, const spm_trace_params *p, size_t begin, size_t end,
                         spm_path *paths, uint8_t *levels);

/* A light subpath's record (--integrator light; docs/ARCHITECTURE.md "Light
 * subpaths"): p is a path record read from the light: h.first_emit the
 * light's emission colour and h.first_emit_c the splat weight of the light's
 * own vertex; vertex j its colour, the light's emission colour as its
 * emitter and c the splat weight of its connection to the camera (f |cos|
 * We / pdf_Wi times the throughput so far and the light's Le / pdf), x[j]
 * the factor's words as a camera path's. px[0] is the pixel the light's own
 * splat lands in, px[j + 1] vertex j's (SPM_NONE: no splat). */
typedef struct {
    spm_path p;
    spm_u32 px[SPM_MAX_DEPTH + 1];
} spm_light_path;

/* Light subpaths [begin, end) of a pass (subpath i keyed as camera path i,
 * spm_ref_path_key) into paths and levels, as spm_ref_trace_range. */
void spm_ref_light_trace_range(const spm_geometry *g, const spm_material *mats,
                               const uint8_t *lvlk, int start_level, const spm_trace_params *p,
                               size_t begin, size_t end, spm_light_path *paths, uint8_t *levels);
/* Shades n light subpaths into their splats (ch floats each, as a camera
 * path's record) appended to out (film_splat.h). */
void spm_ref_shade_splats(const spm_mode_desc *m, const spm_shade_table *tabs,
                          const spm_spec_map *maps, int ch, const spm_trace_params *p,
                          size_t first, const spm_light_path *paths, const uint8_t *levels,
                          size_t n, spm_splats *out);
#endif
