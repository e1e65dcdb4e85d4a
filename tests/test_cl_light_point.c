/* The point light (light point X Y Z SPECTRUM POWER) on both backends:
 *  - a white Lambertian plane (rho = 0.5) seen from above, lit by a point
 *    light alone: every path's light sample at its first vertex is the whole
 *    of its radiance (its bounce escapes into a black sky), so per path
 *    Y = rho I cos(theta) / (pi d^2), I = POWER / (4 pi) (the spectrum at
 *    Y = 1), the hit point and theta, d from the camera ray recomputed here
 *    in double -- on the CPU reference and the OpenCL kernels;
 *  - the kernel's trace against the reference's, path by path, in a closed
 *    box where a point light and an area light of other power share the
 *    selection and a block casts the point light's shadow. */
#include "cl_testlib.h"
#include "spm_rng.h"
#include "testutil.h"

#define SEED 11u
#define POWER 40.0
#define RHO 0.5
static const double light[3] = {0.7, 1.5, 0.4};

/* Float ray arithmetic and the truth bins' sums of 400 products: measured
 * worst 1.4e-6 relative (CPU; OpenCL 1.0e-6); bound 1e-4. */
#define PLANE_REL 1e-4

static void check_plane(const spm_trace_params *p, const float *xyz, size_t n, const char *who)
{
    double worst = 0.0;
    size_t bad = 0, lit = 0;
    for (size_t i = 0; i < n; i++) {
        double d[3], x[3], v[3];
        cl_test_camera_dir(p, i, d);
        double t = -p->cam.eye[1] / d[1]; /* the plane y = 0 */
        for (int k = 0; k < 3; k++) {
            x[k] = p->cam.eye[k] + t * d[k];
            v[k] = light[k] - x[k];
        }
        double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        double want = RHO * (POWER / (4.0 * M_PI)) * (v[1] / sqrt(d2)) / (M_PI * d2);
        double e = fabs(xyz[3 * i + 1] - want) / want;
        worst = fmax(worst, e);
        bad += !(e <= PLANE_REL);
        lit += xyz[3 * i + 1] > 0.0f;
    }
    printf("plane (%s): %zu paths, %zu lit, worst %.3g relative to rho I cos / (pi d^2)\n", who, n,
           lit, worst);
    CHECK(lit == n, "%s: %zu of %zu paths unlit", who, n - lit, n);
    CHECK(bad == 0, "%s: %zu paths off the closed form (worst %.3g)", who, bad, worst);
}

static int write_scene(const char *path, const char *body)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "spectrum equal equal\n%s", body);
    fprintf(f, "light point %.17g %.17g %.17g equal %.17g\n", light[0], light[1], light[2], POWER);
    return fclose(f) != 0;
}

static void test_plane(void)
{
    const char *path = "point_plane.scene";
    if (write_scene(path, "image 24 18\ncamera position 0 3 0 direction 0 -1 0 fov 70\n"
                          "material floor reflect equal 0.5\n"
                          "quad floor -100 0 -100  -100 0 100  100 0 100  100 0 -100\n")) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, 24, 18)) {
        CHECK(0, "the plane scene loads");
        return;
    }
    const int spp = 4;
    size_t n = (size_t)24 * 18 * spp;
    spm_trace_params p = cl_test_params(&s, SEED, 0, (spm_u32)spp);
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    for (int cl = 0; cl < 2; cl++) {
        memset(xyz, 0, 3 * n * sizeof *xyz);
        int rc = cl_test_render_truth(&s, cl, SEED, 24, 18, spp, paths, xyz);
        CHECK(rc == 0, "%s: the render failed", cl ? "opencl" : "cpu");
        if (!rc)
            check_plane(&p, xyz, n, cl ? "opencl" : "cpu");
    }
    free(paths);
    free(xyz);
    cl_test_scene_close(&s);
}

/* as test_cl_trace: a path may diverge only where a few ulps of cos/sin move
 * a ray across an edge; 1 in 1000 is a generous ceiling */
#define MAX_DIVERGENT_FRACTION 1e-3
#define W 24
#define H 24
#define SPP 16

static void test_box(void)
{
    const char *path = "point_box.scene";
    if (write_scene(path, "image 24 24\ncamera position 0 1 -3.5 direction 0 0 1 fov 50\n"
                          "material wall reflect equal 0.7\nmaterial lamp emit equal 3\n"
                          "quad wall -2 0 -2  -2 0 2  2 0 2  2 0 -2\n"
                          "quad wall -2 0 2  -2 2.5 2  2 2.5 2  2 0 2\n"
                          "quad wall -2 2.5 -2  2 2.5 -2  2 2.5 2  -2 2.5 2\n"
                          "quad wall -2 0 -2  -2 2.5 -2  -2 2.5 2  -2 0 2\n"
                          "quad wall 2 0 -2  2 0 2  2 2.5 2  2 2.5 -2\n"
                          "quad wall 0.2 0.6 0  0.2 0.6 0.8  1.2 0.6 0.8  1.2 0.6 0\n"
                          "quad lamp -1.5 2.49 1  -1 2.49 1  -1 2.49 1.5  -1.5 2.49 1.5\n")) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "the box scene loads");
        return;
    }
    CHECK(s.geom.emit_power == 1 && s.geom.nemitters == 3, "the selection: by power over the "
          "area light's two triangles and the point light (%d lights, by power %d)",
          s.geom.nemitters, s.geom.emit_power);
    size_t n = (size_t)W * H * SPP;
    spm_path *gp = spm_xcalloc(n, sizeof *gp), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    spm_trace_params p = cl_test_params(&s, SEED, 0, SPP);
    spm_ref_trace(&s.geom, s.tables.materials, cl_test_lvlk(&s.tables, 0), &p, cp, cl);
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s.geom, &s.tables, 0, SEED, &r, &err) == 0) {
        int rc = spm_cl_trace(r, 0, SPP, gp, gl, &err);
        CHECK(rc == 0, "spm_cl_trace: %s", err.msg);
        size_t diverged = 0, level_diff = 0, point = 0, shadowed = 0;
        spm_u32 pc = s.geom.emitters[2].colour;
        for (size_t i = 0; !rc && i < n; i++) {
            int d = cl_test_path_differs(&gp[i], &cp[i]);
            diverged += d;
            level_diff += !d && gl[i] != cl[i];
            for (spm_u32 j = 0; j < cp[i].h.nvert; j++)
                point += (cp[i].v[j].ids >> 16) == pc;
            shadowed += cp[i].h.nvert > 0 && (cp[i].v[0].ids >> 16) == SPM_NONE;
        }
        printf("box: %zu paths, %zu vertices lit by the point light, %zu first vertices unlit, "
               "%zu diverged, %zu level bytes differ\n", n, point, shadowed, diverged, level_diff);
        CHECK(point > n / 8 && shadowed > n / 50, "too little point light or shadow (%zu, %zu)",
              point, shadowed);
        CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu of %zu paths diverged",
              diverged, n);
        CHECK(level_diff == 0, "%zu paths with equal records have different level bytes",
              level_diff);
        spm_cl_destroy(r);
    } else {
        CHECK(0, "spm_cl_create: %s", err.msg);
    }
    free(gp);
    free(cp);
    free(gl);
    free(cl);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_plane();
    test_box();
    TEST_END();
}
