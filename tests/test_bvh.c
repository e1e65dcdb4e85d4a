/* Geometry and BVH: MiniLight triangle data, emitter list, camera frame, BVH
 * structure, and BVH closest hits against brute force on rays chosen to be
 * hard (grazing shared edges, through shared vertices, in a wall's plane,
 * leaving a surface, axis-parallel). */
#include <float.h>
#include "geometry_vec3.h"
#include "geomtest_scene.h"
#include "testutil.h"

static void vec_check(const float *a, double x, double y, double z, double tol, const char *what)
{
    CHECK(fabs(a[0] - x) <= tol && fabs(a[1] - y) <= tol && fabs(a[2] - z) <= tol,
          "%s: (%g %g %g) vs (%g %g %g)", what, a[0], a[1], a[2], x, y, z);
}

static void test_triangle_data(void)
{
    spm_scene s;
    ts_init(&s);
    int m = ts_material(&s, ts_colour(&s, SPM_KIND_REFLECTANCE, 0.5), -1);
    ts_tri(&s, m, (float[]){1, 1, 1}, (float[]){3, 1, 1}, (float[]){1, 4, 1});
    spm_geometry g;
    spm_error err;
    CHECK(spm_geometry_build(&s, &g, &err) == 0, "build: %s", err.msg);
    CHECK(g.ntris == 1 && g.nnodes == 1 && g.nodes[0].count == 1, "one leaf");
    const spm_tri *t = &g.tris[0];
    /* exact in float: small integers */
    vec_check(t->v0, 1, 1, 1, 0, "v0");
    vec_check(t->v1, 3, 1, 1, 0, "v1");
    vec_check(t->v2, 1, 4, 1, 0, "v2");
    vec_check(t->n, 0, 0, 1, 0, "normal = normalise(e1 x e2)");
    vec_check(t->t, 1, 0, 0, 0, "tangent = normalise(e1)");
    CHECK(t->area == 3.0f, "area |e1 x e2| / 2 = 3: %g", t->area);
    CHECK(g.nemitters == 0, "no emitter");
    spm_geometry_free(&g);
    ts_free(&s);
}

static void test_bad_triangles(void)
{
    spm_scene s;
    ts_init(&s);
    int m = ts_material(&s, -1, -1);
    ts_tri(&s, m, (float[]){0, 0, 0}, (float[]){1, 0, 0}, (float[]){0, 1, 0});
    ts_tri(&s, m, (float[]){0, 0, 0}, (float[]){1, 1, 1}, (float[]){2, 2, 2}); /* line 101 */
    spm_geometry g;
    spm_error err = {{0}};
    CHECK(spm_geometry_build(&s, &g, &err) != 0, "collinear triangle rejected");
    CHECK(strstr(err.msg, "<test>:101:") && strstr(err.msg, "zero area"), "message: %s", err.msg);
    CHECK(g.tris == NULL && g.nodes == NULL, "nothing left allocated");
    s.tris[1].p[2][1] = 5.0f;
    s.tris[1].material = 7;
    CHECK(spm_geometry_build(&s, &g, &err) != 0 && strstr(err.msg, "<test>:101:"),
          "bad material index named: %s", err.msg);
    ts_free(&s);
}

static void test_emitters(void)
{
    spm_scene s;
    ts_init(&s);
    int grey = ts_colour(&s, SPM_KIND_REFLECTANCE, 0.5);
    int light = ts_material(&s, grey, ts_colour(&s, SPM_KIND_EMISSION, 2.0));
    int dark = ts_material(&s, grey, ts_colour(&s, SPM_KIND_EMISSION, 0.0)); /* MiniLight: zero emission is no emitter */
    int plain = ts_material(&s, grey, -1);
    float lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    ts_box(&s, plain, lo, hi, 0);
    for (int i = 0; i < 3; i++) {
        float y = 0.2f + 0.2f * (float)i;
        ts_tri(&s, i == 0 ? dark : light, (float[]){0.1f, y, 0.1f}, (float[]){0.9f, y, 0.1f},
               (float[]){0.1f, y, 0.9f});
    }
    spm_geometry g;
    spm_error err;
    CHECK(spm_geometry_build(&s, &g, &err) == 0, "build: %s", err.msg);
    CHECK(g.nemitters == 2, "two emitting triangles: %d", g.nemitters);
    for (int i = 0; i < g.nemitters; i++)
        CHECK(g.tris[g.emitters[i].tri].material == (spm_u32)light, "emitter %d has the light", i);
    spm_geometry_free(&g);
    ts_free(&s);
}

