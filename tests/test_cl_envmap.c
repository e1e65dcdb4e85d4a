/* The environment map (background map FILE) on both backends, on maps the
 * test writes (tests/envmap_testlib.h):
 *  - the furnace: a white Lambertian sphere (reflectance 1, convex: a
 *    bounce escapes) under a constant map is invisible: the mean Y of the
 *    paths that meet it is the map's (the camera rays that miss it) within
 *    1 %, next-event estimation alone carrying the light (a Lambertian's
 *    bounce counts no emission);
 *  - the kernel's trace against the reference's, path by path, on a floor
 *    with a coated sphere (its rough lobe takes MIS against the map) and a
 *    diffuse one, an area light and a rotated map with a small sun. */
#include "cl_testlib.h"
#include "envmap_testlib.h"
#include "testutil.h"

#define SEED 5u

/* a UV sphere of n rows, 2n columns: triangles into f, material m */
static void write_sphere(FILE *f, const char *m, int n, double r, double cx, double cy, double cz)
{
    for (int a = 0; a < n; a++)
        for (int b = 0; b < 2 * n; b++) {
            double q[4][3], t[2] = {M_PI * a / n, M_PI * (a + 1) / n};
            double p[2] = {M_PI * b / n, M_PI * (b + 1) / n};
            for (int k = 0; k < 4; k++) {
                double th = t[k == 1 || k == 2], ph = p[k >= 2];
                q[k][0] = cx + r * sin(th) * cos(ph);
                q[k][1] = cy + r * cos(th);
                q[k][2] = cz + r * sin(th) * sin(ph);
            }
            static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (int s = 0; s < 2; s++) {
                if ((s == 0 && a == n - 1) || (s == 1 && a == 0))
                    continue; /* the poles' degenerate halves */
                fprintf(f, "tri %s", m);
                for (int k = 0; k < 3; k++)
                    fprintf(f, "  %.9g %.9g %.9g", q[tri[s][k]][0], q[tri[s][k]][1],
                            q[tri[s][k]][2]);
                fprintf(f, "\n");
            }
        }
}

/* the scene file `scene` to write, once the map is written (NULL: failed) */
static FILE *open_scene(const char *scene, const char *map, int w, int h, envmap_texel_fn fn)
{
    FILE *f = envmap_write_hdr(map, w, h, fn) ? NULL : fopen(scene, "w");
    CHECK(f != NULL, "cannot write %s and %s", map, scene);
    return f;
}

/* 1 % of the map, as the issue asks; the estimate's standard error at
 * 48 x 48 x 192 paths is 0.23 % (printed: 1.29 a path, over the sphere's) */
#define FURNACE_REL 0.01

static void test_furnace(void)
{
    const int w = 48, h = 48, spp = 192;
    FILE *f = open_scene("envmap_furnace.scene", "envmap_white.hdr", 16, 8, envmap_white);
    if (!f)
        return;
    fprintf(f, "image %d %d\ncamera position 0 0 -3 direction 0 0 1 fov 40\n"
               "spectrum white equal\nmaterial white reflect white 1\n"
               "background map envmap_white.hdr scale 1.5\n", w, h);
    write_sphere(f, "white", 24, 1.0, 0.0, 0.0, 0.0);
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, "envmap_furnace.scene", w, h)) {
        CHECK(0, "the furnace loads");
        return;
    }
    size_t n = (size_t)w * h * spp;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    for (int cl = 0; cl < 2; cl++) {
        const char *who = cl ? "opencl" : "cpu";
        if (cl_test_render_truth(&s, cl, SEED, w, h, spp, paths, xyz)) {
            CHECK(0, "%s: the furnace did not render", who);
            continue;
        }
        double bg = 0.0, sum = 0.0, sum2 = 0.0;
        size_t nbg = 0, met = 0;
        for (size_t i = 0; i < n; i++)
            if (paths[i].h.nvert == 0)
                bg += xyz[3 * i + 1], nbg++;
        bg /= (double)(nbg ? nbg : 1);
        for (size_t i = 0; i < n; i++)
            if (paths[i].h.nvert > 0) {
                double r = xyz[3 * i + 1] / bg;
                sum += r, sum2 += r * r, met++;
            }
        double mean = met ? sum / (double)met : 0.0;
        double se = met > 1 ? sqrt((sum2 / (double)met - mean * mean) / (double)(met - 1)) : 1.0;
        printf("furnace (%s): map Y %.5f over %zu paths; the sphere's %zu paths %.5f of it "
               "(se %.5f)\n", who, bg, nbg, met, mean, se);
        CHECK(fabs(bg - 1.5) < 0.015, "%s: the map's Y %.5f, not its scale 1.5", who, bg);
        CHECK(met > n / 4, "%s: the sphere met by %zu paths", who, met);
        CHECK(fabs(mean - 1.0) <= FURNACE_REL, "%s: the white sphere at %.4f of the map", who,
              mean);
    }
    free(paths);
    free(xyz);
    cl_test_scene_close(&s);
}

