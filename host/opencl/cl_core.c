/* OpenCL plumbing: listing, contexts, program builds, error names. */
#include "cl_core.h"
#include "cl_contract.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "spectrum.h"

const char *spm_cl_errname(cl_int code)
{
    switch (code) {
#define E(x) \
    case x:  \
        return #x;
        E(CL_SUCCESS) E(CL_DEVICE_NOT_FOUND) E(CL_DEVICE_NOT_AVAILABLE)
        E(CL_COMPILER_NOT_AVAILABLE) E(CL_MEM_OBJECT_ALLOCATION_FAILURE) E(CL_OUT_OF_RESOURCES)
        E(CL_OUT_OF_HOST_MEMORY) E(CL_PROFILING_INFO_NOT_AVAILABLE) E(CL_MEM_COPY_OVERLAP)
        E(CL_IMAGE_FORMAT_MISMATCH) E(CL_IMAGE_FORMAT_NOT_SUPPORTED) E(CL_BUILD_PROGRAM_FAILURE)
        E(CL_MAP_FAILURE) E(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        E(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST) E(CL_COMPILE_PROGRAM_FAILURE)
        E(CL_LINKER_NOT_AVAILABLE) E(CL_LINK_PROGRAM_FAILURE) E(CL_DEVICE_PARTITION_FAILED)
        E(CL_KERNEL_ARG_INFO_NOT_AVAILABLE) E(CL_INVALID_VALUE) E(CL_INVALID_DEVICE_TYPE)
        E(CL_INVALID_PLATFORM) E(CL_INVALID_DEVICE) E(CL_INVALID_CONTEXT)
        E(CL_INVALID_QUEUE_PROPERTIES) E(CL_INVALID_COMMAND_QUEUE) E(CL_INVALID_HOST_PTR)
        E(CL_INVALID_MEM_OBJECT) E(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR) E(CL_INVALID_IMAGE_SIZE)
        E(CL_INVALID_SAMPLER) E(CL_INVALID_BINARY) E(CL_INVALID_BUILD_OPTIONS)
        E(CL_INVALID_PROGRAM) E(CL_INVALID_PROGRAM_EXECUTABLE) E(CL_INVALID_KERNEL_NAME)
        E(CL_INVALID_KERNEL_DEFINITION) E(CL_INVALID_KERNEL) E(CL_INVALID_ARG_INDEX)
        E(CL_INVALID_ARG_VALUE) E(CL_INVALID_ARG_SIZE) E(CL_INVALID_KERNEL_ARGS)
        E(CL_INVALID_WORK_DIMENSION) E(CL_INVALID_WORK_GROUP_SIZE) E(CL_INVALID_WORK_ITEM_SIZE)
        E(CL_INVALID_GLOBAL_OFFSET) E(CL_INVALID_EVENT_WAIT_LIST) E(CL_INVALID_EVENT)
        E(CL_INVALID_OPERATION) E(CL_INVALID_GL_OBJECT) E(CL_INVALID_BUFFER_SIZE)
        E(CL_INVALID_MIP_LEVEL) E(CL_INVALID_GLOBAL_WORK_SIZE) E(CL_INVALID_PROPERTY)
        E(CL_INVALID_IMAGE_DESCRIPTOR) E(CL_INVALID_COMPILER_OPTIONS) E(CL_INVALID_LINKER_OPTIONS)
        E(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef E
    case -1001:
        return "CL_PLATFORM_NOT_FOUND_KHR";
    default:
        return "unknown OpenCL error";
    }
}

int spm_cl_check(cl_int code, const char *what, spm_error *err)
{
    if (code == CL_SUCCESS)
        return 0;
    if (!strcmp(spm_cl_errname(code), "unknown OpenCL error"))
        spm_errorf(err, "%s: OpenCL error %d", what, (int)code);
    else
        spm_errorf(err, "%s: %s", what, spm_cl_errname(code));
    return 1;
}

static void info_str(cl_device_id d, cl_device_info what, char *buf, size_t n)
{
    buf[0] = 0;
    if (clGetDeviceInfo(d, what, n, buf, NULL) != CL_SUCCESS)
        snprintf(buf, n, "?");
    buf[n - 1] = 0;
}

static void fill_device(spm_cl_device *o, int index, int pi, cl_platform_id p, cl_device_id d)
{
    memset(o, 0, sizeof *o);
    o->index = index;
    o->platform_index = pi;
    o->platform = p;
    o->device = d;
    info_str(d, CL_DEVICE_NAME, o->name, sizeof o->name);
    info_str(d, CL_DEVICE_VERSION, o->version, sizeof o->version);
    if (clGetPlatformInfo(p, CL_PLATFORM_NAME, sizeof o->platform_name, o->platform_name, NULL))
        snprintf(o->platform_name, sizeof o->platform_name, "?");
    o->platform_name[sizeof o->platform_name - 1] = 0;
    clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof o->type, &o->type, NULL);
    clGetDeviceInfo(d, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof o->compute_units, &o->compute_units, NULL);
    clGetDeviceInfo(d, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof o->global_mem, &o->global_mem, NULL);
    clGetDeviceInfo(d, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof o->max_alloc, &o->max_alloc, NULL);
    clGetDeviceInfo(d, CL_DEVICE_LOCAL_MEM_SIZE, sizeof o->local_mem, &o->local_mem, NULL);
    clGetDeviceInfo(d, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof o->max_work_group,
                    &o->max_work_group, NULL);
}

spm_cl_kind spm_cl_device_kind(cl_device_type t)
{
    int gpu = (t & (CL_DEVICE_TYPE_GPU | CL_DEVICE_TYPE_ACCELERATOR)) != 0;
    int cpu = (t & CL_DEVICE_TYPE_CPU) != 0;
    return gpu && cpu ? SPM_CL_SIMULATOR : gpu ? SPM_CL_GPU : SPM_CL_CPU;
}

typedef struct {
    cl_platform_id id;
    cl_device_id *devs;
    cl_uint ndev;
    spm_cl_kind kind; /* its devices' first kind */
    cl_uint order;    /* the loader's */
    char name[256];
} platform_entry;

/* By kind (GPU/accelerator, CPU, simulator), then by name, then the loader's
 * order (qsort is not stable, so the loader index is the last key). */
static int platform_cmp(const void *pa, const void *pb)
{
    const platform_entry *a = pa, *b = pb;
    if (a->kind != b->kind)
        return a->kind < b->kind ? -1 : 1;
    int c = strcmp(a->name, b->name);
    if (c)
        return c;
    return a->order < b->order ? -1 : a->order > b->order;
}

int spm_cl_devices(spm_cl_device **list, int *n, spm_error *err)
{
    *list = NULL;
    *n = 0;
    cl_uint np = 0;
    cl_int rc = clGetPlatformIDs(0, NULL, &np);
    if (rc == -1001 /* CL_PLATFORM_NOT_FOUND_KHR: the ICD loader found no driver */ || np == 0) {
        spm_errorf(err, "no OpenCL platform found (is an OpenCL driver such as PoCL installed?)");
        return 1;
    }
    if (spm_cl_check(rc, "clGetPlatformIDs", err))
        return 1;
    cl_platform_id *plats = spm_xcalloc(np, sizeof *plats);
    platform_entry *pe = spm_xcalloc(np, sizeof *pe);
    int npe = 0, ok = !spm_cl_check(clGetPlatformIDs(np, plats, NULL), "clGetPlatformIDs", err);
    for (cl_uint p = 0; ok && p < np; p++) {
        cl_uint nd = 0;
        rc = clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, 0, NULL, &nd);
        if (rc == CL_DEVICE_NOT_FOUND || nd == 0)
            continue;
        if (spm_cl_check(rc, "clGetDeviceIDs", err)) {
            ok = 0;
            break;
        }
        platform_entry *e = &pe[npe];
        e->id = plats[p];
        e->order = p;
        e->devs = spm_xcalloc(nd, sizeof *e->devs);
        npe++;
        rc = clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, nd, e->devs, &e->ndev);
        if (spm_cl_check(rc, "clGetDeviceIDs", err)) {
            ok = 0;
            break;
        }
        if (e->ndev > nd)
            e->ndev = nd;
        e->kind = SPM_CL_SIMULATOR;
        for (cl_uint d = 0; d < e->ndev; d++) {
            cl_device_type t = 0;
            clGetDeviceInfo(e->devs[d], CL_DEVICE_TYPE, sizeof t, &t, NULL);
            if (spm_cl_device_kind(t) < e->kind)
                e->kind = spm_cl_device_kind(t);
        }
        if (clGetPlatformInfo(e->id, CL_PLATFORM_NAME, sizeof e->name, e->name, NULL))
            snprintf(e->name, sizeof e->name, "?");
        e->name[sizeof e->name - 1] = 0;
    }
    if (ok)
        qsort(pe, (size_t)npe, sizeof *pe, platform_cmp);
    int cap = 0;
    for (int p = 0; ok && p < npe; p++)
        for (cl_uint d = 0; d < pe[p].ndev; d++) {
            if (*n == cap) {
                cap = cap ? 2 * cap : 8;
                *list = spm_xrealloc(*list, (size_t)cap * sizeof **list);
            }
            fill_device(&(*list)[*n], *n, p, pe[p].id, pe[p].devs[d]);
            (*n)++;
        }
    for (int p = 0; p < npe; p++)
        free(pe[p].devs);
    free(pe);
    free(plats);
    if (ok && *n == 0) {
        spm_errorf(err, "no OpenCL device found on %u platform(s)", (unsigned)np);
        ok = 0;
    }
    if (!ok) {
        free(*list);
        *list = NULL;
        *n = 0;
        return 1;
    }
    return 0;
}