static void frame_check(const spm_camera *c, const char *what)
{
    const float *v[3] = {c->dir, c->right, c->up};
    for (int i = 0; i < 3; i++)
        for (int j = i; j < 3; j++) {
            double d = v[i][0] * v[j][0] + v[i][1] * v[j][1] + v[i][2] * v[j][2];
            CHECK(fabs(d - (i == j)) < 1e-6, "%s: frame not orthonormal (%d.%d = %g)", what, i,
                  j, d);
        }
}

static void test_camera(void)
{
    float eye[3] = {1, 2, 3};
    spm_camera c = spm_camera_make(eye, (float[]){0, 0, 5}, 90.0f, 8, 4);
    frame_check(&c, "along z");
    vec_check(c.dir, 0, 0, 1, 1e-7, "dir normalised");
    vec_check(c.right, 1, 0, 0, 1e-7, "right = Y x dir");
    vec_check(c.up, 0, 1, 0, 1e-7, "up = dir x right");
    vec_check(c.eye, 1, 2, 3, 0, "eye");
    CHECK_NEAR(c.tan_half, 1.0, 1e-6, "tan(90 deg / 2)");
    CHECK(c.width == 8 && c.height == 4, "size");
    c = spm_camera_make(eye, (float[]){1, -1, 0.5f}, 40.0f, 8, 4);
    frame_check(&c, "oblique");
    CHECK(c.up[1] > 0, "up keeps +y: %g", c.up[1]);
    c = spm_camera_make(eye, (float[]){0, -2, 0}, 5.0f, 8, 4);
    frame_check(&c, "down");
    vec_check(c.up, 0, 0, 1, 0, "MiniLight: looking down, up is +Z");
    vec_check(c.right, 1, 0, 0, 0, "right = Z x dir");
    CHECK_NEAR(c.tan_half, tan(5.0 * 3.14159265358979 / 180.0), 1e-6, "angle clamped up to 10 degrees");
    c = spm_camera_make(eye, (float[]){0, 3, 0}, 170.0f, 8, 4);
    frame_check(&c, "up");
    vec_check(c.up, 0, 0, -1, 0, "MiniLight: looking up, up is -Z");
    CHECK_NEAR(c.tan_half, tan(80.0 * 3.14159265358979 / 180.0), 1e-5, "angle clamped down to 160 degrees");
}

/* ---- BVH ---------------------------------------------------------------- */

static int box_inside(const float *lo, const float *hi, const float *plo, const float *phi)
{
    for (int i = 0; i < 3; i++)
        if (lo[i] < plo[i] || hi[i] > phi[i])
            return 0;
    return 1;
}

/* Walks the tree: leaves partition the triangle array, leaves hold at most 4,
 * boxes nest and hold their triangles, depth fits the traversal stack. */
static void check_structure(const spm_geometry *g, const char *name)
{
    int *seen = calloc((size_t)g->ntris, sizeof *seen);
    int stack[2 * SPM_BVH_STACK], depth[2 * SPM_BVH_STACK], top = 0, bad = 0, maxd = 0;
    stack[top] = 0, depth[top++] = 0;
    while (top > 0 && !bad) {
        top--;
        const spm_bvh_node *n = &g->nodes[stack[top]];
        int d = depth[top];
        maxd = d > maxd ? d : maxd;
        if (n->count > 0) {
            bad |= n->count > 4 || n->first + n->count > (spm_u32)g->ntris;
            for (spm_u32 k = 0; !bad && k < n->count; k++) {
                const spm_tri *t = &g->tris[n->first + k];
                seen[n->first + k]++;
                for (int v = 0; v < 3; v++) {
                    const float *p = v == 0 ? t->v0 : v == 1 ? t->v1 : t->v2;
                    bad |= !box_inside(p, p, n->bmin, n->bmax);
                }
            }
        } else {
            bad |= n->first + 1 >= (spm_u32)g->nnodes || top + 2 > 2 * SPM_BVH_STACK;
            for (int c = 0; c < 2 && !bad; c++) {
                const spm_bvh_node *ch = &g->nodes[n->first + c];
                bad |= !box_inside(ch->bmin, ch->bmax, n->bmin, n->bmax);
                stack[top] = (int)n->first + c, depth[top++] = d + 1;
            }
        }
    }
    int once = 1;
    for (int i = 0; i < g->ntris; i++)
        once &= seen[i] == 1;
    CHECK(!bad && once, "%s: BVH structure (bad %d, every triangle in one leaf %d)", name, bad,
          once);
    CHECK(maxd < SPM_BVH_STACK, "%s: depth %d", name, maxd);
    free(seen);
}

