/* Smooth shading on both backends, on tools/gen_meshes.py's smooth_box.scene
 * (the conductor test box with a smooth conductor sphere, sphere_n.obj of
 * 224 triangles with its vertex normals, and a smooth diffuse one):
 *  - the reference's shading normal (refcpu_shading.h) at hits on the
 *    conductor sphere against the true sphere's normal there, unit(x - c),
 *    beside the facet's normal for scale;
 *  - the kernel's trace against the reference's, path by path (records, the
 *    conductor's words, level bytes): the kernel interpolates and bends the
 *    normal as the reference does. */
#include "cl_testlib.h"
#include "refcpu_shading.h"
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "testutil.h"
#include <unistd.h>

#define SEED 11u
#define W 32
#define H 24
#define SPP 16
/* as test_cl_conductor: a path may diverge only where a few ulps of cos/sin
 * move a ray across an edge */
#define MAX_DIVERGENT_FRACTION 1e-3

static char dir[256];

/* Angle between unit a and b (radians). */
static double angle(const float a[3], const double b[3])
{
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], c[3] = {
        a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), dot);
}

/* The sphere: centre (0.17, 0.5, 0.2), radius 0.08 (smooth_box.scene). Rays
 * from the camera to points spread over the sphere's face; hits on it whose
 * viewer makes a cosine above 0.3 with the true normal (away from the
 * silhouette, where the bend of kernels/shading.clh takes over). */
static void test_accuracy(const cl_test_scene *s)
{
    const double c[3] = {0.17, 0.5, 0.2}, r = 0.08;
    const spm_geometry *g = &s->geom;
    double sum_s = 0, sum_f = 0, worst_s = 0, worst_f = 0;
    int n = 0;
    for (int i = 0; i < 4000; i++) {
        float u = spm_rng(3u, (spm_u32)i, 0u, 0u), v = spm_rng(3u, (spm_u32)i, 0u, 1u);
        float target[3] = {(float)(c[0] + r * (2 * u - 1)), (float)(c[1] + r * (2 * v - 1)),
                           (float)c[2]};
        float o[3], d[3], dv[3], t;
        for (int k = 0; k < 3; k++)
            o[k] = g->cam.eye[k];
        v3_sub(dv, target, o);
        v3_normalise(d, dv);
        int hit = spm_bvh_intersect(g, o, d, 0xFFFFFFFFu, &t);
        if (hit < 0)
            continue;
        const spm_tri *tr = &g->tris[hit];
        float x[3];
        v3_madd(x, o, d, t);
        double tn[3], len = 0;
        for (int k = 0; k < 3; k++) {
            tn[k] = x[k] - c[k];
            len += tn[k] * tn[k];
        }
        len = sqrt(len);
        if (!tr->vn || fabs(len - r) > 0.05 * r)
            continue; /* not the conductor sphere */
        for (int k = 0; k < 3; k++)
            tn[k] /= len;
        if (-(d[0] * tn[0] + d[1] * tn[1] + d[2] * tn[2]) < 0.3)
            continue;
        float gn[3] = {tr->n[0], tr->n[1], tr->n[2]}, sn[3], st[3];
        if (v3_dot(gn, d) > 0.0f)
            gn[0] = -gn[0], gn[1] = -gn[1], gn[2] = -gn[2];
        spm_ref_shading_frame(tr, &g->vnormals[9 * (size_t)(tr->vn - 1u)], o, d, gn, sn, st);
        double as = angle(sn, tn), af = angle(gn, tn);
        sum_s += as;
        sum_f += af;
        worst_s = fmax(worst_s, as);
        worst_f = fmax(worst_f, af);
        n++;
        CHECK(fabs(v3_dot(sn, st)) < 1e-5f && fabs(v3_dot(st, st) - 1.0f) < 1e-5f,
              "the tangent is a unit vector perpendicular to the shading normal");
    }
    printf("sphere, %d hits: shading normal vs the true normal mean %.3g, worst %.3g rad; "
           "the facet's mean %.3g, worst %.3g rad\n", n, sum_s / n, worst_s, sum_f / n, worst_f);
    CHECK(n > 1000, "too few hits on the sphere (%d)", n);
    /* The vertex normals are the vertices' radii, (p_i - c) / r, and the hit x
     * lies in the facet, x = w p0 + u p1 + v p2, so the interpolated normal
     * w n0 + u n1 + v n2 is (x - c) / r: exactly the true normal's direction
     * in real arithmetic, float rounding aside (measured: mean 6e-7, worst
     * 3.7e-6 rad; the facet's own normal is off by 0.14 on average, up to 0.27:
     * 8 rings of 16 segments). Bound 2e-5 rad, 5x the measured worst. */
    CHECK(worst_s < 2e-5, "the shading normal is off: mean %.3g, worst %.3g", sum_s / n, worst_s);
    CHECK(sum_f / n > 0.05, "the facets are too fine to tell (mean %.3g)", sum_f / n);
}

