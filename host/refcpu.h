/* The CPU reference: MiniLight's transport and every mode's shading in plain
 * scalar C. Shares structs, constants and the RNG with the kernels through
 * include/, never their arithmetic. */
#ifndef SPM_REFCPU_H
#define SPM_REFCPU_H
#include <stddef.h>
#include <stdint.h>
#include "geometry.h"
#include "tables.h"

/* Trace one pass: npix * p->spp_per_pass paths; path i belongs to pixel
 * i / spp_per_pass and sample p->first_sample + i % spp_per_pass. Writes the
 * records and each path's level byte (level feeler on `lvlk`, see tables.h). */
void spm_ref_trace(const spm_geometry *g, const spm_material *mats, const uint8_t *lvlk,
                   const spm_trace_params *p, spm_path *paths, uint8_t *levels);

/* Shade n records in `mode` to XYZ (3 floats per path). ml/mlc use each path's
 * level byte; hero needs the pass parameters for its wavelength offsets. */
void spm_ref_shade(const spm_tables *t, int mode, const spm_trace_params *p, const spm_path *paths,
                   const uint8_t *levels, size_t n, float *xyz);
#endif
