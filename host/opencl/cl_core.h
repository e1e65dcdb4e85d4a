/* OpenCL plumbing: device listing and selection by one index across all
 * platforms, context/queue creation, program builds from kernels/, and
 * error reporting by name and call site. Every function returns 0 on success
 * or non-zero with *err filled; nothing here exits. Thread-safe: each caller
 * owns its spm_cl_ctx, and the listing functions only read the platforms. */
#ifndef SPM_CL_CORE_H
#define SPM_CL_CORE_H
#include <stddef.h>
#include <stdint.h>
#ifdef __APPLE__
#include <OpenCL/cl.h>
#else
#include <CL/cl.h>
#endif
#include "util.h"

/* The error code's name, e.g. "CL_OUT_OF_RESOURCES" ("unknown OpenCL error" otherwise). */
const char *spm_cl_errname(cl_int code);

/* If code != CL_SUCCESS: fill err with "<what>: <CL name>" (what names the call site,
 * e.g. "clEnqueueNDRangeKernel(trace)") and return 1; else 0. */
int spm_cl_check(cl_int code, const char *what, spm_error *err);

typedef struct {
    int index;                /* as `specmip devices` numbers it */
    int platform_index;
    cl_platform_id platform;
    cl_device_id device;
    char name[256];
    char platform_name[256];
    char version[128];        /* CL_DEVICE_VERSION */
    cl_device_type type;
    cl_uint compute_units;
    cl_ulong global_mem;      /* bytes */
    cl_ulong max_alloc;       /* largest single buffer, bytes */
    cl_ulong local_mem;
    size_t max_work_group;
} spm_cl_device;

/* What a device is, from its CL_DEVICE_TYPE: a GPU or accelerator, a CPU, or
 * a simulator (one that claims to be a CPU and a GPU at once, as Oclgrind's
 * does). */
typedef enum { SPM_CL_GPU, SPM_CL_CPU, SPM_CL_SIMULATOR } spm_cl_kind;
spm_cl_kind spm_cl_device_kind(cl_device_type t);

/* All devices of all platforms, numbered platform by platform in a fixed
 * order: platforms with a GPU or accelerator first, then those with CPU
 * devices, then simulators; within each, by platform name (the ICD loader's
 * own order may follow the order its vendor files were read in); within a
 * platform, in its order. platform_index counts only the platforms that have
 * devices. *list is malloc'ed (free it); no platform at all is an error ("no
 * OpenCL platform"). */
int spm_cl_devices(spm_cl_device **list, int *n, spm_error *err);
/* Whether `--device all` takes device i of list: every GPU and accelerator,
 * and the CPU devices of the first platform that has any (two OpenCL
 * implementations of one CPU share its cores: the second adds no speed, and
 * a slower one holds the render back); a simulator only when every device
 * is one (as under the oclgrind wrapper). */
int spm_cl_device_in_all(const spm_cl_device *list, int n, int i);
/* One device by index; an unknown index is an error listing the available ones. */
int spm_cl_device_get(int index, spm_cl_device *out, spm_error *err);
/* "0: NAME (PLATFORM)" lines for an error message or listing. */
void spm_cl_device_list_text(const spm_cl_device *list, int n, char *buf, size_t bufsize);

typedef struct {
    spm_cl_device dev;
    cl_context ctx;
    cl_command_queue queue;   /* in-order, with profiling enabled */
} spm_cl_ctx;

int spm_cl_ctx_create(int device_index, spm_cl_ctx *c, spm_error *err);
void spm_cl_ctx_release(spm_cl_ctx *c);

/* Build a program from kernel files (paths relative to the data root, e.g.
 * "kernels/trace.cl", found via spm_data_path) with the options every build
 * uses (see cl_core.c) plus `defines` ("-DNAME=V ..."). On a build failure the
 * compiler log goes to stderr and err names the device and first log line. */
int spm_cl_build(spm_cl_ctx *c, const char *const *files, int nfiles, const char *defines,
                 cl_program *out, spm_error *err);

/* Seconds between an event's START and END (profiling); -1 when the device
 * gives no times (Rusticl gives none; also with SPECMIP_CL_NO_TIMES set). */
double spm_cl_event_seconds(cl_event e);

/* Kernels, buffers and launches for the programs outside the renderer (the
 * bench's ray replay and operation timings), so that no OpenCL call lives
 * outside opencl/. `what` names the kernel or buffer in the error. */
int spm_cl_kernel(cl_program p, const char *name, cl_kernel *out, spm_error *err);
int spm_cl_arg(cl_kernel k, cl_uint i, size_t size, const void *val, const char *what,
               spm_error *err);
/* size bytes (an empty buffer has 4: OpenCL refuses size 0), copied from host
 * unless it is NULL. */
int spm_cl_buffer(const spm_cl_ctx *c, cl_mem_flags flags, size_t size, const void *host,
                  const char *what, cl_mem *out, spm_error *err);
/* Blocking reads and writes of a buffer's first size bytes. */
int spm_cl_read(const spm_cl_ctx *c, cl_mem m, size_t size, void *dst, const char *what,
                spm_error *err);
int spm_cl_write(const spm_cl_ctx *c, cl_mem m, size_t size, const void *src, const char *what,
                 spm_error *err);
/* One launch of global work-items in groups of local (0: the implementation
 * picks), waited for; its kernel seconds in *s (spm_cl_event_seconds). */
int spm_cl_launch(const spm_cl_ctx *c, cl_kernel k, size_t global, size_t local, double *s,
                  const char *what, spm_error *err);
/* These take NULL (nothing made yet). */
void spm_cl_release_kernel(cl_kernel k);
void spm_cl_release_mem(cl_mem m);
void spm_cl_release_program(cl_program p);
#endif
