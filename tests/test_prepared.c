/* The prepared scene that rank 0 sends the other ranks (prepared.h): what
 * comes out of a block is what went in, array for array, and renders the same
 * pass image bit for bit on the CPU reference; a damaged or foreign block is
 * an error, never a crash; and the no-scene-file test hook refuses a scene. */
#include <stdlib.h>
#include <string.h>
#include "backend_cpu.h"
#include "geometry.h"
#include "prepared.h"
#include "render_plan.h"
#include "scene.h"
#include "spectrum.h"
#include "tables.h"
#include "testutil.h"

static int same(const void *a, const void *b, size_t n)
{
    return (a == NULL) == (b == NULL) && (!a || memcmp(a, b, n) == 0);
}

/* One pass of 2 spp on the CPU reference; malloc'ed image or NULL. */
static float *cpu_pass(const spm_geometry *g, const spm_tables *t, int mode)
{
    spm_render_plan plan;
    spm_error err;
    if (spm_render_plan_init(&plan, g, t, mode, 7, &err)) {
        CHECK(0, "%s", err.msg);
        return NULL;
    }
    spm_backend *b = spm_backend_cpu_create(&plan, &err);
    CHECK(b != NULL, "%s", err.msg);
    float *img = calloc(plan.npix * 3, sizeof *img);
    spm_pass_stats st;
    memset(&st, 0, sizeof st);
    CHECK(b && b->pass(b, 0, 2, img, &st, &err) == 0, "%s", err.msg);
    if (b)
        b->destroy(b);
    spm_render_plan_free(&plan);
    return img;
}

