/* The quantised wide BVH (host/geometry/bvh_quant.c): every child's box lies
 * inside its dequantised box, computed as the kernel computes it, on random
 * and adversarial boxes (tiny, huge, far from the origin, flat, subnormal),
 * and the codes are the tightest such (so a quantiser that gave up, 0 and
 * 255, would fail). The check itself is shown able to fail: a quantiser that
 * rounds to nearest, written here, breaks containment on the same boxes.
 * Then whole trees: spm_bvhq_build mirrors the wide tree node for node, its
 * leaves and planes unchanged. */
#include <float.h>
#include <stdlib.h>
#include <string.h>
#include "bvh_quant.h"
#include "testutil.h"

static unsigned long long rng_state = 88172645463325252ULL;
static double rnd(void)
{
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

/* Four children's boxes on one axis (n of them used). */
typedef struct {
    float lo[4], hi[4];
    int n;
    const char *what;
} axis_case;

/* The rounding to nearest a careless quantiser would use. */
static void codes_nearest(float o, float s, float lo, float hi, unsigned char *ql,
                          unsigned char *qh)
{
    double a = nearbyint(((double)lo - o) / s), b = nearbyint(((double)hi - o) / s);
    *ql = (unsigned char)(a < 0 ? 0 : a > 255 ? 255 : a);
    *qh = (unsigned char)(b < 0 ? 0 : b > 255 ? 255 : b);
}

typedef void (*codes_fn)(float, float, float, float, unsigned char *, unsigned char *);

/* Children whose true box escapes their dequantised one; with tight, also
 * checks that no code could move inward, the scale a power of two. */
static int escapes(const axis_case *c, codes_fn codes, int tight)
{
    float l = INFINITY, h = -INFINITY;
    for (int i = 0; i < c->n; i++) {
        l = c->lo[i] < l ? c->lo[i] : l;
        h = c->hi[i] > h ? c->hi[i] : h;
    }
    float o, s;
    if (spm_bvhq_axis(l, h, &o, &s)) {
        CHECK(0, "%s: no frame for [%g, %g]", c->what, l, h);
        return 0;
    }
    int bad = 0;
    for (int i = 0; i < c->n; i++) {
        unsigned char ql, qh;
        codes(o, s, c->lo[i], c->hi[i], &ql, &qh);
        float fl = spm_bvhq_face(o, s, ql), fh = spm_bvhq_face(o, s, qh);
        bad += !(fl <= c->lo[i] && fh >= c->hi[i]);
        if (!tight)
            continue;
        int e;
        CHECK(frexpf(s, &e) == 0.5f, "%s: scale %g not a power of two", c->what, s);
        CHECK(ql == 255 || spm_bvhq_face(o, s, ql + 1u) > c->lo[i],
              "%s: child %d lower code %u not the tightest", c->what, i, ql);
        CHECK(qh == 0 || spm_bvhq_face(o, s, qh - 1u) < c->hi[i],
              "%s: child %d upper code %u not the tightest", c->what, i, qh);
        if (fl > c->lo[i] || fh < c->hi[i])
            fprintf(stderr, "%s: child %d [%.9g, %.9g] escapes [%.9g, %.9g] (codes %u %u, "
                    "origin %.9g, scale %g)\n", c->what, i, c->lo[i], c->hi[i], fl, fh, ql, qh,
                    o, s);
    }
    return bad;
}

/* A case of n children: centre base, spread of centres `spread`, sizes up to `size`
 * (size 0: flat). */
static axis_case make_case(const char *what, double base, double spread, double size, int n)
{
    axis_case c = {.n = n, .what = what};
    for (int i = 0; i < n; i++) {
        double m = base + (rnd() - 0.5) * spread, r = rnd() * size;
        c.lo[i] = (float)(m - r);
        c.hi[i] = (float)(m + r);
        if (c.hi[i] < c.lo[i])
            c.hi[i] = c.lo[i];
    }
    return c;
}

/* n children whose bounds are origin + k ulps, k random below `ulps`. */
static axis_case ulp_case(const char *what, float base, int ulps, int n)
{
    axis_case c = {.n = n, .what = what};
    for (int i = 0; i < n; i++) {
        float a = base, b;
        for (int k = (int)(rnd() * ulps); k > 0; k--)
            a = nextafterf(a, INFINITY);
        b = a;
        for (int k = (int)(rnd() * ulps); k > 0; k--)
            b = nextafterf(b, INFINITY);
        c.lo[i] = a, c.hi[i] = b;
    }
    return c;
}

static void test_boxes(void)
{
    static const struct {
        const char *what;
        double base, spread, size;
    } kinds[] = {
        {"unit", 0.0, 2.0, 0.5},        {"tiny", 1e-3, 1e-30, 1e-31},
        {"subnormal", 0.0, 1e-39, 1e-40}, {"huge", 0.0, 1e30, 1e29},
        {"huger", 0.0, 1e38, 1e37},     {"far", 1e7, 1.0, 0.3},
        {"far, small", -3e6, 1e-2, 1e-3}, {"flat", 5.0, 0.0, 0.0},
        {"flat, spread", 5.0, 4.0, 0.0}, {"wide and thin", 0.0, 1e6, 1e-4},
    };
    int caught = 0, cases = 0;
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++)
        for (int rep = 0; rep < 2000; rep++) {
            axis_case c = make_case(kinds[k].what, kinds[k].base, kinds[k].spread, kinds[k].size,
                                    1 + rep % 4);
            CHECK(escapes(&c, spm_bvhq_codes, 1) == 0, "%s: a box escapes", c.what);
            caught += escapes(&c, codes_nearest, 0) > 0;
            cases++;
        }
    static const float ulp_bases[] = {1.0f, -1.0f, 1e7f, 3.3e-38f, 1e-45f, 0.0f, 6e37f};
    for (size_t k = 0; k < sizeof ulp_bases / sizeof *ulp_bases; k++)
        for (int rep = 0; rep < 2000; rep++) {
            axis_case c = ulp_case("ulps", ulp_bases[k], 1 + rep % 700, 2 + rep % 3);
            CHECK(escapes(&c, spm_bvhq_codes, 1) == 0, "ulps from %g: a box escapes",
                  ulp_bases[k]);
            caught += escapes(&c, codes_nearest, 0) > 0;
            cases++;
        }
    /* a child exactly the frame, and one of the frame's ends alone */
    axis_case edge = {{-1e20f, -1e20f, 3.0f, 0.0f}, {7e19f, -1e20f, 7e19f, 0.0f}, 3, "ends"};
    CHECK(escapes(&edge, spm_bvhq_codes, 1) == 0, "frame's ends");
    printf("to-nearest rounding escapes in %d of %d cases\n", caught, cases);
    CHECK(caught > cases / 10, "the check sees a to-nearest quantiser (%d of %d)", caught, cases);
    /* beyond 8 bits of any finite power of two: refused, not wrapped */
    float o, s;
    CHECK(spm_bvhq_axis(-FLT_MAX, FLT_MAX, &o, &s) == 1, "an extent beyond 2^128 is refused");
    CHECK(spm_bvhq_axis(-1e38f, 1e38f, &o, &s) == 0 && spm_bvhq_face(o, s, 255) >= 1e38f,
          "an extent of 2e38 fits");
}

