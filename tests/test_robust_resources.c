/* The device memory check (cl_resources.h) against made-up devices: an
 * image whose path records exceed the largest buffer is refused naming the
 * image, the buffer and the device; one within every buffer limit but over
 * the global memory is refused too; a usual image fits a usual device. */
#include "cl_resources.h"
#include "testutil.h"
#include <string.h>

static spm_cl_device device(double alloc_gb, double global_gb)
{
    spm_cl_device d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "test device");
    d.max_alloc = (cl_ulong)(alloc_gb * 1073741824.0);
    d.global_mem = (cl_ulong)(global_gb * 1073741824.0);
    return d;
}

int main(void)
{
    spm_geometry g;
    spm_tables t;
    memset(&g, 0, sizeof g);
    memset(&t, 0, sizeof t);
    g.ntris = 100000; /* a large scene: 100k triangles, 2 BVH nodes each */
    g.nnodes = 200000;
    g.nemitters = 100;
    t.ncolours = 300;
    t.nmaterials = 300;
    spm_cl_footprint f;
    spm_error err;
    spm_cl_device pocl = device(2.0, 4.379); /* this machine's PoCL device */

    /* 1920x1080, one sample a pass: 2.07M paths, each a vertex slab of
     * SPM_MAX_DEPTH vertices (~1 GB together) */
    size_t npix = 1920 * 1080;
    spm_cl_footprint_of(&g, &t, npix, npix, &f);
    CHECK(strcmp(f.largest_what, "path records") == 0, "largest is %s", f.largest_what);
    CHECK(f.largest == npix * SPM_MAX_DEPTH * sizeof(spm_vertex), "records %zu", f.largest);
    /* everything else (per path a header, a level byte, two indices, XYZ;
     * the pass image; the scene) is counted on top */
    size_t per_path_rest = sizeof(spm_dev_head) + 1 + 2 * sizeof(spm_u32) + 3 * sizeof(float);
    CHECK(f.total >= f.largest + npix * per_path_rest + npix * 12, "total %zu", f.total);
    CHECK(spm_cl_footprint_check(&pocl, &f, 1920, 1080, npix, &err) == 0, "%s", err.msg);

    /* 4096x4096: 8 GB of vertex slabs in one buffer */
    npix = 4096 * 4096;
    spm_cl_footprint_of(&g, &t, npix, npix, &f);
    CHECK(spm_cl_footprint_check(&pocl, &f, 4096, 4096, npix, &err) != 0, "4096^2 refused");
    CHECK(strstr(err.msg, "4096x4096") && strstr(err.msg, "path records") &&
              strstr(err.msg, "test device") && strstr(err.msg, "per buffer"),
          "%s", err.msg);
    printf("%s\n", err.msg);

    /* every buffer within a generous per-buffer limit, the sum over the memory */
    npix = 1920 * 1080;
    spm_cl_footprint_of(&g, &t, npix, npix, &f);
    spm_cl_device small = device(2.0, (double)f.total / 1073741824.0 * 0.99);
    CHECK(spm_cl_footprint_check(&small, &f, 1920, 1080, npix, &err) != 0, "total refused");
    CHECK(strstr(err.msg, "device memory") != NULL, "%s", err.msg);
    printf("%s\n", err.msg);
    /* ... and exactly the total fits */
    small.global_mem = f.total;
    CHECK(spm_cl_footprint_check(&small, &f, 1920, 1080, npix, &err) == 0, "total fits");
    TEST_END();
}
