/* The normals `smooth` computes for a mesh without its own
 * (spm_mesh_smooth_normals), against closed forms: a tessellated unit
 * sphere's against its positions, a tessellated ellipsoid's (the statement's
 * non-uniform scale) against the gradient of its implicit equation, a cube's
 * against its face normals (every edge sharper than the crease), two faces
 * hinged either side of the crease angle, and triangles that carry their
 * own normals left as they are. */
#include "mesh.h"
#include "testutil.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* a UV sphere of `rings` x `segs` (poles single), counter-clockwise from outside */
static spm_mesh_data uv_sphere(int rings, int segs)
{
    spm_mesh_data d;
    memset(&d, 0, sizeof d);
    int nv = 2 + (rings - 1) * segs;
    float (*v)[3] = malloc((size_t)nv * sizeof *v);
    v[0][0] = 0, v[0][1] = 1, v[0][2] = 0;
    for (int i = 1; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double th = M_PI * i / rings, ph = 2 * M_PI * j / segs;
            float *p = v[1 + (i - 1) * segs + j];
            p[0] = (float)(sin(th) * cos(ph));
            p[1] = (float)cos(th);
            p[2] = (float)(-sin(th) * sin(ph));
        }
    v[nv - 1][0] = 0, v[nv - 1][1] = -1, v[nv - 1][2] = 0;
    d.ntris = (uint64_t)segs * 2 * (rings - 1);
    d.tris = calloc(d.ntris, sizeof *d.tris);
    uint64_t t = 0;
#define RING(i, j) (1 + ((i) - 1) * segs + (j) % segs)
#define TRI(a, b, c)                                                                          \
    do {                                                                                      \
        memcpy(d.tris[t].p[0], v[a], 12);                                                     \
        memcpy(d.tris[t].p[1], v[b], 12);                                                     \
        memcpy(d.tris[t].p[2], v[c], 12);                                                     \
        t++;                                                                                  \
    } while (0)
    for (int j = 0; j < segs; j++) {
        TRI(0, RING(1, j), RING(1, j + 1));
        for (int i = 1; i < rings - 1; i++) {
            TRI(RING(i, j), RING(i + 1, j), RING(i + 1, j + 1));
            TRI(RING(i, j), RING(i + 1, j + 1), RING(i, j + 1));
        }
        TRI(RING(rings - 1, j), nv - 1, RING(rings - 1, j + 1));
    }
    free(v);
    return d;
}

static void identity(double m[3][4])
{
    memset(m, 0, 12 * sizeof(double));
    m[0][0] = m[1][1] = m[2][2] = 1;
}

/* the angle in degrees between a and b */
static double angle(const double a[3], const double b[3])
{
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = dot / (la * lb);
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * (180.0 / M_PI);
}

/* The sphere scaled by (a, b, c): the scene normal of a corner, M^-T q (as
 * spm_mesh_add maps a file normal), against the ellipsoid's, (x/a, y/b, z/c)
 * at file point (x, y, z). Returns the largest angle, in degrees. */
static double sphere_error(int rings, int segs, const double s[3], double crease)
{
    spm_mesh_data d = uv_sphere(rings, segs);
    double m[3][4];
    identity(m);
    for (int i = 0; i < 3; i++)
        m[i][i] = s[i];
    uint64_t made;
    spm_mesh_normals *n = spm_mesh_smooth_normals(&d, m, crease, &made);
    CHECK(n && made == d.ntris, "the sphere's %llu triangles all get normals (%llu)",
          (unsigned long long)d.ntris, (unsigned long long)made);
    double worst = 0;
    for (uint64_t t = 0; n && t < d.ntris; t++)
        for (int v = 0; v < 3; v++) {
            const float *p = d.tris[t].p[v], *q = n[t].n[v];
            double got[3], want[3];
            for (int i = 0; i < 3; i++) {
                got[i] = q[i] / s[i];
                want[i] = p[i] / s[i];
            }
            worst = fmax(worst, angle(got, want));
        }
    free(n);
    free(d.tris);
    return worst;
}

