/* The light tree's walk in the kernels (kernels/light_tree.clh) against the
 * CPU reference's (host/cpu/refcpu_light_tree.c), path by path: a floor
 * (a rough metal) under a grid of small lamps of mixed power and facing, a point, a spot
 * and a distant light (beside the tree), a wall that shades part of it; the
 * selection and the MIS weight at a BSDF-sampled lamp both through the
 * tree. The tree must change the paths (against the reference by power),
 * and the kernel must follow the reference's. */
#include "cl_testlib.h"
#include "light_tree.h"
#include "testutil.h"

#define SEED 5u
#define W 24
#define H 24
#define SPP 16
/* as test_cl_trace: a path may diverge only where a few ulps move a ray
 * across an edge or a walk's draw across a node's split */
#define MAX_DIVERGENT_FRACTION 1e-3

static int write_scene(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "image %d %d\ncamera position 0 3 -6 direction 0 -0.5 1 fov 60\n"
               "spectrum equal equal\nspectrum warm blackbody 2700\n"
               "material floor reflect equal 0.5\nmaterial rough conductor equal 0.2 equal 3 alpha 0.3\n"
               "material dim emit warm 1\nmaterial bright emit equal 30\n"
               "quad rough -10 0 -10  -10 0 10  10 0 10  10 0 -10\n"
               "quad floor -3 0 2  -3 1.5 2  0 1.5 2  0 0 2\n", W, H);
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 10; j++) {
            float x = -4.0f + 0.7f * (float)i, z = -2.0f + 0.7f * (float)j, y = 1.0f + 0.1f * (float)((i * 7 + j * 3) % 9);
            const char *m = (i * 5 + j * 11) % 13 ? "dim" : "bright";
            if ((i + j) % 3) /* facing down */
                fprintf(f, "quad %s %g %g %g  %g %g %g  %g %g %g  %g %g %g\n", m, x, y, z,
                        x + 0.2f, y, z, x + 0.2f, y, z + 0.2f, x, y, z + 0.2f);
            else /* standing, facing -z */
                fprintf(f, "quad %s %g %g %g  %g %g %g  %g %g %g  %g %g %g\n", m, x, y, z, x,
                        y + 0.2f, z, x + 0.2f, y + 0.2f, z, x + 0.2f, y, z);
        }
    fprintf(f, "light point 2 2 0 equal 40\n"
               "light spot -2 3 1  -2 0 1 equal intensity 20 cone 30\n"
               "light distant 0.3 -1 0.2 equal 0.2\n");
    return fclose(f) != 0;
}

/* 1 when a path's vertex words differ (cl_test_path_differs compares the
 * records alone): an emitter a lobe hit and its MIS-weighted factor, where
 * the pmf of the tree's walk from the lobe's vertex enters */
static int words_differ(const spm_path *a, const spm_path *b)
{
    for (spm_u32 j = 0; j < a->h.nvert && j < SPM_MAX_DEPTH; j++)
        if (a->x[j].ids != b->x[j].ids || !cl_test_close_rel(a->x[j].hit_c, b->x[j].hit_c))
            return 1;
    return 0;
}

/* the kernel's paths (cl_test_trace_diff keeps only the reference's) */
static int trace_kernel(cl_test_scene *s, spm_path *gp)
{
    size_t n = (size_t)W * H * SPP;
    uint8_t *gl = spm_xcalloc(n, 1);
    spm_cl_renderer *r;
    spm_error err;
    int rc = spm_cl_create(0, &s->geom, &s->tables, 0, SEED, &r, &err);
    if (!rc) {
        rc = spm_cl_trace(r, 0, SPP, gp, gl, &err);
        spm_cl_destroy(r);
    }
    free(gl);
    return rc;
}

/* the paths whose lobe hit an emitter (a vertex word's hit colour) */
static size_t lobe_hits(const spm_path *p, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        for (spm_u32 j = 0; j < p[i].h.nvert && j < SPM_MAX_DEPTH; j++)
            k += p[i].x[j].hit_c > 0.0f;
    return k;
}

int main(void)
{
    if (!cl_test_have_device())
        return 77;
    const char *path = "light_tree.scene";
    cl_test_scene s;
    if (write_scene(path) || cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "the scene %s is written and loads", path);
        TEST_END();
    }
    size_t n = (size_t)W * H * SPP, diverged, level_diff;
    spm_path *power = spm_xcalloc(n, sizeof *power), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *lv = spm_xcalloc(n, 1);
    spm_trace_params pp = cl_test_params(&s, SEED, 0, SPP);
    spm_ref_trace(&s.geom, s.tables.materials, cl_test_lvlk(&s.tables, 0), &pp, power, lv);
    spm_light_tree_attach(&s.geom, s.tables.materials);
    CHECK(s.geom.ntree > 0 && s.geom.nemitters == 243, "the tree over %d lights", s.geom.nemitters);
    spm_path *gp = spm_xcalloc(n, sizeof *gp);
    if (cl_test_trace_diff(&s, SEED, SPP, cp, &diverged, &level_diff) == 0 &&
        trace_kernel(&s, gp) == 0) {
        size_t moved = 0, lit = 0, words = 0, hits = lobe_hits(cp, n);
        for (size_t i = 0; i < n; i++) {
            moved += cl_test_path_differs(&power[i], &cp[i]) || words_differ(&power[i], &cp[i]);
            words += !cl_test_path_differs(&gp[i], &cp[i]) && words_differ(&gp[i], &cp[i]);
            for (spm_u32 j = 0; j < cp[i].h.nvert; j++)
                lit += (cp[i].v[j].ids >> 16) != SPM_NONE;
        }
        printf("tree: %zu paths, %zu light samples that lit, %zu paths other than by power, "
               "%zu lobe hits on emitters; kernel against reference: %zu diverged, %zu more "
               "with other vertex words, %zu level bytes differ\n", n, lit, moved, hits, diverged,
               words, level_diff);
        CHECK(hits > n / 100, "only %zu lobe hits on emitters", hits);
        CHECK((double)words <= MAX_DIVERGENT_FRACTION * (double)n, "%zu of %zu paths' vertex words "
              "differ (the MIS weight at a lobe's emitter hit)", words, n);
        CHECK(moved > n / 4, "only %zu of %zu paths changed with the tree", moved, n);
        CHECK(lit > n / 4, "only %zu light samples lit", lit);
        CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu of %zu paths diverged",
              diverged, n);
        CHECK(level_diff == 0, "%zu paths with equal records have other level bytes", level_diff);
    } else {
        CHECK(0, "the kernels ran");
    }
    free(gp);
    free(power);
    free(cp);
    free(lv);
    cl_test_scene_close(&s);
    TEST_END();
}
