/* The device memory check (cl_resources.h) against made-up devices. A pass is
 * rendered in batches, so the per-pass buffers do not grow with the image:
 * a 4096x4096 image needs what a 1920x1080 one needs and fits this
 * machine's device. What is still refused, naming the render, the buffer and
 * the device: a batch's records over a small device's largest buffer, a
 * scene over it, and a sum over the global memory. Also the batch sizing. */
#include "cl_resources.h"
#include "film_splat.h"
#include "render_plan.h"
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

static void batch_sizing(void)
{
    const size_t B = 100;
    CHECK(spm_batch_pixels(1000, 3, B) == 33, "33 pixels of 3 paths in 100");
    CHECK(spm_batch_pixels(10, 3, B) == 10, "a small pass is one batch");
    CHECK(spm_batch_pixels(1000, 500, B) == 1, "a pixel is never split");
    /* a cut pass keeps room for a full batch (a later pass of 2 spp takes 100) */
    CHECK(spm_batch_room(1000, 3, B) == 100, "room %zu", spm_batch_room(1000, 3, B));
    CHECK(spm_batch_pixels(1000, 2, B) * 2 <= spm_batch_room(1000, 3, B), "2 spp fits");
    CHECK(spm_batch_room(10, 3, B) == 30, "uncut pass: its own size");
    CHECK(spm_batch_room(1000, 500, B) == 500, "one pixel of 500 samples");
}

