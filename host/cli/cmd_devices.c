/* `specmip devices`: the OpenCL devices, numbered as --device takes them. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cl_core.h"
#include "commands.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: specmip devices [--help]\n\n"
               "Lists every OpenCL device of every platform with the index that\n"
               "'specmip render --device ID' takes. IDs count across platforms, which\n"
               "come in a fixed order: those with a GPU or accelerator first, then\n"
               "those with CPU devices, then simulators, each by name. '--device all'\n"
               "takes every device except the CPU devices of a second platform\n"
               "(another OpenCL implementation of the same CPU) and simulators (unless\n"
               "there is nothing else); a list such as '--device 0,1' takes any.\n");
}

static const char *type_name(cl_device_type t)
{
    if (spm_cl_device_kind(t) == SPM_CL_SIMULATOR)
        return "simulator";
    if (t & CL_DEVICE_TYPE_GPU)
        return "GPU";
    if (t & CL_DEVICE_TYPE_CPU)
        return "CPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR)
        return "accelerator";
    return "other";
}

int spm_cmd_devices(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return SPM_EXIT_OK;
        }
        fprintf(stderr, "specmip devices: unknown option '%s'\n", argv[i]);
        usage(stderr);
        return SPM_EXIT_INPUT;
    }
    spm_cl_device *list;
    int n;
    spm_error err;
    if (spm_cl_devices(&list, &n, &err)) {
        fprintf(stderr, "specmip devices: %s\n", err.msg);
        return SPM_EXIT_RUNTIME;
    }
    int last_platform = -1;
    for (int i = 0; i < n; i++) {
        const spm_cl_device *d = &list[i];
        if (d->platform_index != last_platform) {
            printf("platform %d: %s\n", d->platform_index, d->platform_name);
            last_platform = d->platform_index;
        }
        printf("  device %d: %s\n", d->index, d->name);
        printf("    type %s, %u compute units, %s\n", type_name(d->type), d->compute_units,
               d->version);
        printf("    global memory %.0f MB, largest buffer %.0f MB, local memory %.0f KB\n",
               (double)d->global_mem / 1048576.0, (double)d->max_alloc / 1048576.0,
               (double)d->local_mem / 1024.0);
        if (!spm_cl_device_in_all(list, n, i))
            printf("    not in --device all (%s)\n",
                   spm_cl_device_kind(d->type) == SPM_CL_SIMULATOR
                       ? "a simulator"
                       : "a CPU device of a second platform");
    }
    free(list);
    return SPM_EXIT_OK;
}
