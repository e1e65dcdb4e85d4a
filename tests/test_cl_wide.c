/* The kernels' wide BVH (host/geometry/bvh_wide.c, kernels/traverse.clh)
 * against brute force over every triangle, on layouts chosen to be awkward:
 * exact ties in t between coincident triangles whose copies lie in several
 * leaves (the lowest index must win in the kernel and in the CPU reference,
 * whatever the visiting order), shadow rays through the any-hit loop
 * (occluded by a triangle in front, and by a coincident triangle of lower
 * index than the emitter but not of higher), and degenerate trees: one
 * triangle, a root with fewer than four children, leaves not full, a deep
 * tree. The rays go through kernels/rays.cl, the renderer's traversal. */
#include "bench_rays.h"
#include "cl_testlib.h"
#include "geomtest_scene.h"
#include "testutil.h"

#define NCOPIES 9 /* coincident copies: more than four leaves of LEAF_MAX 2 */

static float frand(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (float)(*s >> 8) / 16777216.0f;
}

static void unit(float d[3])
{
    float l = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; i++)
        d[i] /= l;
}

/* A ray from o towards p. */
static spm_ray ray_to(const float o[3], const float p[3], spm_u32 emitter)
{
    spm_ray r;
    for (int i = 0; i < 3; i++)
        r.o[i] = o[i], r.d[i] = p[i] - o[i];
    unit(r.d);
    r.skip = 0xFFFFFFFFu;
    r.emitter = emitter;
    return r;
}

/* The kernel's answers (1 when the device ran them). */
static int kernel_hits(const spm_geometry *g, const spm_rayset *rs, int *hits, const char *what)
{
    spm_rays_timing tm;
    char dev[256];
    spm_error err;
    int rc = spm_rays_replay_cl(0, g, rs, 0, 0, hits, &tm, dev, sizeof dev, NULL, NULL, &err);
    CHECK(rc == 0, "%s: %s", what, err.msg);
    CHECK(rc || tm.stack_overflows == 0, "%s: %u stack overflows", what, tm.stack_overflows);
    return rc == 0;
}

/* Lit (1) when the closest hit other than skip is the emitter or nothing. */
static int lit(int closest, spm_u32 emitter)
{
    return closest < 0 || (spm_u32)closest == emitter;
}

/* Every closest-hit ray: kernel = CPU reference = brute force. Returns hits. */
static size_t check_closest(const spm_geometry *g, const spm_rayset *rs, const char *what)
{
    int *hk = spm_xmalloc(rs->n * sizeof *hk), *hr = spm_xmalloc(rs->n * sizeof *hr);
    size_t bad = 0, refbad = 0, nhit = 0;
    if (kernel_hits(g, rs, hk, what)) {
        spm_rays_timing tr;
        spm_rays_replay_ref(g, rs, hr, &tr);
        for (size_t i = 0; i < rs->nclosest; i++) {
            float t;
            int want = spm_brute_intersect(g, rs->rays[i].o, rs->rays[i].d, rs->rays[i].skip, &t);
            bad += hk[i] != want;
            refbad += hr[i] != want;
            nhit += want >= 0;
        }
    }
    CHECK(bad == 0 && refbad == 0, "%s: kernel differs from brute force on %zu, reference on %zu "
          "of %zu rays", what, bad, refbad, rs->nclosest);
    free(hk);
    free(hr);
    return nhit;
}

static void build(spm_scene *s, spm_geometry *g, const char *what)
{
    spm_error err;
    int rc = spm_geometry_build(s, g, &err);
    CHECK(rc == 0, "%s: %s", what, err.msg);
    if (rc)
        exit(1);
}

/* NCOPIES copies of one triangle in the plane z = 0 among 40 scattered
 * triangles; the copies' indices after the BVH's reordering into *copy. */
