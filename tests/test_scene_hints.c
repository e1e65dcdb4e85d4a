/* The closed-mesh test behind the camera-inside hint: closed and open meshes
 * (a tetrahedron, a torus grid, a bipyramid whose apexes have more edges than
 * the insertion sort takes, two-sided triangles: the most vertices a closed
 * mesh can have, past the position table's first size), an edge shared by
 * four faces, a corner written as -0, and the order of the triangles not
 * mattering. */
#include "scene_hints.h"
#include "testutil.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static void tri(spm_scene_tri *t, const float *a, const float *b, const float *c)
{
    memset(t, 0, sizeof *t);
    memcpy(t->p[0], a, sizeof t->p[0]);
    memcpy(t->p[1], b, sizeof t->p[1]);
    memcpy(t->p[2], c, sizeof t->p[2]);
}

/* A torus of nu x nv quads, two triangles each: closed, 2 nu nv triangles. */
static spm_scene_tri *torus(int nu, int nv, int *n)
{
    *n = 2 * nu * nv;
    spm_scene_tri *t = malloc((size_t)*n * sizeof *t);
    float (*p)[3] = malloc((size_t)nu * nv * sizeof *p);
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            p[i * nv + j][0] = (float)((2 + cos(v)) * cos(u));
            p[i * nv + j][1] = (float)((2 + cos(v)) * sin(u));
            p[i * nv + j][2] = (float)sin(v);
        }
    for (int i = 0, k = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int a = i * nv + j, b = (i + 1) % nu * nv + j, c = (i + 1) % nu * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
            tri(&t[k++], p[a], p[b], p[c]);
            tri(&t[k++], p[a], p[c], p[d]);
        }
    free(p);
    return t;
}

/* A bipyramid of 2 * sides faces about the z axis: its apexes have `sides` edges each. */
static spm_scene_tri *bipyramid(int sides, int *n)
{
    *n = 2 * sides;
    spm_scene_tri *t = malloc((size_t)*n * sizeof *t);
    const float top[3] = {0, 0, 1}, bottom[3] = {0, 0, -1};
    for (int i = 0; i < sides; i++) {
        float a[3] = {(float)cos(2 * M_PI * i / sides), (float)sin(2 * M_PI * i / sides), 0};
        float b[3] = {(float)cos(2 * M_PI * (i + 1) / sides),
                      (float)sin(2 * M_PI * (i + 1) / sides), 0};
        if (i + 1 == sides)
            b[0] = 1, b[1] = 0;
        tri(&t[2 * i], top, a, b);
        tri(&t[2 * i + 1], bottom, b, a);
    }
    return t;
}

/* m separate triangles, each twice (the second reversed): closed, 3m vertices for 2m faces. */
static spm_scene_tri *two_sided(int m, int *n)
{
    *n = 2 * m;
    spm_scene_tri *t = malloc((size_t)*n * sizeof *t);
    for (int i = 0; i < m; i++) {
        float a[3] = {(float)i, 0, 0}, b[3] = {(float)i + 0.5f, 0, 0}, c[3] = {(float)i, 1, 0};
        tri(&t[2 * i], a, b, c);
        tri(&t[2 * i + 1], a, c, b);
    }
    return t;
}

