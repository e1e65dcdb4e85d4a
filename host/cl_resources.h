/* Device memory a render needs, checked against the device's limits before
 * the OpenCL backend is created, so that an image or scene too large for the
 * device is refused with a clear sentence before any buffer or kernel exists.
 * The sizes follow host/render_cl.c's buffers: per pass (record headers,
 * vertex slabs, level bytes, identity and bucket indices, per-path XYZ for
 * every path; the pass image), and
 * per scene (triangles, BVH, emitters, materials, level table, colour tables). */
#ifndef SPM_CL_RESOURCES_H
#define SPM_CL_RESOURCES_H
#include <stddef.h>
#include "clhost.h"
#include "geometry.h"
#include "tables.h"

typedef struct {
    size_t largest;          /* the largest single buffer, bytes */
    const char *largest_what; /* its name, as render_cl.c calls it */
    size_t total;            /* all buffers together, bytes */
} spm_cl_footprint;

/* The footprint of rendering npix pixels with paths_per_pass paths a pass.
 * Colour tables are counted as if every shade kernel were built (an upper
 * bound: they are a few hundred KB even for large scenes). */
void spm_cl_footprint_of(const spm_geometry *g, const spm_tables *t, size_t npix,
                         size_t paths_per_pass, spm_cl_footprint *out);

/* 0 if the footprint fits the device (each buffer within CL_DEVICE_MAX_MEM_ALLOC_SIZE,
 * the sum within CL_DEVICE_GLOBAL_MEM_SIZE), else fills err with what does not
 * fit, by how much, and what to do; width x height name the image. */
int spm_cl_footprint_check(const spm_cl_device *dev, const spm_cl_footprint *f, int width,
                           int height, size_t paths_per_pass, spm_error *err);
#endif
