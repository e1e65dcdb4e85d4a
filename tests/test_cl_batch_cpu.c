/* The CPU reference backend cuts a pass into batches of whole pixels too:
 * the pass image and statistics are the same bit for bit whatever the batch
 * size (every mode, two scenes), and its buffers hold one batch (hero, keyed
 * by a path's index in the pass, shades whole passes: backend_cpu.c). */
#include "backend_cpu.h"
#include "test_cl_batch.h"

#define W 40
#define H 30
#define SPP 3u
#define FIRST 3u

static int pass(spm_backend *b, size_t batch_paths, float *img, spm_pass_stats *st)
{
    spm_error err;
    memset(st, 0, sizeof *st);
    spm_backend_cpu_set_batch_paths(b, batch_paths);
    int rc = b->pass(b, FIRST, SPP, img, st, &err);
    CHECK(rc == 0, "cpu pass (batches of %zu paths): %s", batch_paths, err.msg);
    return rc;
}

static void pass_images(const cl_test_scene *s, const char *scene, int mode)
{
    size_t npix = (size_t)W * H, nf = npix * 3;
    float *cut = spm_xcalloc(nf, sizeof *cut), *whole = spm_xcalloc(nf, sizeof *whole);
    spm_pass_stats st_cut, st_whole;
    spm_render_plan plan;
    spm_error err;
    if (spm_render_plan_init(&plan, &s->geom, &s->tables, mode, 9u, &err)) {
        CHECK(0, "plan: %s", err.msg);
        return;
    }
    spm_backend *b = spm_backend_cpu_create(&plan, &err);
    char what[128];
    snprintf(what, sizeof what, "%s, mode %d", scene ? scene : "default scene", mode);
    /* 100 paths: 33 pixels a batch, the last of 12 */
    if (!pass(b, 100, cut, &st_cut)) {
        size_t room = 100;
        CHECK(spm_backend_cpu_batch_capacity(b) == room, "%s: buffers for %zu paths, not %zu",
              what, spm_backend_cpu_batch_capacity(b), room);
        if (!pass(b, 0, whole, &st_whole)) {
            CHECK(memcmp(cut, whole, nf * sizeof *cut) == 0, "%s: the pass image depends on the batches", what);
            batch_check_same_stats(&st_cut, &st_whole, what);
            CHECK(st_whole.paths == npix * SPP, "%s: %llu paths", what,
                  (unsigned long long)st_whole.paths);
        }
    }
    b->destroy(b);
    spm_render_plan_free(&plan);
    free(cut);
    free(whole);
}

int main(void)
{
    for (size_t k = 0; k < sizeof batch_scenes / sizeof *batch_scenes; k++) {
        cl_test_scene s;
        if (batch_scene_open(&s, batch_scenes[k], W, H)) {
            CHECK(0, "scene %zu", k);
            continue;
        }
        for (size_t m = 0; m < sizeof batch_modes / sizeof *batch_modes; m++)
            pass_images(&s, batch_scenes[k], batch_modes[m]);
        cl_test_scene_close(&s);
    }
    TEST_END();
}
