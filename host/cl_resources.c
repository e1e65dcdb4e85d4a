/* Device memory footprint of a render (cl_resources.h). */
#include "cl_resources.h"
#include <stdio.h>

static void add(spm_cl_footprint *f, size_t bytes, const char *what)
{
    f->total += bytes;
    if (bytes > f->largest) {
        f->largest = bytes;
        f->largest_what = what;
    }
}

void spm_cl_footprint_of(const spm_geometry *g, const spm_tables *t, size_t npix,
                         size_t paths_per_pass, spm_cl_footprint *out)
{
    spm_cl_footprint f = {0, "nothing", 0};
    size_t n = paths_per_pass, nc = (size_t)t->ncolours;
    /* per pass (render_cl.c reserve() and the pass image): headers and
     * vertex slabs with room for every depth */
    add(&f, n * sizeof(spm_dev_head), "path record headers");
    add(&f, n * SPM_MAX_DEPTH * sizeof(spm_vertex), "path records");
    add(&f, n, "level bytes");
    add(&f, n * sizeof(spm_u32), "identity indices");
    add(&f, n * sizeof(spm_u32), "bucket indices");
    add(&f, n * 3 * sizeof(float), "path XYZ");
    add(&f, npix * 3 * sizeof(float), "pass image");
    /* per scene (render_cl.c upload_scene()) */
    add(&f, (size_t)g->ntris * sizeof(spm_tri), "triangles");
    add(&f, (size_t)g->nnodes * sizeof(spm_bvh_node), "BVH");
    add(&f, (size_t)g->nemitters * sizeof(spm_u32), "emitters");
    add(&f, (size_t)t->nmaterials * sizeof(spm_material), "materials");
    add(&f, nc * SPM_PRETEST_KMAX, "level table");
    /* colour tables and weights of every kernel: levels with their spike lanes
     * (whole vectors), truth, rgb, hero */
    size_t rows = nc + 3, floats = SPM_TRUTH_BINS + 4 + SPM_L0_BINS + 4 * (SPM_TRUTH_BINS + 1);
    for (int l = 0; l < SPM_NUM_LEVELS; l++)
        floats += (size_t)SPM_LEVEL_BINS(l) + SPM_MAX_SPIKES + (16 >> l);
    add(&f, rows * floats * sizeof(float), "colour tables");
    *out = f;
}

static double gb(size_t bytes)
{
    return (double)bytes / (1024.0 * 1024.0 * 1024.0);
}

int spm_cl_footprint_check(const spm_cl_device *dev, const spm_cl_footprint *f, int width,
                           int height, size_t paths_per_pass, spm_error *err)
{
    if (f->largest > dev->max_alloc) {
        spm_errorf(err,
                   "a %dx%d image needs %.2f GB in one device buffer (%s for %zu paths a pass); "
                   "device '%s' allows %.2f GB per buffer: render a smaller image",
                   width, height, gb(f->largest), f->largest_what, paths_per_pass, dev->name,
                   gb((size_t)dev->max_alloc));
        return 1;
    }
    if (f->total > dev->global_mem) {
        spm_errorf(err,
                   "a %dx%d image needs %.2f GB of device memory (%zu paths a pass); "
                   "device '%s' has %.2f GB: render a smaller image",
                   width, height, gb(f->total), paths_per_pass, dev->name,
                   gb((size_t)dev->global_mem));
        return 1;
    }
    return 0;
}
