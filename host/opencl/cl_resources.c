/* Device memory footprint of a render (cl_resources.h). */
#include "cl_resources.h"
#include <stdio.h>
#include "cl_buffers.h"
#include "film_splat.h"
#include "modes.h"
#include "render_plan.h"
#include "materials.h"

static void add(spm_cl_footprint *f, size_t bytes, const char *what, int scene)
{
    f->total += bytes;
    if (bytes > f->largest) {
        f->largest = bytes;
        f->largest_what = what;
        f->largest_is_scene = scene;
    }
}

void spm_cl_footprint_of(const spm_geometry *g, const spm_tables *t, size_t npix,
                         size_t paths_per_pass, spm_cl_footprint *out)
{
    spm_cl_footprint_of_ch(g, t, npix, paths_per_pass, 3, out);
}

/* The batch buffers for n paths (or records) of vertex_bytes a vertex, the
 * scene's buffers and the colour tables. */
static void batch_and_scene(spm_cl_footprint *f, const spm_geometry *g, const spm_tables *t,
                            size_t n, size_t vertex_bytes, int pix_ch)
{
    f->batch_paths = n;
    /* the backend's buffers (cl_buffers.h) */
#define BATCH(field, what, per_path, flags, init) add(f, n * (per_path), what, 0);
    SPM_CL_BATCH_BUFFERS(BATCH)
    const uint8_t *lvlk = t->lvlk; /* the size is the same whichever level table */
#define SCENE(field, what, bytes, host) add(f, bytes, what, 1);
    SPM_CL_SCENE_BUFFERS(SCENE)
    (void)lvlk;
    /* shade tables: those of the mode with the largest */
    size_t tables = 0;
    for (int m = 0; m < SPM_MODE_COUNT; m++) {
        size_t b = spm_mode_footprint(&spm_modes[m], t);
        tables = b > tables ? b : tables;
    }
    add(f, tables, "colour tables", 1);
    if (pix_ch > 3) /* spectral bin maps: at most a few entries per bin and lane */
        add(f, (size_t)SPM_NUM_LEVELS * 4 * (SPM_TRUTH_BINS + SPM_MAX_SPIKES + 1) * sizeof(float),
            "spectral bin maps", 1);
}

void spm_cl_footprint_of_ch(const spm_geometry *g, const spm_tables *t, size_t npix,
                            size_t paths_per_pass, int pix_ch, spm_cl_footprint *out)
{
    spm_cl_footprint f = {0, "nothing", 0, 0, 0};
    size_t spp = npix ? paths_per_pass / npix : 0;
    /* a vertex's record for the scene's types (tables without materials: the plain one) */
    size_t vertex_bytes = t->materials ? spm_material_vertex_bytes(t->materials, t->nmaterials)
                                       : sizeof(spm_vertex);
    size_t n = spm_batch_room(npix, spp ? spp : 1,
                              spm_plan_batch_paths(SPM_CL_BATCH_PATHS, pix_ch, vertex_bytes));
    batch_and_scene(&f, g, t, n, vertex_bytes, pix_ch);
    *out = f;
}

/* The pass's fixed-point sums and image, per pixel and channel (both splatting
 * integrators). */
static void add_film(spm_cl_footprint *f, size_t npix, int pix_ch)
{
    size_t cells = npix * (size_t)pix_ch;
    add(f, cells * sizeof(int64_t), "splat sums", 0);
    add(f, cells * sizeof(float), "pass image", 0);
}

void spm_cl_footprint_of_bdpt(const spm_geometry *g, const spm_tables *t, size_t npix,
                              int pix_ch, spm_cl_footprint *out)
{
    /* cl_bdpt.c: the record room a chunk starts with, every vertex with its
     * words (-DSPM_BDPT), each record its pixel and value for the splats */
    spm_cl_footprint f = {0, "nothing", 0, 0, 0};
    size_t n = SPM_BDPT_CHUNK * SPM_BDPT_ROOM_PER_SAMPLE;
    batch_and_scene(&f, g, t, n, sizeof(spm_vertex) + sizeof(spm_vertex_ext), pix_ch);
    add(&f, n * sizeof(spm_u32), "splat pixels", 0);
    add(&f, n * (size_t)pix_ch * sizeof(float), "splat values", 0);
    add_film(&f, npix, pix_ch);
    *out = f;
}

void spm_cl_footprint_add_light(spm_cl_footprint *f, size_t npix, size_t paths_per_pass,
                                int pix_ch)
{
    /* cl_light.c reserve_light: a chunk's pixel words (a slab per vertex and
     * the light's own), its splat list at two splats a subpath, the 64-bit
     * sums and the pass image */
    size_t room = paths_per_pass < SPM_SPLAT_CHUNK ? paths_per_pass : SPM_SPLAT_CHUNK;
    add(f, room * (SPM_MAX_DEPTH + 1) * sizeof(spm_u32), "splat pixel words", 0);
    add(f, 2 * room * sizeof(spm_u32), "splat pixels", 0);
    add(f, 2 * room * (size_t)pix_ch * sizeof(float), "splat values", 0);
    add_film(f, npix, pix_ch);
}

/* "1.50 GB" or "128.0 MB": a batch's buffers are well under a gigabyte. */
static const char *size_str(size_t bytes, char buf[32])
{
    double mb = (double)bytes / (1024.0 * 1024.0);
    if (mb >= 1024.0)
        snprintf(buf, 32, "%.2f GB", mb / 1024.0);
    else
        snprintf(buf, 32, "%.1f MB", mb);
    return buf;
}

/* What to do about it: a scene buffer needs a smaller scene; a batch's
 * buffers are already the smallest the renderer cuts a pass into. */
static const char *advice(const spm_cl_footprint *f)
{
    return f->largest_is_scene ? "render a smaller scene or use a larger device"
                               : "use a device with more memory";
}

int spm_cl_footprint_check(const spm_cl_device *dev, const spm_cl_footprint *f, int width,
                           int height, size_t paths_per_pass, spm_error *err)
{
    char need[32], have[32];
    if (f->largest > dev->max_alloc) {
        spm_errorf(err,
                   "a %dx%d render needs %s in one device buffer (%s; %zu paths a pass in "
                   "batches of %zu); device '%s' allows %s per buffer: %s",
                   width, height, size_str(f->largest, need), f->largest_what, paths_per_pass,
                   f->batch_paths, dev->name, size_str((size_t)dev->max_alloc, have), advice(f));
        return 1;
    }
    if (f->total > dev->global_mem) {
        spm_errorf(err,
                   "a %dx%d render needs %s of device memory (%zu paths a pass in batches "
                   "of %zu); device '%s' has %s: %s",
                   width, height, size_str(f->total, need), paths_per_pass, f->batch_paths,
                   dev->name, size_str((size_t)dev->global_mem, have), advice(f));
        return 1;
    }
    return 0;
}