/* n triangles of size `size` scattered over a cube of side `side` at `at`. */
static spm_geometry mesh(int n, double at, double side, double size)
{
    spm_geometry g;
    memset(&g, 0, sizeof g);
    g.ntris = n;
    g.tris = calloc((size_t)n, sizeof *g.tris);
    g.cam.eye[2] = (float)(at - side);
    for (int i = 0; i < n; i++) {
        spm_tri *t = &g.tris[i];
        for (int k = 0; k < 3; k++) {
            double c = at + (rnd() - 0.5) * side;
            t->v0[k] = (float)c;
            t->v1[k] = (float)(c + (rnd() - 0.5) * size);
            t->v2[k] = (float)(c + (rnd() - 0.5) * size);
        }
        t->vn = (spm_u32)i;
    }
    return g;
}

/* The quantised tree against the wide one it was made from, node for node:
 * the same leaves, interior children at the mapped slots, every child's box
 * inside its dequantised box, the planes copied. Returns boxes escaping. */
static int compare_trees(const spm_geometry *g, const spm_bvhq_node *q, size_t nq, const char *what)
{
    size_t pbytes = SPM_LEAF_PLANES_FLOATS((size_t)g->ntris) * sizeof(float);
    spm_u32 wp = (spm_u32)((pbytes + sizeof(spm_bvh4_node) - 1) / sizeof(spm_bvh4_node));
    spm_u32 qp = (spm_u32)((pbytes + sizeof(spm_bvhq_node) - 1) / sizeof(spm_bvhq_node));
    CHECK(nq == 1 + qp + ((size_t)g->nwide - 1 - wp), "%s: %zu slots", what, nq);
    CHECK(!memcmp(&q[1], &g->wide[1], pbytes), "%s: the leaf planes copied", what);
    int bad = 0, wrong = 0;
    for (spm_u32 k = 0; k < (spm_u32)g->nwide; k = k ? k + 1 : 1 + wp) {
        const spm_bvh4_node *w = &g->wide[k];
        const spm_bvhq_node *n = &q[k ? k - wp + qp : 0];
        const float *lo[3] = {w->bmin_x, w->bmin_y, w->bmin_z};
        const float *hi[3] = {w->bmax_x, w->bmax_y, w->bmax_z};
        const unsigned char *ql[3] = {n->qlo_x, n->qlo_y, n->qlo_z};
        const unsigned char *qh[3] = {n->qhi_x, n->qhi_y, n->qhi_z};
        for (int i = 0; i < SPM_WIDE; i++) {
            spm_u32 c = w->child[i];
            spm_u32 want = (c == SPM_WIDE_EMPTY || (c & SPM_WIDE_LEAF)) ? c : c - wp + qp;
            wrong += n->child[i] != want;
            if (c == SPM_WIDE_EMPTY)
                continue;
            for (int a = 0; a < 3; a++)
                bad += !(spm_bvhq_face(n->origin[a], n->scale[a], ql[a][i]) <= lo[a][i] &&
                         spm_bvhq_face(n->origin[a], n->scale[a], qh[a][i]) >= hi[a][i]);
        }
    }
    CHECK(wrong == 0, "%s: %d children at the wrong slot", what, wrong);
    return bad;
}

