/* What `--device all` takes from a device list (no OpenCL calls: the lists
 * are made up, numbered as spm_cl_devices numbers them): GPUs and
 * accelerators of every platform, the CPU devices of the first platform that
 * has any, a simulator only when there is nothing else; and how a device type
 * is classified. */
#include <string.h>
#include "cl_core.h"
#include "testutil.h"

static spm_cl_device dev(int index, int platform, cl_device_type type)
{
    spm_cl_device d;
    memset(&d, 0, sizeof d);
    d.index = index;
    d.platform_index = platform;
    d.type = type;
    return d;
}

static void takes(const char *what, const spm_cl_device *list, int n, const int *want)
{
    for (int i = 0; i < n; i++)
        CHECK(spm_cl_device_in_all(list, n, i) == want[i], "%s: device %d: %d, want %d", what,
              i, spm_cl_device_in_all(list, n, i), want[i]);
}

int main(void)
{
    const cl_device_type cpu = CL_DEVICE_TYPE_CPU, gpu = CL_DEVICE_TYPE_GPU,
                         acc = CL_DEVICE_TYPE_ACCELERATOR,
                         everything = CL_DEVICE_TYPE_CPU | CL_DEVICE_TYPE_GPU |
                                      CL_DEVICE_TYPE_ACCELERATOR | CL_DEVICE_TYPE_DEFAULT;
    CHECK(spm_cl_device_kind(cpu) == SPM_CL_CPU, "CPU");
    CHECK(spm_cl_device_kind(cpu | CL_DEVICE_TYPE_DEFAULT) == SPM_CL_CPU, "default CPU");
    CHECK(spm_cl_device_kind(gpu) == SPM_CL_GPU, "GPU");
    CHECK(spm_cl_device_kind(acc) == SPM_CL_GPU, "accelerator");
    CHECK(spm_cl_device_kind(everything) == SPM_CL_SIMULATOR, "all types at once (Oclgrind)");

    /* PoCL with two devices, then Rusticl's llvmpipe */
    spm_cl_device a[] = {dev(0, 0, cpu), dev(1, 0, cpu), dev(2, 1, cpu)};
    takes("two CPU platforms", a, 3, (const int[]){1, 1, 0});

    /* a GPU platform, then PoCL, then another CPU platform with a GPU too */
    spm_cl_device b[] = {dev(0, 0, gpu), dev(1, 0, gpu), dev(2, 1, cpu), dev(3, 2, gpu),
                         dev(4, 2, cpu)};
    takes("GPUs everywhere, CPUs from one platform", b, 5, (const int[]){1, 1, 1, 1, 0});

    /* a simulator listed before a CPU platform does not make that one "second" */
    spm_cl_device c[] = {dev(0, 0, everything), dev(1, 1, cpu), dev(2, 2, cpu)};
    takes("simulator, then two CPU platforms", c, 3, (const int[]){0, 1, 0});

    /* a lone device is always taken, a simulator too (run under oclgrind) */
    spm_cl_device d[] = {dev(0, 0, cpu)};
    takes("one CPU", d, 1, (const int[]){1});
    spm_cl_device e[] = {dev(0, 0, everything)};
    takes("one simulator", e, 1, (const int[]){1});
    CHECK(!spm_cl_device_in_all(a, 3, 3) && !spm_cl_device_in_all(a, 3, -1), "out of range");
    TEST_END();
}
