/* The tangents made for normal maps (geometry.h spm_tangents_make) against
 * frames worked out by hand: dP/du of a triangle whose (u, v) are its
 * positions, mirrored (handedness -1) and turned a quarter; a tangent made
 * perpendicular to a tilted vertex normal; two faces meeting at a vertex
 * whose tangents differ, averaged by their corner angles (90 and 45
 * degrees), and the fold of a box's edge; a triangle without (u, v)
 * variation gets some unit tangent perpendicular to its normal. */
#include "geometry.h"
#include "testutil.h"
#include <math.h>
#include <string.h>

#define TOL 1e-6

static spm_tangent_in tri(const float p[3][3], const float n[3], const float uv[3][2])
{
    spm_tangent_in t;
    memcpy(t.p, p, sizeof t.p);
    memcpy(t.uv, uv, sizeof t.uv);
    for (int v = 0; v < 3; v++)
        memcpy(t.n[v], n, sizeof t.n[v]);
    return t;
}

static void expect(const float got[4], double x, double y, double z, double w, const char *what)
{
    CHECK(fabs(got[0] - x) < TOL && fabs(got[1] - y) < TOL && fabs(got[2] - z) < TOL &&
              got[3] == (float)w,
          "%s: tangent (%g %g %g, %g), want (%g %g %g, %g)", what, got[0], got[1], got[2],
          got[3], x, y, z, w);
}

static void test_single(void)
{
    const float p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, z[3] = {0, 0, 1};
    const float plain[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const float mirror[3][2] = {{1, 0}, {0, 0}, {1, 1}};   /* u = 1 - x, v = y */
    const float quarter[3][2] = {{0, 0}, {0, 1}, {-1, 0}}; /* u = -y, v = x */
    spm_tangent_in in[3] = {tri(p, z, plain), tri(p, z, mirror), tri(p, z, quarter)};
    float out[3][12];
    for (int i = 0; i < 3; i++) /* each alone: plain's and quarter's first corners are one vertex */
        spm_tangents_make(&in[i], 1, &out[i]);
    for (int v = 0; v < 3; v++) {
        /* T = dP/du = +x; B = dP/dv = +y = z x T: +1 */
        expect(out[0] + 4 * v, 1, 0, 0, 1, "plain");
        /* T = -x; B = +y, z x T = -y: -1 */
        expect(out[1] + 4 * v, -1, 0, 0, -1, "mirrored");
        /* T = -y; B = +x = z x (-y): +1 */
        expect(out[2] + 4 * v, 0, -1, 0, 1, "quarter turn");
    }
}

/* vertex normals leaning 45 degrees towards +x: T = x - n (n.x) made unit */
static void test_tilted(void)
{
    const float p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const float uv[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const float n[3] = {1, 0, 1}; /* not unit: the maker normalises */
    spm_tangent_in in = tri(p, n, uv);
    float out[1][12];
    spm_tangents_make(&in, 1, out);
    double a = sqrt(0.5);
    for (int v = 0; v < 3; v++) /* (1 0 0) - (a 0 a) a = (1/2 0 -1/2): unit (a 0 -a); n x T = +y */
        expect(out[0] + 4 * v, a, 0, -a, 1, "tilted normal");
}

/* Two faces around the origin (normal +z, (u, v) (0, 0) there): the first
 * with u = x (T = +x, corner angle 90 degrees), the second with u = x + y,
 * v = y - x (T = (1 1 0) / sqrt 2, corner 45 degrees): at the origin
 * T = unit(pi/2 (1 0 0) + pi/4 (a a 0)); elsewhere each face's own. */
static void test_weighted(void)
{
    const float p1[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, uv1[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const float p2[3][3] = {{0, 0, 0}, {-1, 0, 0}, {-1, -1, 0}};
    const float uv2[3][2] = {{0, 0}, {-1, 1}, {-2, 0}}, z[3] = {0, 0, 1};
    spm_tangent_in in[2] = {tri(p1, z, uv1), tri(p2, z, uv2)};
    float out[2][12];
    spm_tangents_make(in, 2, out);
    double a = sqrt(0.5), x = M_PI / 2 + M_PI / 4 * a, y = M_PI / 4 * a, l = hypot(x, y);
    expect(out[0], x / l, y / l, 0, 1, "origin, first face");
    expect(out[1], x / l, y / l, 0, 1, "origin, second face");
    expect(out[0] + 4, 1, 0, 0, 1, "first face's own vertex");
    expect(out[1] + 4, a, a, 0, 1, "second face's own vertex");
}

/* A box's edge along y: the top (z = 0, x 0..1, normal +z) with u = x and
 * the side (x = 0, z -1..0, normal -x) with u = z, one normal (-a 0 a) on
 * the edge: both faces' tangents project to (a 0 a) there. */
static void test_fold(void)
{
    double a = sqrt(0.5);
    const float top[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const float side[3][3] = {{0, 0, 0}, {0, 1, 0}, {0, 0, -1}};
    const float uvt[3][2] = {{0, 0}, {1, 0}, {0, 1}}, uvs[3][2] = {{0, 0}, {0, 1}, {-1, 0}};
    const float e[3] = {(float)-a, 0, (float)a};
    spm_tangent_in in[2] = {tri(top, e, uvt), tri(side, e, uvs)};
    float out[2][12];
    spm_tangents_make(in, 2, out);
    expect(out[0], a, 0, a, 1, "fold, top face");
    expect(out[1], a, 0, a, 1, "fold, side face");
}

static void test_degenerate(void)
{
    const float p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, n[3] = {0, 0.6f, 0.8f};
    const float uv[3][2] = {{0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}};
    spm_tangent_in in = tri(p, n, uv);
    float out[1][12];
    spm_tangents_make(&in, 1, out);
    const float *t = out[0];
    double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]), dn = t[1] * 0.6 + t[2] * 0.8;
    CHECK(fabs(len - 1) < TOL && fabs(dn) < TOL && isfinite(t[3]),
          "no (u, v) variation: tangent (%g %g %g) not unit and perpendicular", t[0], t[1], t[2]);
}

int main(void)
{
    test_single();
    test_tilted();
    test_weighted();
    test_fold();
    test_degenerate();
    TEST_END();
}