static void test_trees(void)
{
    static const struct {
        const char *what;
        int n;
        double at, side, size;
    } kinds[] = {
        {"soup", 3000, 0.0, 2.0, 0.1},       {"far soup", 3000, 1e6, 10.0, 0.5},
        {"tiny soup", 2000, 0.0, 1e-20, 1e-22}, {"huge soup", 2000, 0.0, 1e30, 1e28},
        {"one triangle", 1, 3.0, 1.0, 1.0},  {"slivers", 2000, -4e4, 3.0, 1e-6},
    };
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++) {
        spm_geometry g = mesh(kinds[k].n, kinds[k].at, kinds[k].side, kinds[k].size);
        spm_error err;
        if (spm_bvh_build_threads(&g, 1, &err)) {
            CHECK(0, "%s: BVH build: %s", kinds[k].what, err.msg);
            spm_geometry_free(&g);
            continue;
        }
        spm_bvhq_node *q;
        size_t nq;
        CHECK(spm_bvhq_build(&g, &q, &nq, &err) == 0, "%s: quantised build", kinds[k].what);
        CHECK(nq > 0 && (size_t)g.nwide * sizeof(spm_bvh4_node) > nq * sizeof *q,
              "%s: smaller than the wide tree (%zu against %d slots)", kinds[k].what, nq, g.nwide);
        CHECK(compare_trees(&g, q, nq, kinds[k].what) == 0, "%s: a child box escapes",
              kinds[k].what);
        free(q);
        spm_geometry_free(&g);
    }
}

int main(void)
{
    test_boxes();
    test_trees();
    TEST_END();
}