/* a unit cube's 12 triangles, counter-clockwise from outside */
static spm_mesh_data cube(void)
{
    static const int face[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                   {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    spm_mesh_data d;
    memset(&d, 0, sizeof d);
    d.ntris = 12;
    d.tris = calloc(12, sizeof *d.tris);
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 2; k++)
            for (int v = 0; v < 3; v++) {
                int c = face[f][v == 0 ? 0 : k + 3 - v]; /* the lists wind inwards */
                for (int i = 0; i < 3; i++)
                    d.tris[2 * f + k].p[v][i] = (float)((c >> (2 - i)) & 1);
            }
    return d;
}

static void face_normal(const spm_mesh_tri *t, double n[3])
{
    double a[3], b[3];
    for (int i = 0; i < 3; i++) {
        a[i] = t->p[1][i] - t->p[0][i];
        b[i] = t->p[2][i] - t->p[0][i];
    }
    n[0] = a[1] * b[2] - a[2] * b[1];
    n[1] = a[2] * b[0] - a[0] * b[2];
    n[2] = a[0] * b[1] - a[1] * b[0];
}

/* the largest angle between a corner's normal and its face's */
static double cube_error(double crease)
{
    spm_mesh_data d = cube();
    double m[3][4];
    identity(m);
    uint64_t made;
    spm_mesh_normals *n = spm_mesh_smooth_normals(&d, m, crease, &made);
    double worst = 0;
    for (uint64_t t = 0; n && t < 12; t++) {
        double f[3];
        face_normal(&d.tris[t], f);
        CHECK(f[0] * (d.tris[t].p[0][0] - 0.5) + f[1] * (d.tris[t].p[0][1] - 0.5) +
                  f[2] * (d.tris[t].p[0][2] - 0.5) > 0, "cube triangle %llu faces out",
              (unsigned long long)t);
        for (int v = 0; v < 3; v++) {
            double q[3] = {n[t].n[v][0], n[t].n[v][1], n[t].n[v][2]};
            worst = fmax(worst, angle(q, f));
        }
    }
    free(n);
    free(d.tris);
    return worst;
}

/* Two triangles sharing the edge (0 0 0)-(0 0 1), their faces `deg` apart:
 * the shared corners' normals, joined or not under the crease. 1 joined. */
static int hinge_joined(double deg, double crease)
{
    spm_mesh_data d;
    memset(&d, 0, sizeof d);
    d.ntris = 2;
    d.tris = calloc(2, sizeof *d.tris);
    double a = deg * (M_PI / 180.0);
    const float t0[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    const float t1[3][3] = {{0, 0, 0}, {0, 0, 1}, {(float)-cos(a), (float)sin(a), 0}};
    memcpy(d.tris[0].p, t0, sizeof t0);
    memcpy(d.tris[1].p, t1, sizeof t1);
    double m[3][4];
    identity(m);
    uint64_t made;
    spm_mesh_normals *n = spm_mesh_smooth_normals(&d, m, crease, &made);
    double f0[3], f1[3], q0[3], q1[3];
    face_normal(&d.tris[0], f0);
    face_normal(&d.tris[1], f1);
    CHECK(fabs(angle(f0, f1) - deg) < 1e-4, "the hinge's faces are %g degrees apart", deg);
    for (int i = 0; i < 3; i++) {
        q0[i] = n[0].n[0][i]; /* (0 0 0) in each */
        q1[i] = n[1].n[0][i];
    }
    int joined = angle(q0, q1) < 1e-4;
    CHECK(joined || (angle(q0, f0) < 1e-4 && angle(q1, f1) < 1e-4),
          "split corners keep their faces' normals");
    free(n);
    free(d.tris);
    return joined;
}

/* triangles with their own normals keep them; the others get computed ones */
static void check_own_normals(void)
{
    spm_mesh_data d = uv_sphere(8, 16);
    d.normals = calloc(d.ntris, sizeof *d.normals);
    for (int v = 0; v < 3; v++)
        d.normals[5].n[v][1] = 7.0f; /* any non-zero normal, kept as it is */
    double m[3][4];
    identity(m);
    uint64_t made;
    spm_mesh_normals *n = spm_mesh_smooth_normals(&d, m, 60, &made);
    CHECK(n && made == d.ntris - 1, "all but the triangle with normals: %llu",
          (unsigned long long)made);
    CHECK(n && !memcmp(&n[5], &d.normals[5], sizeof n[5]), "its own normals are kept");
    CHECK(n && n[6].n[0][0] != 0, "a triangle without gets some");
    free(n);
    for (uint64_t t = 0; t < d.ntris; t++)
        for (int v = 0; v < 3; v++)
            d.normals[t].n[v][0] = 1.0f;
    CHECK(!spm_mesh_smooth_normals(&d, m, 60, &made) && made == 0,
          "every triangle has its own: nothing computed");
    free(d.normals);
    free(d.tris);
}

int main(void)
{
    /* Measured: the 8 x 16 UV sphere (the facets of the bundled test sphere,
     * 22.5 degrees round and 22.5 along a meridian) 1.27 degrees off the
     * radius, where a quad's diagonal makes a vertex's fan lopsided; the
     * ellipsoid (scale 1 2 0.5) 4.33; on a 32 x 64 tessellation 0.55: the
     * error is the tessellation's, shrinking with the facets. Bounds 2, 6, 1.
     * Shown failing: an unweighted sum is 2.59, 3.81 and 1.47 off (and the
     * cube's corner 65.9 from a face); the scene normal returned without
     * M^T, 1.27, 29.6 and 35.5. */
    const double unit[3] = {1, 1, 1}, ell[3] = {1, 2, 0.5};
    double e = sphere_error(8, 16, unit, 60);
    printf("8 x 16 sphere: %.3g degrees\n", e);
    CHECK(e < 2, "the smoothed sphere's normals are near its radii: %g degrees off", e);
    e = sphere_error(8, 16, ell, 60);
    printf("8 x 16 ellipsoid: %.3g degrees\n", e);
    CHECK(e < 6, "the smoothed ellipsoid's normals: %g degrees off", e);
    e = sphere_error(32, 64, ell, 60);
    printf("32 x 64 ellipsoid: %.3g degrees\n", e);
    CHECK(e < 1, "the finer ellipsoid's normals: %g degrees off", e);
    e = sphere_error(8, 16, unit, 10);
    printf("8 x 16 sphere, crease 10: %.3g degrees\n", e);
    CHECK(e > 5, "under a crease of 10 degrees the sphere stays faceted: %g degrees off", e);

    e = cube_error(60);
    printf("cube, crease 60: %.3g degrees\n", e);
    CHECK(e < 1e-5, "the cube keeps its faces' normals: %g degrees off", e);
    e = cube_error(120);
    printf("cube, crease 120: %.3g degrees\n", e);
    CHECK(fabs(e - 54.7356) < 0.01, "a crease above 90 rounds the cube's corners: %g "
                                    "(the diagonal's 54.7356 from a face)", e);

    CHECK(hinge_joined(59, 60), "faces 59 degrees apart join under a crease of 60");
    CHECK(!hinge_joined(61, 60), "faces 61 degrees apart keep their edge under 60");
    CHECK(hinge_joined(89, 90) && !hinge_joined(91, 90), "the crease of 90 splits at 90");
    check_own_normals();
    TEST_END();
}