/* as test_cl_trace: a path may diverge only where a few ulps of cos/sin move
 * a ray across an edge or a texel's border; 1 in 1000 is a generous ceiling */
#define MAX_DIVERGENT_FRACTION 1e-3
#define W 32
#define H 24
#define SPP 16

static void test_trace(void)
{
    FILE *f = open_scene("envmap_trace.scene", "envmap_sun.hdr", 64, 32, envmap_sun);
    if (!f)
        return;
    fprintf(f, "image %d %d\ncamera position 0 1.2 -4.5 direction 0 -0.2 1 fov 50\n"
               "spectrum white equal\nmaterial floor reflect white 0.6\n"
               "material paint coated reflect white 0.5 ior 1.5 alpha 0.2\n"
               "material lamp emit white 4\nbackground map envmap_sun.hdr rotate 30\n"
               "quad floor -4 0 -4  -4 0 4  4 0 4  4 0 -4\n"
               "quad lamp -2 2.5 1  -1.5 2.5 1  -1.5 2.5 1.5  -2 2.5 1.5\n", W, H);
    write_sphere(f, "paint", 12, 0.8, -0.9, 0.8, 0.0);
    write_sphere(f, "floor", 12, 0.8, 0.9, 0.8, 0.0);
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, "envmap_trace.scene", W, H)) {
        CHECK(0, "the trace scene loads");
        return;
    }
    size_t n = (size_t)W * H * SPP, diverged, level_diff, mapped = 0, escaped = 0;
    spm_path *cp = spm_xcalloc(n, sizeof *cp);
    int rc = cl_test_trace_diff(&s, SEED, SPP, cp, &diverged, &level_diff);
    CHECK(rc == 0, "the kernels traced");
    spm_u32 first = (spm_u32)s.scene.env->first, last = first + (spm_u32)s.scene.env->ncolours;
    for (size_t i = 0; !rc && i < n; i++) {
        for (spm_u32 j = 0; j < cp[i].h.nvert; j++) {
            spm_u32 e = cp[i].v[j].ids >> 16;
            mapped += e >= first && e < last;
        }
        escaped += cp[i].h.nvert > 0 && cp[i].h.bg != SPM_NONE;
    }
    printf("trace: %zu paths, %zu vertices lit by the map, %zu paths escaping into it after "
           "a bounce, %zu diverged, %zu level bytes differ\n", n, mapped, escaped, diverged,
           level_diff);
    CHECK(mapped > n / 4 && escaped > n / 400, "too little of the map (%zu, %zu)", mapped, escaped);
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu of %zu paths diverged",
          diverged, n);
    CHECK(level_diff == 0, "%zu paths with equal records have different level bytes", level_diff);
    free(cp);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_furnace();
    test_trace();
    TEST_END();
}
