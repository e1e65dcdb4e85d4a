/* Textured emission (kernels/light_area.clh emit_texture, its reference
 * host/cpu/refcpu_light_area.c) on both backends, on
 * scenes/emissive_texture.scene (a room lit by a panel whose emission is a
 * checkerboard texture): the kernel's trace against the reference's, path by
 * path (records, level bytes), and each mode's shade kernel against the
 * reference's shading of the same records. That the lookups happened: the
 * emissions the camera's rays see (the records' first emission) and the
 * light samples' (a vertex's light colour) are each several of the texture's
 * palette colours, never the material's own emission (its mean colour,
 * which only the light pick reads). That the texel is the right one is
 * tests/cli_emit_texture.sh's; that the light sample's and the ray's lookups
 * estimate one emission, test_strategies'. */
#include "cl_testlib.h"
#include "testutil.h"

#define SEED 11u
#define W 32
#define H 32
#define SPP 16
#define MAX_DIVERGENT_FRACTION 1e-3 /* as test_cl_trace */
#define SHADE_REL 1e-4              /* no spectral arithmetic of its own */

/* colour id (0xFFFF, as 16 bits of a record, or SPM_NONE: none) marked in
 * seen, counted in *distinct the first time */
static void mark(unsigned char *seen, spm_u32 id, int *distinct)
{
    if (id < 0xFFFFu && !seen[id])
        seen[id] = 1, (*distinct)++;
}

static void trace_compare(void *ctx, const cl_test_scene *s, spm_cl_renderer *r,
                          const spm_path *cp, const uint8_t *cl, size_t n)
{
    size_t diverged = 0, level_diff = 0, mean_seen = 0;
    spm_path *gp = spm_xcalloc(n, sizeof *gp);
    uint8_t *gl = spm_xcalloc(n, 1);
    unsigned char *seen_hit = spm_xcalloc(65536, 1), *seen_nee = spm_xcalloc(65536, 1);
    int hits = 0, nees = 0;
    spm_u32 mean = SPM_NONE;
    for (int m = 0; m < s->tables.nmaterials; m++)
        if (s->tables.materials[m].emit != SPM_NONE)
            mean = s->tables.materials[m].emit;
    spm_error err;
    (void)ctx;
    CHECK(spm_cl_trace(r, 0, SPP, gp, gl, &err) == 0, "spm_cl_trace: %s", err.msg);
    for (size_t i = 0; i < n; i++) {
        int d = cl_test_path_differs(&gp[i], &cp[i]);
        diverged += d;
        level_diff += !d && gl[i] != cl[i];
        mark(seen_hit, cp[i].h.first_emit, &hits);
        mean_seen += cp[i].h.first_emit == mean;
        for (spm_u32 j = 0; j < cp[i].h.nvert && j < SPM_MAX_DEPTH; j++) {
            mark(seen_nee, cp[i].v[j].ids >> 16, &nees);
            mean_seen += (cp[i].v[j].ids >> 16) == mean;
        }
    }
    printf("trace: %zu paths, %d emission colours seen, %d sampled, %zu the mean's; %zu diverged, "
           "%zu level bytes differ\n", n, hits, nees, mean_seen, diverged, level_diff);
    CHECK(mean != SPM_NONE, "the scene has an emitter");
    CHECK(hits >= 4 && nees >= 4, "too few texel colours: %d seen, %d sampled", hits, nees);
    CHECK(mean_seen == 0, "%zu emissions are the material's mean colour", mean_seen);
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu paths diverged", diverged);
    CHECK(level_diff == 0, "%zu level bytes differ", level_diff);
    free(seen_hit);
    free(seen_nee);
    free(gp);
    free(gl);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/emissive_texture.scene", SPM_SOURCE_DIR);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "scenes/emissive_texture.scene loads");
        TEST_END();
    }
    int failed = cl_test_modes(&s, SEED, SPP, SHADE_REL, "scene", trace_compare, NULL);
    CHECK(failed == 0, "%d modes shade the scene off the reference", failed);
    cl_test_scene_close(&s);
    TEST_END();
}
