/* Device memory a render needs, checked against the device's limits before
 * the OpenCL backend is created, so that a render too large for the device is
 * refused with a clear sentence before any buffer or kernel exists.
 *
 * A pass is traced and shaded in batches of whole pixels (a pixel's samples
 * stay together), so the per-pass buffers hold one batch, whatever the image
 * size. The buffers are the backend's own lists (cl_buffers.h): per batch
 * (record headers, vertex slabs, level bytes, identity and bucket indices,
 * per-path XYZ, the batch's pixel sums) and per scene (triangles, BVH,
 * emitters, materials, level table), plus the mode's shade tables. The pass
 * image lives on the host. */
#ifndef SPM_CL_RESOURCES_H
#define SPM_CL_RESOURCES_H
#include <stddef.h>
#include "cl_core.h"
#include "geometry.h"
#include "tables.h"

/* Paths in one batch, at most (a batch is never less than one pixel). 2^18
 * paths make a vertex-slab buffer of 128 MiB, the smallest
 * CL_DEVICE_MAX_MEM_ALLOC_SIZE OpenCL allows a full-profile device, so every
 * such device takes it; and they are 4x the ~64K paths of a pass at the
 * default image size (render_run.h), which therefore stays one batch. The
 * same on every device: a multi-device render shares out the same batches. */
#define SPM_CL_BATCH_PATHS ((size_t)1 << 18)

typedef struct {
    size_t largest;          /* the largest single buffer, bytes */
    const char *largest_what; /* its name, as cl_buffers.h lists it */
    int largest_is_scene;    /* it is a scene buffer (else a per-batch one) */
    size_t total;            /* all buffers together, bytes */
    size_t batch_paths;      /* paths in one batch */
} spm_cl_footprint;

/* The footprint of rendering npix pixels with paths_per_pass paths a pass
 * (npix times the samples per pixel of a pass), in batches of at most
 * SPM_CL_BATCH_PATHS paths. Colour tables are counted as for the mode whose
 * tables are largest (modes.h spm_mode_footprint; an upper bound: a few
 * hundred KB even for large scenes). */
void spm_cl_footprint_of(const spm_geometry *g, const spm_tables *t, size_t npix,
                         size_t paths_per_pass, spm_cl_footprint *out);

/* The same for path records of pix_ch floats (render_plan.h: XYZ and the
 * spectral bins), whose batches are cut smaller to match
 * (spm_plan_batch_paths). */
void spm_cl_footprint_of_ch(const spm_geometry *g, const spm_tables *t, size_t npix,
                            size_t paths_per_pass, int pix_ch, spm_cl_footprint *out);

/* What the light integrator adds (--integrator light, host/opencl/cl_light.c):
 * a chunk's pixel words and splat list (as first reserved: two splats a
 * subpath; it grows when a chunk has more) and, per pixel and channel, the
 * 64-bit fixed-point sums and the pass image. */
void spm_cl_footprint_add_light(spm_cl_footprint *f, size_t npix, size_t paths_per_pass,
                                int pix_ch);
/* The bidirectional integrator (--integrator bdpt, host/opencl/cl_bdpt.c)
 * cuts a pass into chunks of SPM_BDPT_CHUNK samples and starts with room for
 * SPM_BDPT_ROOM_PER_SAMPLE connected paths' records a sample (a chunk that
 * finds more grows it). */
#define SPM_BDPT_CHUNK ((size_t)2048)
#define SPM_BDPT_ROOM_PER_SAMPLE 8

/* Its footprint, in place of spm_cl_footprint_of_ch's: the batch buffers
 * for the record room it starts with (each vertex with its words), a
 * record's splat pixel and value, the scene's buffers and tables, and per
 * pixel and channel the 64-bit sums and the pass image. */
void spm_cl_footprint_of_bdpt(const spm_geometry *g, const spm_tables *t, size_t npix,
                              int pix_ch, spm_cl_footprint *out);

/* 0 if the footprint fits the device (each buffer within CL_DEVICE_MAX_MEM_ALLOC_SIZE,
 * the sum within CL_DEVICE_GLOBAL_MEM_SIZE), else fills err with what does not
 * fit, by how much, and what to do; width x height name the image. */
int spm_cl_footprint_check(const spm_cl_device *dev, const spm_cl_footprint *f, int width,
                           int height, size_t paths_per_pass, spm_error *err);
#endif