static void tri_vertex(const spm_tri *t, int v, float p[3])
{
    const float *q = v == 0 ? t->v0 : v == 1 ? t->v1 : t->v2;
    for (int i = 0; i < 3; i++)
        p[i] = q[i];
}

static void rand_dir(unsigned *st, float d[3])
{
    float z = 2.0f * ts_rand(st) - 1.0f, phi = 6.2831853f * ts_rand(st);
    float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    d[0] = r * cosf(phi), d[1] = r * sinf(phi), d[2] = z;
}

typedef struct {
    long rays, hits, mismatches;
} tally;

static void compare_ray(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                        tally *t)
{
    float tb, tf;
    int b = spm_bvh_intersect(g, o, d, skip, &tb);
    int f = spm_brute_intersect(g, o, d, skip, &tf);
    t->rays++;
    t->hits += f >= 0;
    /* Both run the same float test on the same triangle and break exact ties
     * by index, so any difference means the BVH pruned a hit: no tolerance. */
    if (b != f || (f >= 0 && tb != tf)) {
        if (t->mismatches++ < 5)
            fprintf(stderr, "mismatch: o (%.9g %.9g %.9g) d (%.9g %.9g %.9g) bvh %d %.9g brute %d %.9g\n",
                    o[0], o[1], o[2], d[0], d[1], d[2], b, tb, f, tf);
    }
}

/* Rays of five kinds, `per_kind` each, from points in the scene's box grown by 20%. */
static void ray_battery(const spm_geometry *g, int per_kind, unsigned seed, const char *name)
{
    float lo[3], hi[3];
    for (int i = 0; i < 3; i++) {
        float ext = g->nodes[0].bmax[i] - g->nodes[0].bmin[i];
        lo[i] = g->nodes[0].bmin[i] - 0.2f * ext;
        hi[i] = g->nodes[0].bmax[i] + 0.2f * ext;
    }
    unsigned st = seed;
    tally t[5] = {{0}};
    for (int r = 0; r < per_kind; r++) {
        float o[3], d[3], p[3], a[3], b[3];
        for (int i = 0; i < 3; i++)
            o[i] = lo[i] + (hi[i] - lo[i]) * ts_rand(&st);
        /* 0: random */
        rand_dir(&st, d);
        compare_ray(g, o, d, 0xFFFFFFFFu, &t[0]);
        /* 1: aimed at a point on a triangle edge (shared edges graze) */
        const spm_tri *tr = &g->tris[(int)(ts_rand(&st) * g->ntris) % g->ntris];
        int e = (int)(ts_rand(&st) * 3) % 3;
        tri_vertex(tr, e, a);
        tri_vertex(tr, (e + 1) % 3, b);
        float s = ts_rand(&st);
        for (int i = 0; i < 3; i++)
            p[i] = a[i] + (b[i] - a[i]) * s, d[i] = p[i] - o[i];
        v3_normalise(d, d);
        compare_ray(g, o, d, 0xFFFFFFFFu, &t[1]);
        /* 2: aimed at a vertex (shared by several triangles) */
        for (int i = 0; i < 3; i++)
            d[i] = a[i] - o[i];
        v3_normalise(d, d);
        compare_ray(g, o, d, 0xFFFFFFFFu, &t[2]);
        /* 3: axis-parallel, from a vertex's coordinates on one axis (in a
         * wall's plane for axis-aligned walls) */
        int ax = r % 3;
        float q[3] = {o[0], o[1], o[2]};
        q[(ax + 1) % 3] = a[(ax + 1) % 3];
        d[0] = d[1] = d[2] = 0.0f;
        d[ax] = (r / 3) % 2 ? 1.0f : -1.0f;
        compare_ray(g, q, d, 0xFFFFFFFFu, &t[3]);
        /* 4: leaving a surface point, skipping its triangle */
        int ti = (int)(ts_rand(&st) * g->ntris) % g->ntris;
        float u1 = sqrtf(ts_rand(&st)), u2 = ts_rand(&st);
        for (int i = 0; i < 3; i++)
            p[i] = g->tris[ti].v0[i] + (g->tris[ti].v1[i] - g->tris[ti].v0[i]) * (1 - u1) +
                   (g->tris[ti].v2[i] - g->tris[ti].v0[i]) * ((1 - u2) * u1);
        rand_dir(&st, d);
        compare_ray(g, p, d, (spm_u32)ti, &t[4]);
    }
    const char *kinds[5] = {"random", "edge", "vertex", "axis", "surface"};
    for (int k = 0; k < 5; k++) {
        CHECK(t[k].mismatches == 0, "%s/%s: %ld of %ld rays disagree", name, kinds[k],
              t[k].mismatches, t[k].rays);
        /* the battery must exercise hits and misses, or it tests nothing */
        CHECK(t[k].hits > t[k].rays / 20 && (k == 4 || t[k].hits < t[k].rays),
              "%s/%s: %ld hits of %ld rays", name, kinds[k], t[k].hits, t[k].rays);
    }
}