int spm_cl_device_in_all(const spm_cl_device *list, int n, int i)
{
    if (i < 0 || i >= n)
        return 0;
    spm_cl_kind k = spm_cl_device_kind(list[i].type);
    if (k == SPM_CL_GPU)
        return 1;
    if (k == SPM_CL_SIMULATOR) { /* only when nothing else is there (run under oclgrind) */
        for (int j = 0; j < n; j++)
            if (spm_cl_device_kind(list[j].type) != SPM_CL_SIMULATOR)
                return 0;
        return 1;
    }
    for (int j = 0; j < i; j++)
        if (spm_cl_device_kind(list[j].type) == SPM_CL_CPU &&
            list[j].platform_index != list[i].platform_index)
            return 0;
    return 1;
}

void spm_cl_device_list_text(const spm_cl_device *list, int n, char *buf, size_t bufsize)
{
    size_t used = 0;
    buf[0] = 0;
    for (int i = 0; i < n && used + 1 < bufsize; i++) {
        int w = snprintf(buf + used, bufsize - used, "%s%d: %s (%s)", i ? "; " : "",
                         list[i].index, list[i].name, list[i].platform_name);
        if (w < 0)
            break;
        used += (size_t)w;
    }
}

int spm_cl_device_get(int index, spm_cl_device *out, spm_error *err)
{
    spm_cl_device *list;
    int n;
    if (spm_cl_devices(&list, &n, err))
        return 1;
    if (index < 0 || index >= n) {
        char avail[768];
        spm_cl_device_list_text(list, n, avail, sizeof avail);
        spm_errorf(err, "no OpenCL device %d; available: %s", index, avail);
        free(list);
        return 1;
    }
    *out = list[index];
    free(list);
    return 0;
}

