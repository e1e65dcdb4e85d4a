/* The OpenCL backend cuts a pass into batches of whole pixels: the pass
 * image, the statistics, the trace records and the shaded XYZ are the same
 * bit for bit whatever the batch size (every mode, two scenes), and the
 * per-batch buffers hold one batch, not the pass. The batch sizes are chosen
 * so the last batch is partial (1200 pixels in batches of 33 or 7) and one
 * is smaller than a pixel's samples (one pixel a batch). */
#include "test_cl_batch.h"

#define W 40
#define H 30
#define SPP 3u
#define FIRST 3u /* a pass other than the first: sample keys start at 3 */
#define SEED 9u

static spm_cl_renderer *create(const cl_test_scene *s, int mode)
{
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s->geom, &s->tables, mode, SEED, &r, &err)) {
        CHECK(0, "spm_cl_create(mode %d): %s", mode, err.msg);
        return NULL;
    }
    return r;
}

static int pass(spm_cl_renderer *r, size_t batch_paths, float *img, spm_pass_stats *st)
{
    spm_error err;
    memset(st, 0, sizeof *st);
    spm_cl_set_batch_paths(r, batch_paths);
    int rc = spm_cl_pass(r, FIRST, SPP, img, st, &err);
    CHECK(rc == 0, "spm_cl_pass (batches of %zu paths): %s", batch_paths, err.msg);
    return rc;
}

/* Batches of 100 paths (33 pixels) first, so the buffers are sized for them,
 * then the whole pass as one batch (the default size exceeds it). */
static void pass_images(const cl_test_scene *s, const char *scene, int mode)
{
    size_t npix = (size_t)W * H, nf = npix * 3;
    float *cut = spm_xcalloc(nf, sizeof *cut), *whole = spm_xcalloc(nf, sizeof *whole);
    spm_pass_stats st_cut, st_whole;
    spm_cl_renderer *r = create(s, mode);
    char what[128];
    snprintf(what, sizeof what, "%s, mode %d", scene ? scene : "default scene", mode);
    if (r && !pass(r, 100, cut, &st_cut)) {
        CHECK(spm_cl_batch_capacity(r) == 100, "%s: buffers for %zu paths, not one batch", what,
              spm_cl_batch_capacity(r));
        if (!pass(r, 0, whole, &st_whole)) {
            CHECK(memcmp(cut, whole, nf * sizeof *cut) == 0, "%s: the pass image depends on the batches", what);
            batch_check_same_stats(&st_cut, &st_whole, what);
            CHECK(st_whole.paths == npix * SPP, "%s: %llu paths", what,
                  (unsigned long long)st_whole.paths);
            if (scene && mode == SPM_MODE_ML) /* the case bucket() sorts */
                CHECK(batch_levels_used(&st_whole) > 1, "%s: one level only", what);
        }
    }
    spm_cl_destroy(r);
    free(cut);
    free(whole);
}

/* A batch smaller than one pixel's samples still holds that pixel. */
static void one_pixel_batches(const cl_test_scene *s)
{
    size_t nf = (size_t)W * H * 3;
    float *a = spm_xcalloc(nf, sizeof *a), *b = spm_xcalloc(nf, sizeof *b);
    spm_pass_stats sa, sb;
    spm_cl_renderer *r = create(s, SPM_MODE_REF);
    if (r && !pass(r, 1, a, &sa) && !pass(r, 0, b, &sb)) {
        CHECK(memcmp(a, b, nf * sizeof *a) == 0, "one-pixel batches change the image");
        batch_check_same_stats(&sa, &sb, "one-pixel batches");
    }
    spm_cl_destroy(r);
    free(a);
    free(b);
}

/* The test hooks batch too: records traced in batches of 7 pixels are the
 * pass's records (each path keyed by its own pixel), and hero, whose
 * wavelengths are keyed by pixel and sample, shades them alike. */
static void hooks(const cl_test_scene *s)
{
    size_t n = (size_t)W * H * SPP;
    spm_path *pa = spm_xcalloc(n, sizeof *pa), *pb = spm_xcalloc(n, sizeof *pb);
    uint8_t *la = spm_xcalloc(n, 1), *lb = spm_xcalloc(n, 1);
    float *xa = spm_xcalloc(n * 3, sizeof *xa), *xb = spm_xcalloc(n * 3, sizeof *xb);
    spm_error err;
    spm_cl_renderer *r = create(s, SPM_MODE_HERO);
    if (r) {
        spm_cl_set_batch_paths(r, 7 * SPP);
        int rc = spm_cl_trace(r, FIRST, SPP, pa, la, &err) ||
                 spm_cl_shade(r, FIRST, SPP, pa, la, xa, &err);
        CHECK(rc == 0, "hooks in batches: %s", err.msg);
        spm_cl_set_batch_paths(r, 0);
        rc = rc || spm_cl_trace(r, FIRST, SPP, pb, lb, &err) ||
             spm_cl_shade(r, FIRST, SPP, pb, lb, xb, &err);
        CHECK(rc == 0, "hooks in one batch: %s", err.msg);
        size_t diff = 0;
        for (size_t i = 0; !rc && i < n; i++)
            diff += cl_test_path_hash(&pa[i]) != cl_test_path_hash(&pb[i]) || la[i] != lb[i];
        CHECK(!rc && diff == 0, "%zu of %zu records depend on the batches", diff, n);
        CHECK(!rc && memcmp(xa, xb, n * 3 * sizeof *xa) == 0, "hero XYZ depends on the batches");
    }
    spm_cl_destroy(r);
    free(pa);
    free(pb);
    free(la);
    free(lb);
    free(xa);
    free(xb);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    for (size_t k = 0; k < sizeof batch_scenes / sizeof *batch_scenes; k++) {
        cl_test_scene s;
        if (batch_scene_open(&s, batch_scenes[k], W, H)) {
            CHECK(0, "scene %zu", k);
            continue;
        }
        for (size_t m = 0; m < sizeof batch_modes / sizeof *batch_modes; m++)
            pass_images(&s, batch_scenes[k], batch_modes[m]);
        if (!batch_scenes[k]) {
            one_pixel_batches(&s);
            hooks(&s);
        }
        cl_test_scene_close(&s);
    }
    TEST_END();
}
