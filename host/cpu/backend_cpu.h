/* The CPU reference backend and its batching. A pass is
 * traced and shaded in batches of whole pixels, like the OpenCL backend
 * (render_plan.h), so its memory stays bounded whatever the image size. */
#ifndef SPM_BACKEND_CPU_H
#define SPM_BACKEND_CPU_H
#include <stddef.h>
#include "backend.h"

/* Paths in one batch, at most: 2^16 records (36 MB with their XYZ), as many
 * as a pass at the default image size; the CPU has no launch cost to
 * amortise, so larger batches would only cost memory. */
#define SPM_CPU_BATCH_PATHS ((size_t)1 << 16)

/* The reference on the plan (render_plan.h), which must outlive it. */
spm_backend *spm_backend_cpu_create(const spm_render_plan *plan, spm_error *err);
/* As a kind of backend (backend.h): one, no devices. */
extern const spm_backend_kind spm_backend_kind_cpu;

/* Test hooks on a backend from spm_backend_cpu_create: batches of at most
 * `paths` paths from the next pass on (0: the default); the paths the
 * per-batch buffers have room for now. */
void spm_backend_cpu_set_batch_paths(spm_backend *b, size_t paths);
size_t spm_backend_cpu_batch_capacity(const spm_backend *b);
#endif