int spm_cl_ctx_create(int device_index, spm_cl_ctx *c, spm_error *err)
{
    memset(c, 0, sizeof *c);
    if (spm_cl_device_get(device_index, &c->dev, err))
        return 1;
    cl_int rc;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)c->dev.platform,
                                     0};
    c->ctx = clCreateContext(props, 1, &c->dev.device, NULL, NULL, &rc);
    if (spm_cl_check(rc, "clCreateContext", err))
        return 1;
    c->queue = clCreateCommandQueue(c->ctx, c->dev.device, CL_QUEUE_PROFILING_ENABLE, &rc);
    if (spm_cl_check(rc, "clCreateCommandQueue", err)) {
        clReleaseContext(c->ctx);
        c->ctx = NULL;
        return 1;
    }
    return 0;
}

void spm_cl_ctx_release(spm_cl_ctx *c)
{
    if (c->queue)
        clReleaseCommandQueue(c->queue);
    if (c->ctx)
        clReleaseContext(c->ctx);
    c->queue = NULL;
    c->ctx = NULL;
}

static char *read_file(const char *path, spm_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        spm_errorf(err, "%s: cannot open kernel source (set SPECMIP_DATA to the source tree?)",
                   path);
        return NULL;
    }
    size_t cap = 1 << 14, n = 0;
    char *s = spm_xmalloc(cap);
    size_t got;
    while ((got = fread(s + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (n + 1 == cap)
            s = spm_xrealloc(s, cap *= 2);
    }
    fclose(f);
    s[n] = 0;
    return s;
}

/* Build options, and why:
 *  -cl-std=CL1.2: the one language version every device here must accept.
 *  -I include -I kernels: spm_shared.h/spm_rng.h are the host/kernel contract;
 *   kernels/ holds the generic shade body included once per vector width.
 *  -cl-fp32-correctly-rounded-divide-sqrt (when the device offers it): the
 *   trace stage's divides and square roots then round like the CPU reference's,
 *   so fewer paths flip at triangle edges.
 *  No -cl-fast-relaxed-math / -cl-finite-math-only: they would let the compiler
 *   drop NaN/Inf handling and reorder sums (non-reproducible images). */
int spm_cl_build(spm_cl_ctx *c, const char *const *files, int nfiles, const char *defines,
                 cl_program *out, spm_error *err)
{
    *out = NULL;
    if (spm_cl_contract_check(err))
        return 1;
    char **src = spm_xcalloc((size_t)nfiles, sizeof *src);
    int ok = 1;
    char path[4096];
    for (int i = 0; i < nfiles && ok; i++) {
        src[i] = read_file(spm_data_path(files[i], path, sizeof path), err);
        ok = src[i] != NULL;
    }
    cl_int rc = CL_SUCCESS;
    cl_program prog = NULL;
    if (ok) {
        prog = clCreateProgramWithSource(c->ctx, (cl_uint)nfiles, (const char **)src, NULL, &rc);
        ok = !spm_cl_check(rc, "clCreateProgramWithSource", err);
    }
    for (int i = 0; i < nfiles; i++)
        free(src[i]);
    free(src);
    if (!ok)
        return 1;

    cl_device_fp_config fp = 0;
    clGetDeviceInfo(c->dev.device, CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, NULL);
    char inc[4096], ker[4096];
    spm_data_path("include", inc, sizeof inc);
    spm_data_path("kernels", ker, sizeof ker);
    size_t olen = strlen(inc) + strlen(ker) + strlen(defines ? defines : "") + 256;
    char *opts = spm_xmalloc(olen);
    snprintf(opts, olen, "-cl-std=CL1.2 -I %s -I %s%s %s", inc, ker,
             (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) ? " -cl-fp32-correctly-rounded-divide-sqrt"
                                                        : "",
             defines ? defines : "");
    rc = clBuildProgram(prog, 1, &c->dev.device, opts, NULL, NULL);
    free(opts);
    if (rc == CL_BUILD_PROGRAM_FAILURE || rc == CL_INVALID_BUILD_OPTIONS) {
        size_t n = 0;
        clGetProgramBuildInfo(prog, c->dev.device, CL_PROGRAM_BUILD_LOG, 0, NULL, &n);
        char *log = spm_xcalloc(n + 1, 1);
        clGetProgramBuildInfo(prog, c->dev.device, CL_PROGRAM_BUILD_LOG, n, log, NULL);
        fprintf(stderr, "specmip: kernel build log (%s):\n%s\n", c->dev.name, log);
        char first[256] = "";
        sscanf(log, "%255[^\n]", first);
        spm_errorf(err, "clBuildProgram(%s): %s on '%s' (log above): %s", files[0],
                   spm_cl_errname(rc), c->dev.name, first);
        free(log);
        clReleaseProgram(prog);
        return 1;
    }
    if (spm_cl_check(rc, "clBuildProgram", err)) {
        clReleaseProgram(prog);
        return 1;
    }
    *out = prog;
    return 0;
}

double spm_cl_event_seconds(cl_event e)
{
    /* SPECMIP_CL_NO_TIMES: behave as a device without profiling (Rusticl) */
    if (getenv("SPECMIP_CL_NO_TIMES"))
        return -1.0;
    /* Mesa 22.3's Rusticl answers CL_SUCCESS with the placeholders 0, 1, 2, 3
     * for QUEUED .. END; no real clock reads within a microsecond of its zero */
    cl_ulong a = 0, b = 0;
    if (clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof a, &a, NULL) ||
        clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof b, &b, NULL) || a < 1000)
        return -1.0;
    return b > a ? (double)(b - a) * 1e-9 : 0.0;
}