int main(void)
{
    batch_sizing();
    spm_geometry g;
    spm_tables t;
    memset(&g, 0, sizeof g);
    memset(&t, 0, sizeof t);
    g.ntris = 100000; /* a large scene: 100k triangles, a 4-wide node per 3 */
    g.nwide = 33000;
    g.nemitters = 100;
    t.ncolours = 300;
    t.nmaterials = 300;
    spm_cl_footprint f, f4k;
    spm_error err;
    spm_cl_device pocl = device(2.0, 4.379); /* this machine's PoCL device */

    /* 1920x1080, one sample a pass: 2.07M paths in batches of
     * SPM_CL_BATCH_PATHS, each path a vertex slab of SPM_MAX_DEPTH vertices */
    size_t npix = 1920 * 1080;
    spm_cl_footprint_of(&g, &t, npix, npix, &f);
    CHECK(f.batch_paths == SPM_CL_BATCH_PATHS, "batch %zu", f.batch_paths);
    CHECK(strcmp(f.largest_what, "path records") == 0, "largest is %s", f.largest_what);
    CHECK(f.largest == SPM_CL_BATCH_PATHS * SPM_MAX_DEPTH * sizeof(spm_vertex), "records %zu",
          f.largest);
    /* everything else (per path a header, a level byte, two indices, XYZ, a
     * batch-image entry; the scene) is counted on top */
    size_t per_path_rest = sizeof(spm_dev_head) + 1 + 2 * sizeof(spm_u32) + 6 * sizeof(float);
    size_t scene = g.ntris * sizeof(spm_tri) + g.nwide * sizeof(spm_bvh4_node);
    CHECK(f.total >= f.largest + f.batch_paths * per_path_rest + scene, "total %zu", f.total);
    CHECK(spm_cl_footprint_check(&pocl, &f, 1920, 1080, npix, &err) == 0, "%s", err.msg);

    /* 4096x4096 (8 GB of records in one pass, refused before batching): the same footprint */
    spm_cl_footprint_of(&g, &t, (size_t)4096 * 4096, (size_t)4096 * 4096, &f4k);
    CHECK(f4k.total == f.total && f4k.largest == f.largest, "4096^2: %zu bytes", f4k.total);
    CHECK(spm_cl_footprint_check(&pocl, &f4k, 4096, 4096, (size_t)4096 * 4096, &err) == 0,
          "4096^2 refused: %s", err.msg);

    /* spectral records of 403 floats (400 bins): batches shrink so that the
     * per-path buffers, records and batch image (2 x 403 floats a path) among
     * them, take no more than with XYZ alone */
    spm_cl_footprint fs, fx;
    spm_cl_footprint_of_ch(&g, &t, npix, npix, 403, &fs);
    CHECK(fs.batch_paths < f.batch_paths, "spectral batch %zu", fs.batch_paths);
    CHECK(fs.total <= f.total, "spectral total %zu over the XYZ one %zu", fs.total, f.total);
    /* the records counted at their size: the same batch with XYZ alone (a
     * 1-sample pass of that many pixels) needs 2 x 400 floats a path less */
    spm_cl_footprint_of(&g, &t, fs.batch_paths, fs.batch_paths, &fx);
    CHECK(fx.batch_paths == fs.batch_paths &&
              fs.total - fx.total >= fs.batch_paths * 2 * 400 * sizeof(float),
          "spectral records: %zu bytes more than XYZ's %zu in batches of %zu", fs.total - fx.total,
          fx.total, fs.batch_paths);

    /* a scene whose types record more per vertex (a conductor: spm_vertex_ext
     * words): its spectral batches shrink by its own records' size, so they
     * too take no more than its XYZ ones */
    spm_material metal = {0};
    metal.type = SPM_MAT_CONDUCTOR;
    t.materials = &metal;
    t.nmaterials = 1;
    spm_cl_footprint fm, fms;
    spm_cl_footprint_of(&g, &t, npix, npix, &fm);
    spm_cl_footprint_of_ch(&g, &t, npix, npix, 403, &fms);
    CHECK(fm.largest == SPM_CL_BATCH_PATHS * SPM_MAX_DEPTH * (sizeof(spm_vertex) +
                                                              sizeof(spm_vertex_ext)),
          "conductor records %zu", fm.largest);
    CHECK(fms.total <= fm.total, "conductor spectral total %zu over the XYZ one %zu", fms.total,
          fm.total);
    CHECK(fms.batch_paths > fs.batch_paths, "conductor spectral batch %zu, plain %zu",
          fms.batch_paths, fs.batch_paths);
    t.materials = NULL;
    t.nmaterials = 300;

    /* the light integrator's buffers on top (host/opencl/cl_light.c): a
     * chunk's pixel words and splat list, per pixel and channel the 64-bit
     * sums and the pass image; a device that holds the path tracer's render
     * but not them refuses the light tracer's */
    spm_cl_footprint fl = f, fls = fs;
    spm_cl_footprint_add_light(&fl, npix, npix, 3);
    size_t light = SPM_SPLAT_CHUNK * (SPM_MAX_DEPTH + 1) * sizeof(spm_u32) +
                   2 * SPM_SPLAT_CHUNK * (sizeof(spm_u32) + 3 * sizeof(float)) +
                   npix * 3 * (sizeof(int64_t) + sizeof(float));
    CHECK(fl.total == f.total + light, "light: %zu bytes, the path tracer's %zu + %zu", fl.total,
          f.total, light);
    spm_cl_device mid = device(2.0, (double)(f.total + light / 2) / 1073741824.0);
    CHECK(spm_cl_footprint_check(&mid, &f, 1920, 1080, npix, &err) == 0, "path: %s", err.msg);
    CHECK(spm_cl_footprint_check(&mid, &fl, 1920, 1080, npix, &err) != 0, "light not refused");
    /* 1 nm spectral (403 channels) at 1920x1080: 6.7 GB of sums, over one buffer's 2 GB */
    spm_cl_footprint_add_light(&fls, npix, npix, 403);
    CHECK(spm_cl_footprint_check(&pocl, &fls, 1920, 1080, npix, &err) != 0 &&
              strstr(err.msg, "splat sums"),
          "spectral light: %s", err.msg);
    printf("%s\n", err.msg);

    /* the bidirectional integrator's (host/opencl/cl_bdpt.c), in place of the
     * path tracer's batches: its starting record room, every vertex with its
     * words, each record a splat pixel and value, then the sums and the pass
     * image; a device that holds the path tracer's render but not the record
     * room refuses bdpt, naming it */
    spm_cl_footprint fb;
    spm_cl_footprint_of_bdpt(&g, &t, npix, 3, &fb);
    size_t room = SPM_BDPT_CHUNK * SPM_BDPT_ROOM_PER_SAMPLE;
    size_t records = room * SPM_MAX_DEPTH * (sizeof(spm_vertex) + sizeof(spm_vertex_ext));
    size_t per_path = SPM_MAX_DEPTH * sizeof(spm_vertex) + per_path_rest;
    size_t slot = records / room + per_path_rest + sizeof(spm_u32) + 3 * sizeof(float);
    CHECK(fb.batch_paths == 16384 && fb.largest >= records, "bdpt: %zu records, largest %zu",
          fb.batch_paths, fb.largest);
    CHECK(fb.total == f.total - f.batch_paths * per_path + room * slot +
                          npix * 3 * (sizeof(int64_t) + sizeof(float)),
          "bdpt: %zu bytes", fb.total);
    spm_cl_device narrow = device((double)records / 1073741824.0 * 0.99, 4.0);
    spm_cl_footprint f256;
    spm_cl_footprint_of(&g, &t, 128 * 128, 128 * 128, &f256);
    CHECK(spm_cl_footprint_check(&narrow, &f256, 128, 128, 128 * 128, &err) == 0, "path: %s",
          err.msg);
    spm_cl_footprint_of_bdpt(&g, &t, 128 * 128, 3, &fb);
    CHECK(spm_cl_footprint_check(&narrow, &fb, 128, 128, 128 * 128, &err) != 0 &&
              strstr(err.msg, "path records") && strstr(err.msg, "more memory"),
          "bdpt on a narrow device: %s", err.msg);
    printf("%s\n", err.msg);

    /* a pass smaller than a batch is one batch of its own size */
    spm_cl_footprint_of(&g, &t, 256 * 256, 256 * 256, &f4k);
    CHECK(f4k.batch_paths == 256 * 256, "256^2 batch %zu", f4k.batch_paths);

    /* a device whose largest buffer (64 MB) is below one batch's records */
    spm_cl_device tiny = device(1.0 / 16, 4.0);
    CHECK(spm_cl_footprint_check(&tiny, &f, 1920, 1080, npix, &err) != 0, "batch refused");
    CHECK(strstr(err.msg, "1920x1080") && strstr(err.msg, "path records") &&
              strstr(err.msg, "test device") && strstr(err.msg, "per buffer") &&
              strstr(err.msg, "more memory"),
          "%s", err.msg);
    printf("%s\n", err.msg);

    /* a scene whose triangles alone exceed the device's largest buffer */
    g.ntris = 2 * (size_t)(pocl.max_alloc / sizeof(spm_tri));
    spm_cl_footprint_of(&g, &t, npix, npix, &f4k);
    CHECK(spm_cl_footprint_check(&pocl, &f4k, 1920, 1080, npix, &err) != 0, "scene refused");
    CHECK(strstr(err.msg, "triangles") && strstr(err.msg, "smaller scene"), "%s", err.msg);
    printf("%s\n", err.msg);
    g.ntris = 100000;

    /* every buffer within a generous per-buffer limit, the sum over the memory */
    spm_cl_device small = device(2.0, (double)f.total / 1073741824.0 * 0.99);
    CHECK(spm_cl_footprint_check(&small, &f, 1920, 1080, npix, &err) != 0, "total refused");
    CHECK(strstr(err.msg, "device memory") != NULL, "%s", err.msg);
    printf("%s\n", err.msg);
    /* ... and exactly the total fits */
    small.global_mem = f.total;
    CHECK(spm_cl_footprint_check(&small, &f, 1920, 1080, npix, &err) == 0, "total fits");
    TEST_END();
}
