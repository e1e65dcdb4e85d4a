/* The delta lights (light point|spot|distant) on both backends:
 *  - a white Lambertian plane (rho = 0.5) seen from above, lit by one light
 *    alone: every path's light sample at its first vertex is the whole of
 *    its radiance (its bounce escapes into a black sky), so per path, the
 *    hit point recomputed here in double from the camera ray,
 *      point:   Y = rho I cos(theta) / (pi d^2), I = POWER / (4 pi);
 *      spot:    Y = rho I f(alpha) cos(theta) / (pi d^2), alpha the angle
 *               to its axis and f Mitsuba 3's falloff, 1 to the beam angle,
 *               linear in alpha to 0 at the cone's edge (written here from
 *               the statement's angles), 0 beyond: the edge where its angle
 *               says; and its shapes smoothstep (pbrt-v4's, t^2 (3 - 2 t))
 *               and squared (glTF's, t^2), t = (cos alpha - cos c) / (cos b
 *               - cos c) clamped to [0, 1];
 *      distant: Y = rho E cos(theta) / pi,
 *    the spectrum at Y = 1 -- on the CPU reference and the OpenCL kernels;
 *  - the kernel's trace against the reference's, path by path, in a closed
 *    box where the light and an area light of other power share the
 *    selection and a block casts the light's shadow. */
#include "cl_testlib.h"
#include "spm_rng.h"
#include "testutil.h"

#define SEED 11u
#define POWER 40.0
#define RHO 0.5
static const double light[3] = {0.7, 1.5, 0.4};
/* the spot: aimed at (0.2, 0, 0.1), intensity 3, cone 35 degrees, falloff 15 */
static const double target[3] = {0.2, 0.0, 0.1};
#define SPOT_I 3.0
#define SPOT_CONE 35.0
#define SPOT_FALLOFF 15.0
/* the distant light: along (0.3, -1, 0.2), irradiance 0.8 */
static const double travel[3] = {0.3, -1.0, 0.2};
#define DIST_E 0.8

enum { POINT, SPOT, SPOT_SMOOTH, SPOT_SQUARED, DISTANT };
static const char *const kind_name[] = {"point", "spot", "smoothstep spot", "squared spot",
                                        "distant"};
static const char *const spot_shape[] = {"", "linear", "smoothstep", "squared", ""};
#define IS_SPOT(kind) ((kind) >= SPOT && (kind) <= SPOT_SQUARED)

/* Float ray arithmetic and the truth bins' sums of 400 products: measured
 * worst 1.4e-6 relative (CPU; OpenCL 1.0e-6); bound 1e-4, relative to the
 * value without the spot's falloff (an angle's float error moves f by it
 * over the falloff's width). */
#define PLANE_REL 1e-4
/* paths within this angle (rad) of the spot's edge are not judged: float
 * acos and direction errors are ~1e-6 there */
#define EDGE_RAD 1e-4