/* spm_cl_check with "<call>(<what>)" as the call site */
static int check_at(cl_int code, const char *call, const char *what, spm_error *err)
{
    char site[192];
    snprintf(site, sizeof site, "%s(%.150s)", call, what);
    return spm_cl_check(code, site, err);
}

int spm_cl_kernel(cl_program p, const char *name, cl_kernel *out, spm_error *err)
{
    cl_int e;
    *out = clCreateKernel(p, name, &e);
    return check_at(e, "clCreateKernel", name, err);
}

int spm_cl_arg(cl_kernel k, cl_uint i, size_t size, const void *val, const char *what,
               spm_error *err)
{
    return check_at(clSetKernelArg(k, i, size, val), "clSetKernelArg", what, err);
}

int spm_cl_buffer(const spm_cl_ctx *c, cl_mem_flags flags, size_t size, const void *host,
                  const char *what, cl_mem *out, spm_error *err)
{
    cl_int e;
    *out = clCreateBuffer(c->ctx, flags | (host ? CL_MEM_COPY_HOST_PTR : 0), size ? size : 4,
                          (void *)host, &e);
    if (e != CL_SUCCESS)
        *out = NULL;
    return check_at(e, "clCreateBuffer", what, err);
}

int spm_cl_read(const spm_cl_ctx *c, cl_mem m, size_t size, void *dst, const char *what,
                spm_error *err)
{
    return check_at(clEnqueueReadBuffer(c->queue, m, CL_TRUE, 0, size, dst, 0, NULL, NULL),
                    "clEnqueueReadBuffer", what, err);
}