int main(void)
{
    const float v[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
    spm_scene_tri t[8];
    tri(&t[0], v[0], v[2], v[1]);
    tri(&t[1], v[0], v[1], v[3]);
    tri(&t[2], v[0], v[3], v[2]);
    tri(&t[3], v[1], v[2], v[3]);
    CHECK(spm_tris_closed(t, 4), "a tetrahedron is closed");
    CHECK(!spm_tris_closed(t, 3), "three of its faces are open");
    /* a second tetrahedron on the edge v0-v1 (same edge, four faces) */
    memcpy(t + 4, t, 4 * sizeof *t);
    for (int k = 4; k < 8; k++)
        for (int c = 0; c < 3; c++)
            if (!memcmp(t[k].p[c], v[2], sizeof v[2]))
                memcpy(t[k].p[c], v[4], sizeof v[4]);
    CHECK(spm_tris_closed(t + 4, 4), "the second tetrahedron alone is closed");
    CHECK(!spm_tris_closed(t, 8), "two tetrahedra sharing an edge: four faces on it");
    CHECK(spm_tris_unpaired_edges(t, 4) == 0, "a tetrahedron: no unpaired edge");
    CHECK(spm_tris_unpaired_edges(t, 3) == 3, "three faces: the missing face's 3 edges (%ld)",
          spm_tris_unpaired_edges(t, 3));
    /* the two share the face v0 v1 v3 (t[1] and t[5]): its three edges have four faces */
    CHECK(spm_tris_unpaired_edges(t, 8) == 3, "a shared face: its 3 edges on four faces (%ld)",
          spm_tris_unpaired_edges(t, 8));
    CHECK(spm_tris_unpaired_edges(t, 1) == 3, "one triangle: its 3 edges");
    /* -0 is the same position as +0 */
    t[1].p[0][0] = -0.0f;
    CHECK(spm_tris_closed(t, 4), "a corner at -0 joins its neighbours at +0");
    t[1].p[0][0] = 1e-30f;
    CHECK(!spm_tris_closed(t, 4), "a corner moved by 1e-30 does not");

    int n;
    spm_scene_tri *g = torus(400, 300, &n); /* 120000 vertices */
    CHECK(spm_tris_closed(g, n), "a torus of %d triangles is closed", n);
    for (int k = 0; k < n / 2; k++) { /* reversed order */
        spm_scene_tri s = g[k];
        g[k] = g[n - 1 - k];
        g[n - 1 - k] = s;
    }
    CHECK(spm_tris_closed(g, n), "the torus in reverse order is closed");
    CHECK(!spm_tris_closed(g + 1, n - 1), "the torus less one triangle is open");
    CHECK(spm_tris_unpaired_edges(g + 2, n - 2) == 4 || spm_tris_unpaired_edges(g + 2, n - 2) == 6,
          "the torus less two triangles: a quad's hole of 4 edges, or two of 3 (%ld)",
          spm_tris_unpaired_edges(g + 2, n - 2));
    g[n / 2].p[1][2] = nextafterf(g[n / 2].p[1][2], 2.0f);
    CHECK(!spm_tris_closed(g, n), "the torus with one corner moved by an ulp is open");
    free(g);
    g = torus(12, 10, &n); /* 120 vertices */
    CHECK(spm_tris_closed(g, n), "a torus of %d triangles is closed", n);
    CHECK(!spm_tris_closed(g, n - 1), "the small torus less one triangle is open");
    free(g);
    g = bipyramid(100, &n);
    CHECK(spm_tris_closed(g, n), "a bipyramid of %d faces is closed", n);
    CHECK(!spm_tris_closed(g + 1, n - 1), "the bipyramid less one face is open");
    free(g);
    g = two_sided(5000, &n); /* 15000 vertices: more than a table of 16384 slots holds at half load */
    CHECK(spm_tris_closed(g, n), "%d two-sided triangles are closed", n / 2);
    CHECK(!spm_tris_closed(g, n - 1), "less one side, open");
    g[2 * 4000].p[2][1] = 2; /* one triangle's third corner moved on both sides */
    g[2 * 4000 + 1].p[1][1] = 2;
    CHECK(spm_tris_closed(g, n), "still closed with a corner moved on both sides");
    g[2 * 4000 + 1].p[1][1] = 3;
    CHECK(!spm_tris_closed(g, n), "open with it moved on one side only");
    for (int k = 0; k < n; k += 2) /* one side each: 3m vertices for m faces */
        g[k / 2] = g[k];
    CHECK(!spm_tris_closed(g, n / 2), "a soup of %d triangles is open", n / 2);
    CHECK(spm_tris_unpaired_edges(g, n / 2) == 3L * (n / 2), "a soup: every edge unpaired (%ld)",
          spm_tris_unpaired_edges(g, n / 2));
    free(g);
    TEST_END();
}