static void tie_scene(spm_scene *s, spm_geometry *g, int copy[NCOPIES])
{
    ts_init(s);
    int m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.5), -1);
    const float a[3] = {-1, -1, 0}, b[3] = {1, -1, 0}, c[3] = {0, 1, 0};
    for (int k = 0; k < NCOPIES; k++)
        ts_tri(s, m, a, b, c);
    uint32_t seed = 5;
    for (int k = 0; k < 40; k++) {
        float x = 8 * frand(&seed) - 4, y = 8 * frand(&seed) - 4, z = 2 + 4 * frand(&seed);
        ts_tri(s, m, (float[]){x, y, z}, (float[]){x + 0.3f, y, z}, (float[]){x, y + 0.3f, z});
    }
    build(s, g, "tie scene");
    int n = 0;
    for (int i = 0; i < g->ntris && n < NCOPIES; i++)
        if (!memcmp(g->tris[i].v0, a, sizeof a) && !memcmp(g->tris[i].v1, b, sizeof b))
            copy[n++] = i; /* ascending: copy[0] is the lowest index */
    CHECK(n == NCOPIES, "found %d of the %d copies", n, NCOPIES);
}

/* At equal t the lowest index wins, in both backends, though the copies lie
 * in several leaves visited in either order. */
static void test_tie(void)
{
    spm_scene s;
    spm_geometry g;
    int copy[NCOPIES];
    tie_scene(&s, &g, copy);
    spm_rayset rs = {spm_xmalloc(64 * sizeof(spm_ray)), 64, 64};
    uint32_t seed = 9;
    for (int i = 0; i < 64; i++) {
        float u = 0.8f * frand(&seed), v = 0.8f * frand(&seed) * (1 - u);
        float p[3] = {-1 + 2 * u + v, -1 + 2 * v, 0}; /* inside the triangle */
        float o[3] = {4 * frand(&seed) - 2, 4 * frand(&seed) - 2, i % 2 ? -3.0f : 1.5f};
        rs.rays[i] = ray_to(o, p, SPM_RAY_CLOSEST);
    }
    int *hk = spm_xmalloc(rs.n * sizeof *hk), *hr = spm_xmalloc(rs.n * sizeof *hr);
    if (kernel_hits(&g, &rs, hk, "tie")) {
        spm_rays_timing tr;
        spm_rays_replay_ref(&g, &rs, hr, &tr);
        size_t kbad = 0, rbad = 0;
        for (size_t i = 0; i < rs.n; i++) {
            kbad += hk[i] != copy[0];
            rbad += hr[i] != copy[0];
        }
        CHECK(kbad == 0 && rbad == 0, "tie: %zu kernel and %zu reference answers of %zu are not "
              "the lowest copy %d (kernel ray 0: %d)", kbad, rbad, rs.n, copy[0], hk[0]);
    }
    /* the copies span leaves that are separate children somewhere */
    int leaves = 0;
    for (int k = 0; k < g.nnodes; k++)
        leaves += g.nodes[k].count > 0 && g.nodes[k].first <= (spm_u32)copy[NCOPIES - 1] &&
                  g.nodes[k].first + g.nodes[k].count > (spm_u32)copy[0];
    CHECK(leaves >= 3, "the copies lie in %d leaves", leaves);
    free(hk);
    free(hr);
    free(rs.rays);
    spm_geometry_free(&g);
    ts_free(&s);
}

/* Shadow rays through the any-hit loop: towards the lowest copy (lit: no
 * other triangle beats it), towards the highest (occluded by the lower
 * copies at the same t), and towards a scattered triangle behind another. */
