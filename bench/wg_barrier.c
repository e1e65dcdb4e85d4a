/* The cost of a work-group barrier on an OpenCL device (docs/PERFORMANCE.md,
 * "Work-group traversal"): one kernel runs N iterations of a short dependent
 * chain that writes and reads the work-item's own local-memory slot; the
 * other does the same and meets barrier(CLK_LOCAL_MEM_FENCE) twice an
 * iteration, reading a neighbour's slot between them (as cooperating lanes
 * would); a third the same steps with half the barriers. Per work-group size, the
 * kernel time of each (OpenCL profiling, the fastest of R launches after a
 * warm-up) and the cost of one barrier (dense minus sparse, per barrier met).
 *
 * usage: wg_barrier [DEVICE [N [R]]]      (defaults 0, 2000, 5) */
#include <CL/cl.h>
#include <stdio.h>
#include <stdlib.h>

/* A: one step of the chain, written to the work-item's slot; R: the neighbour's slot read
 * into it. "dense" meets a barrier after every A and every R (2 an iteration), "sparse"
 * the same n steps with half the barriers (its second step reads the item's own slot,
 * which needs none); "plain" has no barrier and reads its own slot only. */
static const char *src =
    "#define A a = a * 0.999f + 1.0f; sh[l] = a;\n"
    "#define R(s) a += sh[s] * 1e-6f;\n"
    "#define B barrier(CLK_LOCAL_MEM_FENCE);\n"
    "__kernel void plain(__global float *out, int n)\n"
    "{\n"
    "    __local float sh[64];\n"
    "    uint l = get_local_id(0);\n"
    "    float a = (float)l;\n"
    "    for (int i = 0; i < n; i++) { A R(l) }\n"
    "    out[get_global_id(0)] = a;\n"
    "}\n"
    "__kernel void dense(__global float *out, int n)\n"
    "{\n"
    "    __local float sh[64];\n"
    "    uint l = get_local_id(0), w = get_local_size(0);\n"
    "    float a = (float)l;\n"
    "    for (int i = 0; i < n; i++) { A B R((l + 1) % w) B }\n"
    "    out[get_global_id(0)] = a;\n"
    "}\n"
    "__kernel void sparse(__global float *out, int n)\n"
    "{\n"
    "    __local float sh[64];\n"
    "    uint l = get_local_id(0), w = get_local_size(0);\n"
    "    float a = (float)l;\n"
    "    for (int i = 0; i < n / 2; i++) { A B R((l + 1) % w) B A R(l) }\n"
    "    out[get_global_id(0)] = a;\n"
    "}\n";

#define CHECK(e, what)                                                                   \
    do {                                                                                 \
        if ((e) != CL_SUCCESS) {                                                         \
            fprintf(stderr, "wg_barrier: %s failed (%d)\n", what, (int)(e));             \
            exit(1);                                                                     \
        }                                                                                \
    } while (0)

/* the fastest of r launches (after one warm-up), in seconds */
static double run(cl_command_queue q, cl_kernel k, size_t global, size_t local, int r)
{
    double best = 1e30;
    for (int i = 0; i <= r; i++) {
        cl_event ev;
        CHECK(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, &ev), "launch");
        CHECK(clWaitForEvents(1, &ev), "wait");
        cl_ulong t0, t1;
        clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof t0, &t0, NULL);
        clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof t1, &t1, NULL);
        clReleaseEvent(ev);
        double s = (double)(t1 - t0) * 1e-9;
        if (i > 0 && s < best)
            best = s;
    }
    return best;
}

int main(int argc, char **argv)
{
    int devno = argc > 1 ? atoi(argv[1]) : 0, n = argc > 2 ? atoi(argv[2]) : 2000;
    int r = argc > 3 ? atoi(argv[3]) : 5;
    cl_platform_id plat[8];
    cl_uint np = 0;
    CHECK(clGetPlatformIDs(8, plat, &np), "clGetPlatformIDs");
    cl_device_id devs[16];
    cl_uint nd = 0;
    CHECK(clGetDeviceIDs(plat[0], CL_DEVICE_TYPE_ALL, 16, devs, &nd), "clGetDeviceIDs");
    if (devno < 0 || (cl_uint)devno >= nd) {
        fprintf(stderr, "wg_barrier: no device %d (%u on the first platform)\n", devno, nd);
        return 2;
    }
    cl_device_id dev = devs[devno];
    char name[256];
    clGetDeviceInfo(dev, CL_DEVICE_NAME, sizeof name, name, NULL);
    cl_int e;
    cl_context ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &e);
    CHECK(e, "clCreateContext");
    cl_command_queue q = clCreateCommandQueue(ctx, dev, CL_QUEUE_PROFILING_ENABLE, &e);
    CHECK(e, "clCreateCommandQueue");
    cl_program p = clCreateProgramWithSource(ctx, 1, &src, NULL, &e);
    CHECK(e, "clCreateProgramWithSource");
    CHECK(clBuildProgram(p, 1, &dev, "", NULL, NULL), "clBuildProgram");
    size_t global = 16384;
    cl_mem out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, global * sizeof(float), NULL, &e);
    CHECK(e, "clCreateBuffer");
    const char *names[3] = {"plain", "dense", "sparse"};
    cl_kernel ks[3];
    for (int i = 0; i < 3; i++) {
        ks[i] = clCreateKernel(p, names[i], &e);
        CHECK(e, "clCreateKernel");
        CHECK(clSetKernelArg(ks[i], 0, sizeof out, &out), "arg 0");
        CHECK(clSetKernelArg(ks[i], 1, sizeof n, &n), "arg 1");
    }
    printf("%s: %zu work-items, %d steps each, fastest of %d launches\n", name, global, n, r);
    printf("%6s %10s %10s %10s %18s %18s\n", "group", "plain ms", "dense ms", "sparse ms",
           "ns/barrier/group", "ns/barrier/item");
    size_t sizes[] = {1, 4, 8, 16, 64};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        size_t w = sizes[i];
        double sp = run(q, ks[0], global, w, r), sd = run(q, ks[1], global, w, r);
        double ss = run(q, ks[2], global, w, r);
        /* dense meets n more barriers per work-group than sparse, the same arithmetic */
        double per_group = (sd - ss) / ((double)n * (double)(global / w)) * 1e9;
        printf("%6zu %10.3f %10.3f %10.3f %18.2f %18.3f\n", w, sp * 1e3, sd * 1e3, ss * 1e3,
               per_group, per_group / (double)w);
    }
    for (int i = 0; i < 3; i++)
        clReleaseKernel(ks[i]);
    clReleaseMemObject(out);
    clReleaseProgram(p);
    clReleaseCommandQueue(q);
    clReleaseContext(ctx);
    return 0;
}
