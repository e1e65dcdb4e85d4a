/* A sun 1.5e11 away, as in MiniLight's cornellbox-e and -n: such scenes load
 * in both formats, are lit as the geometry says (a grey floor under a square
 * sun against its closed form; the Cornell box against a twin whose sun is
 * 1000 away in the same direction with the same solid angle), the BVH finds
 * the closest hit of rays from the room, and the far sun costs the CPU
 * reference's traversal no more than 1.2x the near twin's (nodes tested per
 * path: a count, not a time). The kernel against the CPU reference on this
 * scene: test_cl_trace. */
#include "geomtest_scene.h"
#include "refcpu.h"
#include "backend_cpu.h"
#include "backends.h"
#include "scene_build.h"
#include "testutil.h"
#include <float.h>

static void data_scene(const char *name, char *path, size_t n)
{
    snprintf(path, n, "%s/tests/data/scenes/%s", SPM_SOURCE_DIR, name);
}

/* Mean luminance Y of a CPU-reference render (film XYZ), or -1. */
static double render_mean_y(const char *name, int mode, int size, int spp)
{
    char path[1024];
    data_scene(name, path, sizeof path);
    spm_render_config cfg;
    spm_render_config_defaults(&cfg);
    cfg.scene_path = path;
    cfg.mode = mode;
    cfg.spp = spp;
    cfg.seed = 3;
    cfg.width = cfg.height = size;
    cfg.backend = &spm_backend_kind_cpu;
    spm_render_setup s;
    spm_error err;
    err.msg[0] = 0;
    double mean = -1.0;
    if (spm_render_setup_open(&cfg, &s, &err)) {
        CHECK(0, "%s: set-up: %s", name, err.msg);
        spm_render_setup_close(&s);
        return mean;
    }
    size_t npix = (size_t)size * (size_t)size;
    spm_film film;
    spm_run_result res;
    int rc = spm_film_init(&film, size, size, &err);
    if (!rc) {
        spm_run_opts ro = {.spp = spp, .spp_per_pass = spm_spp_per_pass(npix, spp)};
        rc = spm_render_run(s.b, s.nb, npix, &ro, &film, &res, &err);
        CHECK(rc == 0, "%s: render: %s", name, err.msg);
    }
    if (!rc) {
        float *xyz = spm_xmalloc(3 * npix * sizeof *xyz);
        spm_film_resolve(&film, xyz);
        double sum = 0.0;
        for (size_t i = 0; i < npix; i++)
            sum += xyz[3 * i + 1];
        mean = sum / (double)npix;
        free(xyz);
        CHECK(res.total.nonfinite == 0, "%s: %llu non-finite samples", name,
              (unsigned long long)res.total.nonfinite);
        spm_film_free(&film);
    }
    spm_render_setup_close(&s);
    return mean;
}

/* far_sun_floor.scene: a grey floor (0.5) seen straight down, under a square
 * sun of side 1.5e9 and luminance L = 1e5 at height H = 1.5e11, facing it.
 * Every pixel is the floor lit by E = L * integral over the sun of
 * cos_e cos_i / d^2 = L * integral of H^2 / (H^2 + r^2)^2 (r: offset from
 * the sun's centre) = L * side^2 / H^2 * (1 - 2 <r^2> / H^2 + ...) with
 * <r^2> = side^2 / 6, so its luminance is 0.5 * E / pi. Nothing else lights
 * it: no background, and MiniLight never counts emission met after a bounce. */
static void test_floor_closed_form(void)
{
    const double side = 1.5e9, height = 1.5e11, lum = 1e5, refl = 0.5;
    double h2 = height * height;
    double want = refl * lum * side * side / h2 * (1.0 - side * side / 3.0 / h2) / M_PI;
    int modes[] = {SPM_MODE_TRUTH, SPM_MODE_ML};
    for (int m = 0; m < 2; m++) {
        double y = render_mean_y("far_sun_floor.scene", modes[m], 16, 4);
        /* Flat spectra are exact at every level and the series' next term is
         * 1e-9; what is left is float rounding of each sample's weight (a
         * dozen operations, ~1e-6). A sun lost in part, or weighted with a
         * wrong distance or area, misses 1e-5 by far. */
        CHECK(fabs(y - want) <= 1e-5 * want, "mode %s: floor Y %.7g, closed form %.7g",
              spm_mode_name(modes[m]), y, want);
        printf("far sun over a floor, mode %s: Y %.7g (closed form %.7g)\n",
               spm_mode_name(modes[m]), y, want);
    }
}

/* The Cornell box lit by the sun 1.5e11 away and by the same sun 1000 away
 * (scaled toward the origin by 1.496e8: same direction, same solid angle). */
static void test_box_far_vs_near(void)
{
    double far = render_mean_y("cornellbox_sun.ml.txt", SPM_MODE_ML, 48, 8);
    double near = render_mean_y("cornellbox_sun_near.ml.txt", SPM_MODE_ML, 48, 8);
    printf("Cornell box, mean Y: sun 1.5e11 away %.6g, 1000 away %.6g\n", far, near);
    /* Same seed, same samples, so the two renders are correlated: the near sun
     * differs by a parallax of 3e-4 rad (shadow edges move by < 0.2 mm) and by
     * 1/d^2 varying 0.06% across the room. The mean Y is a few units; a sun
     * that is lost or wrongly weighted changes it by tens of percent. */
    CHECK(far > 1.0, "the far sun lights the box (mean Y %g)", far);
    CHECK(fabs(far - near) <= 5e-3 * near, "far %g vs near %g", far, near);
}

typedef struct {
    spm_scene scene;
    spm_geometry geom;
    spm_tables tables;
} loaded;