static void test_shadow(void)
{
    spm_scene s;
    spm_geometry g;
    int copy[NCOPIES];
    tie_scene(&s, &g, copy);
    const int n = 96;
    spm_rayset rs = {spm_xmalloc(n * sizeof(spm_ray)), n, 0};
    uint32_t seed = 21;
    for (int i = 0; i < n; i++) {
        int kind = i % 3;
        spm_u32 ei = kind == 0 ? (spm_u32)copy[0] : kind == 1 ? (spm_u32)copy[NCOPIES - 1]
                                                              : (spm_u32)((i / 3) % g.ntris);
        const spm_tri *t = &g.tris[ei];
        float u = 0.2f + 0.5f * frand(&seed), v = 0.3f * (1 - u), p[3];
        for (int k = 0; k < 3; k++)
            p[k] = t->v0[k] + u * (t->v1[k] - t->v0[k]) + v * (t->v2[k] - t->v0[k]);
        float o[3] = {2 * frand(&seed) - 1, 2 * frand(&seed) - 1, -6};
        rs.rays[i] = ray_to(o, p, ei);
    }
    int *hk = spm_xmalloc(rs.n * sizeof *hk);
    if (kernel_hits(&g, &rs, hk, "shadow")) {
        size_t bad = 0, lowbad = 0, highbad = 0, nlit = 0, ndark = 0;
        for (int i = 0; i < n; i++) {
            float t;
            const spm_ray *r = &rs.rays[i];
            int want = lit(spm_brute_intersect(&g, r->o, r->d, r->skip, &t), r->emitter);
            int got = lit(hk[i], r->emitter);
            bad += got != want;
            lowbad += i % 3 == 0 && !got;
            highbad += i % 3 == 1 && got;
            want ? nlit++ : ndark++;
        }
        CHECK(bad == 0, "shadow: the kernel's verdict differs from brute force on %zu of %d", bad,
              n);
        CHECK(lowbad == 0 && highbad == 0, "shadow: %zu rays to the lowest copy occluded, %zu to "
              "the highest lit", lowbad, highbad);
        CHECK(nlit > n / 3 && ndark > n / 3, "shadow: %zu lit, %zu occluded", nlit, ndark);
    }
    free(hk);
    free(rs.rays);
    spm_geometry_free(&g);
    ts_free(&s);
}

/* Levels of the wide tree below node k. */
static int wide_depth(const spm_geometry *g, spm_u32 k)
{
    int d = 0;
    for (int i = 0; i < SPM_WIDE; i++) {
        spm_u32 c = g->wide[k].child[i];
        if (c != SPM_WIDE_EMPTY && !(c & SPM_WIDE_LEAF)) {
            int e = wide_depth(g, c);
            d = e > d ? e : d;
        }
    }
    return d + 1;
}

/* Leaves of the wide tree below node k holding more than SPM_LEAF_SCALAR
 * triangles (those the four-lane test takes). */
static int lane_leaves(const spm_geometry *g, spm_u32 k)
{
    int n = 0;
    for (int i = 0; i < SPM_WIDE; i++) {
        spm_u32 c = g->wide[k].child[i];
        if (c == SPM_WIDE_EMPTY)
            continue;
        if (c & SPM_WIDE_LEAF)
            n += (c & 3u) + 1u > SPM_LEAF_SCALAR;
        else
            n += lane_leaves(g, c);
    }
    return n;
}

/* Random rays from around the scene towards points on its triangles, and
 * some that miss everything; min_lane: leaves for the four-lane test it must have. */
static void degenerate_case_lanes(spm_scene *s, const char *what, int min_depth, int min_lane)
{
    spm_geometry g;
    build(s, &g, what);
    const int n = 256;
    spm_rayset rs = {spm_xmalloc(n * sizeof(spm_ray)), n, n};
    uint32_t seed = 77;
    for (int i = 0; i < n; i++) {
        const spm_tri *t = &g.tris[i % g.ntris];
        float u = frand(&seed), v = frand(&seed) * (1 - u), p[3], o[3];
        for (int k = 0; k < 3; k++) {
            p[k] = t->v0[k] + u * (t->v1[k] - t->v0[k]) + v * (t->v2[k] - t->v0[k]);
            o[k] = 6 * frand(&seed) - 3;
        }
        if (i % 8 == 7)
            p[0] += 50.0f; /* beside everything */
        rs.rays[i] = ray_to(o, p, SPM_RAY_CLOSEST);
    }
    size_t nhit = check_closest(&g, &rs, what);
    CHECK(nhit > n / 4 && nhit < (size_t)n, "%s: %zu of %d rays hit", what, nhit, n);
    int depth = g.nwide ? wide_depth(&g, 0) : 0;
    CHECK(depth >= min_depth, "%s: wide tree %d levels deep, want >= %d", what, depth, min_depth);
    int lanes = g.nwide ? lane_leaves(&g, 0) : 0;
    CHECK(lanes >= min_lane, "%s: %d leaves of 3 or 4 triangles, want >= %d", what, lanes, min_lane);
    free(rs.rays);
    spm_geometry_free(&g);
}