static void build_and_compare(spm_scene *s, int per_kind, unsigned seed, const char *name)
{
    spm_geometry g;
    spm_error err;
    int rc = spm_geometry_build(s, &g, &err);
    CHECK(rc == 0, "%s: build: %s", name, err.msg);
    if (rc)
        return;
    check_structure(&g, name);
    ray_battery(&g, per_kind, seed, name);
    spm_geometry_free(&g);
}

/* A Cornell-like box: walls split into grids of quads (shared edges and
 * vertices), two inner blocks, and a bumpy height field. */
static void scene_boxes(spm_scene *s)
{
    int m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.5), -1);
    float lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
    ts_box(s, m, lo, hi, 0);
    ts_box(s, m, (float[]){-0.6f, -1, -0.5f}, (float[]){-0.1f, 0.2f, 0.1f}, 0);
    ts_box(s, m, (float[]){0.2f, -1, 0.0f}, (float[]){0.7f, -0.4f, 0.6f}, 0);
    const int N = 12;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            float v[4][3];
            for (int k = 0; k < 4; k++) {
                float x = -1 + 2.0f * (float)(i + (k == 1 || k == 2)) / N;
                float z = -1 + 2.0f * (float)(j + (k >= 2)) / N;
                v[k][0] = x, v[k][2] = z;
                v[k][1] = 0.5f + 0.1f * sinf(3 * x) * cosf(2 * z);
            }
            ts_quad(s, m, v[0], v[3], v[2], v[1]);
        }
}

static void scene_soup(spm_scene *s, unsigned seed)
{
    int m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.5), -1);
    unsigned st = seed;
    for (int i = 0; i < 400; i++) {
        float c[3], v[3][3], size = 0.02f + 0.3f * ts_rand(&st);
        for (int k = 0; k < 3; k++)
            c[k] = 2 * ts_rand(&st) - 1;
        for (int q = 0; q < 3; q++)
            for (int k = 0; k < 3; k++)
                v[q][k] = c[k] + size * (2 * ts_rand(&st) - 1);
        ts_tri(s, m, v[0], v[1], v[2]);
    }
}

static void test_bvh_scenes(void)
{
    spm_scene s;
    ts_init(&s);
    scene_boxes(&s);
    build_and_compare(&s, 3000, 12345u, "boxes");
    ts_free(&s);

    ts_init(&s);
    scene_soup(&s, 777u);
    build_and_compare(&s, 3000, 999u, "soup");
    ts_free(&s);

    /* MiniLight's own Cornell box through the scene loader */
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/scenes/cornellbox.ml.txt", SPM_SOURCE_DIR);
    spm_error err;
    int rc = spm_scene_load(path, &s, &err);
    CHECK(rc == 0, "load %s: %s", path, err.msg);
    if (rc == 0) {
        build_and_compare(&s, 3000, 4242u, "minilight cornell");
        spm_scene_free(&s);
    }
}

static void test_empty_scene(void)
{
    spm_scene s;
    ts_init(&s);
    spm_geometry g;
    spm_error err;
    CHECK(spm_geometry_build(&s, &g, &err) == 0, "empty scene builds");
    float t, o[3] = {0, 0, 0}, d[3] = {0, 0, 1};
    CHECK(g.nnodes == 0 && spm_bvh_intersect(&g, o, d, 0xFFFFFFFFu, &t) == -1, "no hit");
    spm_geometry_free(&g);
    ts_free(&s);
}

int main(void)
{
    spm_quiet_warnings = 1;
    test_triangle_data();
    test_bad_triangles();
    test_emitters();
    test_camera();
    test_empty_scene();
    test_bvh_scenes();
    TEST_END();
}
