/* The closed-mesh test behind the camera-inside hint: closed and open meshes
 * (a tetrahedron, a torus grid large enough that vertex numbers take several
 * radix passes), an edge shared by four faces, a corner written as -0, and the
 * order of the triangles not mattering. */
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
    /* -0 is the same position as +0 */
    t[1].p[0][0] = -0.0f;
    CHECK(spm_tris_closed(t, 4), "a corner at -0 joins its neighbours at +0");
    t[1].p[0][0] = 1e-30f;
    CHECK(!spm_tris_closed(t, 4), "a corner moved by 1e-30 does not");

    int n;
    spm_scene_tri *g = torus(400, 300, &n); /* 120000 vertices: 17-bit ids, 34-bit keys, five (odd) radix passes */
    CHECK(spm_tris_closed(g, n), "a torus of %d triangles is closed", n);
    for (int k = 0; k < n / 2; k++) { /* reversed order */
        spm_scene_tri s = g[k];
        g[k] = g[n - 1 - k];
        g[n - 1 - k] = s;
    }
    CHECK(spm_tris_closed(g, n), "the torus in reverse order is closed");
    CHECK(!spm_tris_closed(g + 1, n - 1), "the torus less one triangle is open");
    g[n / 2].p[1][2] = nextafterf(g[n / 2].p[1][2], 2.0f);
    CHECK(!spm_tris_closed(g, n), "the torus with one corner moved by an ulp is open");
    free(g);
    g = torus(12, 10, &n); /* 120 vertices: 14-bit keys, two (even) radix passes */
    CHECK(spm_tris_closed(g, n), "a torus of %d triangles is closed", n);
    CHECK(!spm_tris_closed(g, n - 1), "the small torus less one triangle is open");
    free(g);
    TEST_END();
}