static void degenerate_case(spm_scene *s, const char *what, int min_depth)
{
    degenerate_case_lanes(s, what, min_depth, 0);
}

static void test_degenerate(void)
{
    spm_scene s;
    ts_init(&s);
    int m = ts_material(&s, ts_colour(&s, SPM_KIND_REFLECTANCE, 0.5), -1);
    ts_tri(&s, m, (float[]){-1, -1, 0}, (float[]){1, -1, 0.5f}, (float[]){0, 1, 0});
    degenerate_case(&s, "one triangle", 1);
    ts_tri(&s, m, (float[]){2, -1, 1}, (float[]){3, -1, 1}, (float[]){2, 1, 1});
    ts_tri(&s, m, (float[]){-2, 2, -1}, (float[]){-1, 2, -1}, (float[]){-2, 2, 1});
    degenerate_case(&s, "three triangles (a root of two children, a full and a half leaf)", 1);
    ts_free(&s);

    /* triangles halving in size and distance towards the origin: the SAH
     * splits one off at a time, a tree as deep as there are triangles / 2 */
    ts_init(&s);
    m = ts_material(&s, ts_colour(&s, SPM_KIND_REFLECTANCE, 0.5), -1);
    float x = 2.0f;
    for (int k = 0; k < 41; k++, x *= 0.5f)
        ts_tri(&s, m, (float[]){x, 0, 0}, (float[]){x * 1.5f, 0, x * 0.3f},
               (float[]){x, x * 0.4f, 0});
    degenerate_case(&s, "deep tree, 41 triangles", 7); /* 3 BVH2 levels a node, the last 4 a leaf */
    ts_free(&s);

    /* a gently bumpy 16 x 16 grid of quads: neighbours' boxes overlap, so the
     * SAH merges them into leaves of 3 and 4 and the rays exercise every lane
     * of the four-lane test (a lane left out fails the brute-force check) */
    ts_init(&s);
    m = ts_material(&s, ts_colour(&s, SPM_KIND_REFLECTANCE, 0.5), -1);
    for (int i = 0; i < 16; i++)
        for (int j = 0; j < 16; j++) {
            float x0 = -2 + i * 0.25f, x1 = x0 + 0.25f, y0 = -2 + j * 0.25f, y1 = y0 + 0.25f;
            float z00 = 0.1f * sinf(3 * x0) * cosf(2 * y0), z10 = 0.1f * sinf(3 * x1) * cosf(2 * y0);
            float z01 = 0.1f * sinf(3 * x0) * cosf(2 * y1), z11 = 0.1f * sinf(3 * x1) * cosf(2 * y1);
            ts_tri(&s, m, (float[]){x0, y0, z00}, (float[]){x1, y0, z10}, (float[]){x1, y1, z11});
            ts_tri(&s, m, (float[]){x0, y0, z00}, (float[]){x1, y1, z11}, (float[]){x0, y1, z01});
        }
    degenerate_case_lanes(&s, "bumpy grid, 512 triangles", 3, 32);
    ts_free(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 77;
    test_tie();
    test_shadow();
    test_degenerate();
    TEST_END();
}