static double norm3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* the closed form at plane point x: *want, and *full its value with f = 1
 * (the tolerance's scale); 0: too near the spot's edge to judge */
static int closed_form(int kind, const double x[3], double *want, double *full)
{
    double v[3], a[3];
    for (int k = 0; k < 3; k++) {
        v[k] = light[k] - x[k];
        a[k] = target[k] - light[k];
    }
    double d = norm3(v), f = 1.0;
    if (kind == DISTANT) {
        *want = *full = RHO * DIST_E * (-travel[1] / norm3(travel)) / M_PI;
        return 1;
    }
    double in = (kind == POINT ? POWER / (4.0 * M_PI) : SPOT_I) * (v[1] / d) / (M_PI * d * d);
    if (IS_SPOT(kind)) {
        double c = SPOT_CONE * M_PI / 180.0, b = (SPOT_CONE - SPOT_FALLOFF) * M_PI / 180.0;
        double alpha = acos(-(v[0] * a[0] + v[1] * a[1] + v[2] * a[2]) / (d * norm3(a)));
        if (fabs(alpha - c) < EDGE_RAD)
            return 0;
        double t = fmin(1.0, fmax(0.0, (cos(alpha) - cos(c)) / (cos(b) - cos(c))));
        f = kind == SPOT_SMOOTH    ? t * t * (3.0 - 2.0 * t)
            : kind == SPOT_SQUARED ? t * t
            : alpha <= b           ? 1.0
            : alpha < c            ? (c - alpha) / (c - b)
                                   : 0.0;
    }
    *full = RHO * in;
    *want = RHO * in * f;
    return 1;
}

static void check_plane(int kind, const spm_trace_params *p, const float *xyz, size_t n,
                        const char *who)
{
    double worst = 0.0;
    size_t bad = 0, lit = 0, dark = 0, judged = 0;
    for (size_t i = 0; i < n; i++) {
        double d[3], x[3], want, full;
        cl_test_camera_dir(p, i, d);
        double t = -p->cam.eye[1] / d[1]; /* the plane y = 0 */
        for (int k = 0; k < 3; k++)
            x[k] = p->cam.eye[k] + t * d[k];
        if (!closed_form(kind, x, &want, &full))
            continue;
        double e = fabs(xyz[3 * i + 1] - want) / full;
        worst = fmax(worst, e);
        bad += !(e <= PLANE_REL);
        judged++;
        lit += xyz[3 * i + 1] > 0.0f;
        dark += want == 0.0;
    }
    printf("%s plane (%s): %zu paths, %zu judged, %zu lit, %zu outside the cone, worst %.3g "
           "relative to the closed form\n", kind_name[kind], who, n, judged, lit, dark, worst);
    CHECK(lit + dark == judged, "%s: %zu of %zu paths unlit", who, judged - lit - dark, judged);
    CHECK(!IS_SPOT(kind) || (dark > n / 4 && lit > n / 4), "%s: the spot's edge is not in view "
          "(%zu outside, %zu lit)", who, dark, lit);
    CHECK(bad == 0, "%s: %zu paths off the closed form (worst %.3g)", who, bad, worst);
}

static int write_scene(int kind, const char *path, const char *body)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "spectrum equal equal\n%s", body);
    if (kind == POINT)
        fprintf(f, "light point %.17g %.17g %.17g equal %.17g\n", light[0], light[1], light[2],
                POWER);
    else if (IS_SPOT(kind))
        fprintf(f, "light spot %.17g %.17g %.17g  %.17g %.17g %.17g equal intensity %.17g "
                "cone %.17g falloff %.17g shape %s\n", light[0], light[1], light[2], target[0],
                target[1], target[2], SPOT_I, SPOT_CONE, SPOT_FALLOFF, spot_shape[kind]);
    else
        fprintf(f, "light distant %.17g %.17g %.17g equal %.17g\n", travel[0], travel[1],
                travel[2], DIST_E);
    return fclose(f) != 0;
}

static void test_plane(int kind)
{
    const char *path = "delta_plane.scene";
    if (write_scene(kind, path, "image 24 18\ncamera position 0 3 0 direction 0 -1 0 fov 70\n"
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
            check_plane(kind, &p, xyz, n, cl ? "opencl" : "cpu");
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

static void test_box(int kind)
{
    const char *path = "delta_box.scene";
    /* the distant light comes in through the open top */
    char body[1024];
    snprintf(body, sizeof body, "image 24 24\ncamera position 0 1 -3.5 direction 0 0 1 fov 50\n"
             "material wall reflect equal 0.7\nmaterial lamp emit equal 3\n"
             "quad wall -2 0 -2  -2 0 2  2 0 2  2 0 -2\n"
             "quad wall -2 0 2  -2 2.5 2  2 2.5 2  2 0 2\n%s"
             "quad wall -2 0 -2  -2 2.5 -2  -2 2.5 2  -2 0 2\n"
             "quad wall 2 0 -2  2 0 2  2 2.5 2  2 2.5 -2\n"
             "quad wall 0.2 0.6 0  0.2 0.6 0.8  1.2 0.6 0.8  1.2 0.6 0\n"
             "quad lamp -1.5 2.49 1  -1 2.49 1  -1 2.49 1.5  -1.5 2.49 1.5\n",
             kind == DISTANT ? "" : "quad wall -2 2.5 -2  2 2.5 -2  2 2.5 2  -2 2.5 2\n");
    if (write_scene(kind, path, body)) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "the box scene loads");
        return;
    }
    CHECK(s.geom.emit_power == 1 && s.geom.nemitters == 3, "the selection: by power over the "
          "area light's two triangles and the %s light (%d lights, by power %d)", kind_name[kind],
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
        printf("%s box: %zu paths, %zu vertices lit by the light, %zu first vertices unlit, "
               "%zu diverged, %zu level bytes differ\n", kind_name[kind], n, point, shadowed, diverged,
               level_diff);
        CHECK(point > n / 16 && shadowed > n / 50, "too little light or shadow (%zu, %zu)",
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
    for (int kind = POINT; kind <= DISTANT; kind++) {
        test_plane(kind);
        if (kind == POINT || kind == SPOT || kind == DISTANT)
            test_box(kind);
    }
    TEST_END();
}