static void round_trip(const char *rel)
{
    char path[1024];
    spm_scene sc;
    spm_geometry g, g2;
    spm_tables t, t2;
    spm_error err;
    spm_pretest_opts po;
    spm_pretest_defaults(&po);
    if (spm_scene_load(spm_data_path(rel, path, sizeof path), &sc, &err)) {
        CHECK(0, "%s", err.msg);
        return;
    }
    sc.width = 16; /* small: the CPU reference renders a pass below */
    sc.height = 12;
    CHECK(spm_geometry_build(&sc, &g, &err) == 0, "%s", err.msg);
    CHECK(spm_tables_build(&sc, &po, &t, &err) == 0, "%s", err.msg);
    spm_prepared_info in = {sc.width, sc.height, 40, SPM_MODE_ML, 5, SPM_INTEGRATOR_LIGHT}, out;
    size_t n;
    unsigned char *buf = spm_prepared_pack(&g, &t, &in, &n);
    CHECK(spm_prepared_unpack(buf, n, &g2, &t2, &out, &err) == 0, "%s: %s", rel, err.msg);
    CHECK(!memcmp(&in, &out, sizeof in), "%s: info", rel);
    CHECK(g2.ntris == g.ntris && g2.nnodes == g.nnodes && g2.nemitters == g.nemitters,
          "%s: counts", rel);
    CHECK(same(g.tris, g2.tris, (size_t)g.ntris * sizeof *g.tris), "%s: triangles", rel);
    CHECK(same(g.nodes, g2.nodes, (size_t)g.nnodes * sizeof *g.nodes), "%s: BVH", rel);
    CHECK(same(g.emitters, g2.emitters, (size_t)g.nemitters * sizeof *g.emitters),
          "%s: emitters", rel);
    CHECK(!memcmp(&g.cam, &g2.cam, sizeof g.cam), "%s: camera", rel);
    CHECK(same(g.light_pdf, g2.light_pdf, (size_t)g.ntris * sizeof *g.light_pdf),
          "%s: light pick probabilities", rel);
    CHECK(g2.nvn == g.nvn && same(g.vnormals, g2.vnormals, (size_t)g.nvn * 9 * sizeof *g.vnormals),
          "%s: vertex normals", rel);
    CHECK(g2.ndisp == g.ndisp && same(g.disp, g2.disp, (size_t)g.ndisp * SPM_TRUTH_BINS * sizeof *g.disp),
          "%s: index tables", rel);
    size_t nc = (size_t)t.ncolours;
    CHECK(t2.ncolours == t.ncolours && t2.nmaterials == t.nmaterials &&
              t2.nspikes == t.nspikes && t2.coarsest_level == t.coarsest_level &&
              t2.bg_up == t.bg_up && t2.bg_down == t.bg_down,
          "%s: table counts", rel);
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        CHECK(same(t.lvl[l], t2.lvl[l], nc * SPM_LEVEL_BINS(l) * sizeof(float)),
              "%s: level %d table", rel, l);
        CHECK(same(t.mlc_lvl[l], t2.mlc_lvl[l], nc * SPM_MLC_STRIDE(l) * sizeof(float)),
              "%s: mlc level %d table", rel, l);
    }
    CHECK(same(t.truth, t2.truth, nc * SPM_TRUTH_BINS * sizeof(float)), "%s: truth", rel);
    CHECK(same(t.rgb, t2.rgb, nc * 4 * sizeof(float)), "%s: rgb", rel);
    CHECK(same(t.lvlk, t2.lvlk, nc * SPM_PRETEST_KMAX), "%s: lvlk", rel);
    CHECK(same(t.mlc_lvlk, t2.mlc_lvlk, nc * SPM_PRETEST_KMAX), "%s: mlc_lvlk", rel);
    CHECK(same(t.pretest, t2.pretest, nc * sizeof *t.pretest), "%s: pretest", rel);
    CHECK(same(t.mlc_pretest, t2.mlc_pretest, nc * sizeof *t.mlc_pretest), "%s: mlc pretest", rel);
    CHECK(same(t.materials, t2.materials, (size_t)t.nmaterials * sizeof *t.materials),
          "%s: materials", rel);
    CHECK(!memcmp(t.cmf_lvl, t2.cmf_lvl, sizeof t.cmf_lvl) &&
              !memcmp(t.hero_edge, t2.hero_edge, sizeof t.hero_edge) &&
              !memcmp(t.hero_index, t2.hero_index, sizeof t.hero_index) &&
              t.hero_t0 == t2.hero_t0 && t.hero_dt == t2.hero_dt && t.hero_pdfk == t2.hero_pdfk &&
              !memcmp(t.spike_cmf, t2.spike_cmf, sizeof t.spike_cmf),
          "%s: weights", rel);
    /* what matters in the end: the same pass image, bit for bit */
    for (int mode = 0; mode < SPM_MODE_COUNT; mode++) {
        float *a = cpu_pass(&g, &t, mode), *b = cpu_pass(&g2, &t2, mode);
        CHECK(a && b && !memcmp(a, b, (size_t)sc.width * sc.height * 3 * sizeof(float)),
              "%s: mode %s: pass image differs", rel, spm_mode_name(mode));
        free(a);
        free(b);
    }
    spm_geometry_free(&g2);
    spm_tables_free(&t2);

    /* damaged blocks: every cut short, a byte of the header, a count */
    int cuts_caught = 1;
    for (size_t k = 0; k < n; k += 1 + n / 97)
        if (spm_prepared_unpack(buf, k, &g2, &t2, &out, &err) == 0) {
            cuts_caught = 0;
            spm_geometry_free(&g2);
            spm_tables_free(&t2);
        }
    CHECK(cuts_caught, "%s: a block cut short was taken", rel);
    buf[0] ^= 1;
    CHECK(spm_prepared_unpack(buf, n, &g2, &t2, &out, &err) != 0 &&
              strstr(err.msg, "another build"),
          "%s: a foreign block was taken (%s)", rel, err.msg);
    buf[0] ^= 1;
    unsigned char *more = malloc(n + 1);
    memcpy(more, buf, n);
    more[n] = 0;
    CHECK(spm_prepared_unpack(more, n + 1, &g2, &t2, &out, &err) != 0 &&
              strstr(err.msg, "damaged"),
          "%s: a block with a trailing byte was taken", rel);
    free(more);
    free(buf);
    spm_geometry_free(&g);
    spm_tables_free(&t);
    spm_scene_free(&sc);
}

int main(void)
{
    round_trip("scenes/cornell.scene");
    round_trip("scenes/cornell_spiky.scene"); /* spike lanes: the mlc tables */
    round_trip("scenes/multilight.scene");
    round_trip("scenes/prism.scene"); /* a dispersive glass: its index table */

    /* the test hook: a process that refuses scene files cannot load one */
    char path[1024];
    spm_scene sc;
    spm_error err;
    spm_input_files_refused = "rank 1";
    CHECK(spm_scene_load(spm_data_path("scenes/cornell.scene", path, sizeof path), &sc, &err) != 0,
          "a refused scene file was read");
    spm_scene_free(&sc);
    spm_input_files_refused = NULL;
    CHECK(spm_scene_load(path, &sc, &err) == 0, "%s", err.msg);
    spm_scene_free(&sc);
    TEST_END();
}