static int load(const char *name, loaded *l)
{
    char path[1024];
    data_scene(name, path, sizeof path);
    spm_error err;
    spm_pretest_opts po;
    spm_pretest_defaults(&po);
    memset(l, 0, sizeof *l);
    if (spm_scene_load(path, &l->scene, &err) || spm_geometry_build(&l->scene, &l->geom, &err) ||
        spm_tables_build(&l->scene, &po, &l->tables, &err)) {
        CHECK(0, "%s: %s", name, err.msg);
        return 1;
    }
    return 0;
}

static void unload(loaded *l)
{
    spm_tables_free(&l->tables);
    spm_geometry_free(&l->geom);
    spm_scene_free(&l->scene);
}

/* BVH nodes tested per path over a CPU-reference pass of w x h x spp paths. */
static double nodes_per_path(const loaded *l, int size, spm_u32 spp)
{
    spm_trace_params p;
    memset(&p, 0, sizeof p);
    p.cam = l->geom.cam;
    p.cam.width = p.cam.height = size;
    p.ntris = (spm_u32)l->geom.ntris;
    p.nemitters = (spm_u32)l->geom.nemitters;
    p.emit_power = (spm_u32)l->geom.emit_power;
    p.bg_up = l->tables.bg_up;
    p.bg_down = l->tables.bg_down;
    p.seed = 11;
    p.spp_per_pass = spp;
    size_t n = (size_t)size * (size_t)size * spp;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    unsigned long long before = spm_bvh_nodes_tested;
    spm_ref_trace(&l->geom, l->tables.materials, l->tables.lvlk, &p, paths, levels);
    double per = (double)(spm_bvh_nodes_tested - before) / (double)n;
    free(paths);
    free(levels);
    return per;
}

/* Rays from the room (origins in its box, the open front included) toward
 * points on the sun and in random directions: the BVH's closest hit is the
 * brute-force one exactly (same float test, ties by index). */
static void test_bvh_closest_hits(const loaded *far)
{
    const spm_geometry *g = &far->geom;
    int sun[2], ns = 0;
    for (int i = 0; i < g->nemitters && ns < 2; i++)
        sun[ns++] = (int)g->emitters[i].tri;
    CHECK(ns == 2, "two sun triangles emit (%d)", ns);
    if (ns < 2)
        return;
    unsigned st = 2024u;
    long rays = 0, mismatches = 0, sun_hits = 0;
    for (int r = 0; r < 20000; r++) {
        float o[3], d[3];
        for (int i = 0; i < 3; i++)
            o[i] = -0.1f + 0.76f * ts_rand(&st);
        o[2] -= 0.9f; /* z from -1 to -0.24: in front of the box, near the eye */
        if (r % 2 == 0) {
            const spm_tri *t = &g->tris[sun[r / 2 % 2]];
            float a = ts_rand(&st), b = ts_rand(&st);
            if (a + b > 1.0f)
                a = 1.0f - a, b = 1.0f - b;
            float q[3];
            for (int i = 0; i < 3; i++)
                q[i] = t->v0[i] + (t->v1[i] - t->v0[i]) * a + (t->v2[i] - t->v0[i]) * b;
            for (int i = 0; i < 3; i++)
                d[i] = q[i] - o[i];
        } else {
            for (int i = 0; i < 3; i++)
                d[i] = 2.0f * ts_rand(&st) - 1.0f;
        }
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int i = 0; i < 3; i++)
            d[i] /= len;
        float tb, tf;
        int hb = spm_bvh_intersect(g, o, d, 0xFFFFFFFFu, &tb);
        int hf = spm_brute_intersect(g, o, d, 0xFFFFFFFFu, &tf);
        rays++;
        sun_hits += hf == sun[0] || hf == sun[1];
        if (hb != hf || (hf >= 0 && tb != tf))
            mismatches++;
    }
    CHECK(mismatches == 0, "%ld of %ld rays: BVH and brute force disagree", mismatches, rays);
    /* aimed rays from in front of the box reach the sun unless the box is in the way */
    CHECK(sun_hits > rays / 4, "only %ld of %ld rays reach the sun", sun_hits, rays);
}

static void test_cost(const loaded *far, const loaded *near)
{
    double f = nodes_per_path(far, 48, 8), n = nodes_per_path(near, 48, 8);
    printf("BVH nodes tested per path: sun 1.5e11 away %.2f, 1000 away %.2f (ratio %.3f)\n", f,
           n, f / n);
    CHECK(n > 1.0, "the count counts (%g)", n);
    CHECK(f <= 1.2 * n, "the far sun costs %.3f x the near one's traversal", f / n);
}

/* The coordinate bound (scene_build.h) lets the sun in and keeps the float
 * ray-triangle products finite; just beyond it is refused (bad-inputs). */
static void test_bound(void)
{
    CHECK(SPM_SCENE_MAX_COORD >= 1.5e11, "MiniLight's sun fits");
    double c = SPM_SCENE_MAX_COORD;
    CHECK(48.0 * c * c * c < FLT_MAX, "t's numerator stays finite at the bound");
}

int main(void)
{
    spm_quiet_warnings = 1;
    test_bound();
    loaded far, near;
    int rc = load("cornellbox_sun.ml.txt", &far);
    rc |= load("cornellbox_sun_near.ml.txt", &near);
    if (!rc) {
        CHECK(far.geom.nemitters == 2 && near.geom.nemitters == 2, "the sun's two triangles emit");
        test_bvh_closest_hits(&far);
        test_cost(&far, &near);
    }
    unload(&far);
    unload(&near);
    test_floor_closed_form();
    test_box_far_vs_near();
    TEST_END();
}