/* A cosine (dimensionless, in [0, 1]) within CL_TEST_WEIGHT_REL relative, or
 * 1e-5 absolute: a grazing cosine carries the few ulps by which the kernel's
 * cos/sin differ from libm's through the path's earlier bounces (measured: 2.3e-6
 * on a cosine of 0.021 at a mirror sphere's rim, 1e-4 of it). */
static int cos_close(float a, float b)
{
    return cl_test_close_rel(a, b) || fabsf(a - b) <= 1e-5f;
}

static int ext_differs(const spm_path *a, const spm_path *b)
{
    for (spm_u32 j = 0; j < a->h.nvert; j++) {
        const spm_vertex_ext *x = &a->x[j], *y = &b->x[j];
        int last = j + 1 == a->h.nvert && a->h.end == SPM_END_TRUNCATED;
        if (x->ids != y->ids || !cos_close(x->cos_light, y->cos_light) ||
            !cl_test_close_rel(x->hit_c, y->hit_c) || (!last && !cos_close(x->cos_lobe, y->cos_lobe)))
            return 1;
    }
    return 0;
}

static void test_paths(const cl_test_scene *s)
{
    size_t n = (size_t)W * H * SPP;
    spm_path *gp = spm_xcalloc(n, sizeof *gp), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    spm_trace_params p = cl_test_params(s, SEED, 0, SPP);
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s->geom, &s->tables, 0, SEED, &r, &err)) {
        CHECK(0, "spm_cl_create: %s", err.msg);
        return;
    }
    spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, 0), &p, cp, cl);
    int rc = spm_cl_trace(r, 0, SPP, gp, gl, &err);
    CHECK(rc == 0, "spm_cl_trace: %s", err.msg);
    size_t diverged = 0, xdiff = 0, level_diff = 0, smooth_paths = 0;
    for (size_t i = 0; i < n; i++) {
        int d = cl_test_path_differs(&gp[i], &cp[i]);
        diverged += d;
        int xd = !d && ext_differs(&gp[i], &cp[i]);
        xdiff += xd;
        for (spm_u32 j = 0; xd && xdiff <= 3 && j < cp[i].h.nvert; j++)
            printf("path %zu vertex %u: kernel ids %08x cos_lobe %.9g cos_light %.9g hit_c %.9g; "
                   "reference %08x %.9g %.9g %.9g\n", i, j, gp[i].x[j].ids, gp[i].x[j].cos_lobe,
                   gp[i].x[j].cos_light, gp[i].x[j].hit_c, cp[i].x[j].ids, cp[i].x[j].cos_lobe,
                   cp[i].x[j].cos_light, cp[i].x[j].hit_c);
        level_diff += !d && gl[i] != cl[i];
    }
    /* how many camera rays hit a smooth triangle (a fresh intersection on the host) */
    for (size_t i = 0; i < n; i += SPP) {
        spm_u32 pixel, sample;
        spm_ref_path_key(&p, i, &pixel, &sample);
        (void)sample;
        float cx = 2.0f * ((float)(pixel % W) + 0.5f) / W - 1.0f;
        float cy = 1.0f - 2.0f * ((float)(pixel / W) + 0.5f) / H, d[3], sd[3], t;
        for (int k = 0; k < 3; k++)
            sd[k] = p.cam.dir[k] + p.cam.tan_half * (p.cam.right[k] * cx + p.cam.up[k] * cy * H / W);
        v3_normalise(d, sd);
        int hit = spm_bvh_intersect(&s->geom, p.cam.eye, d, 0xFFFFFFFFu, &t);
        smooth_paths += hit >= 0 && s->geom.tris[hit].vn != 0;
    }
    printf("smooth box: %zu paths, %zu pixels see a smooth triangle; %zu diverged, %zu "
           "conductor words differ, %zu level bytes differ\n", n, smooth_paths, diverged, xdiff,
           level_diff);
    CHECK(smooth_paths > 20, "too few pixels see the spheres (%zu)", smooth_paths);
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu paths diverged", diverged);
    CHECK(xdiff == 0, "%zu paths' conductor words differ", xdiff);
    CHECK(level_diff == 0, "%zu level bytes differ", level_diff);
    spm_cl_destroy(r);
    free(gp);
    free(cp);
    free(gl);
    free(cl);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    snprintf(dir, sizeof dir, "/tmp/spm_test_cl_smooth.%d", (int)getpid());
    char cmd[1024], path[512];
    snprintf(cmd, sizeof cmd, "python3 %s/tools/gen_meshes.py %s > /dev/null", SPM_SOURCE_DIR, dir);
    if (system(cmd) != 0) {
        CHECK(0, "%s", cmd);
        TEST_END();
    }
    snprintf(path, sizeof path, "%s/smooth_box.scene", dir);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "smooth_box.scene loads");
    } else {
        CHECK(s.geom.nvn > 400, "both spheres smooth (%d smooth triangles)", s.geom.nvn);
        test_accuracy(&s);
        test_paths(&s);
        cl_test_scene_close(&s);
    }
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    TEST_END();
}