int spm_cl_write(const spm_cl_ctx *c, cl_mem m, size_t size, const void *src, const char *what,
                 spm_error *err)
{
    return check_at(clEnqueueWriteBuffer(c->queue, m, CL_TRUE, 0, size, src, 0, NULL, NULL),
                    "clEnqueueWriteBuffer", what, err);
}

int spm_cl_launch(const spm_cl_ctx *c, cl_kernel k, size_t global, size_t local, double *s,
                  const char *what, spm_error *err)
{
    cl_event ev;
    if (check_at(clEnqueueNDRangeKernel(c->queue, k, 1, NULL, &global, local ? &local : NULL, 0,
                                        NULL, &ev),
                 "clEnqueueNDRangeKernel", what, err))
        return 1;
    cl_int rc = clWaitForEvents(1, &ev);
    *s = spm_cl_event_seconds(ev);
    clReleaseEvent(ev);
    return check_at(rc, "clWaitForEvents", what, err);
}

void spm_cl_release_kernel(cl_kernel k)
{
    if (k)
        clReleaseKernel(k);
}

void spm_cl_release_mem(cl_mem m)
{
    if (m)
        clReleaseMemObject(m);
}

void spm_cl_release_program(cl_program p)
{
    if (p)
        clReleaseProgram(p);
}
