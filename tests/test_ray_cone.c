/* The ray cone's spread past a vertex (host/cpu/refcpu_texture.c
 * spm_ref_cone_bounce, the kernel's tex_cone_bounce in the same operations;
 * tests/test_cl_trace.c holds the two to the same records) against closed
 * forms: a flat mirror keeps the spread; a triangle on a sphere of radius R
 * with its exact normals has curvature 1/R, so a mirror there adds 2 w / R;
 * refraction scales it by d(theta_t)/d(theta_i), here by finite differences
 * of Snell's law, and on the sphere adds |1 - 1/eta| w / R; a lobe adds
 * SPM_CONE_LOBE times sqrt(1 / (pi p)): a Lambertian lobe along the normal
 * (density 1/pi) 1 radian's share, at 60 degrees (density 1/(2 pi)) sqrt 2's. */
#include "refcpu_texture.h"
#include "testutil.h"
#include <math.h>
#include <string.h>

static spm_tri tri_at(const float p[3][3], spm_u32 vn)
{
    spm_tri t;
    memset(&t, 0, sizeof t);
    memcpy(t.v0, p[0], sizeof t.v0);
    memcpy(t.v1, p[1], sizeof t.v1);
    memcpy(t.v2, p[2], sizeof t.v2);
    t.vn = vn;
    return t;
}

int main(void)
{
    /* a triangle on the sphere of radius 2 about the origin, normals p / 2 */
    const float r = 2.0f, p[3][3] = {{2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, {1.2f, 1.2f, 1.0583005f}};
    float vn[9];
    for (int i = 0; i < 9; i++)
        vn[i] = p[i / 3][i % 3] / r;
    spm_geometry g;
    memset(&g, 0, sizeof g);
    g.vnormals = vn;
    spm_tri flat = tri_at(p, 0u), round = tri_at(p, 1u);
    const float n[3] = {0.0f, 0.0f, 1.0f}, d[3] = {0.0f, 0.6f, -0.8f};
    spm_ref_bsample mirror = {{0.0f, 0.6f, 0.8f}, 1.0f, 1.0f, 0.0f, 0.0f, 0, 0};
    CHECK(spm_ref_cone_bounce(&g, &flat, 0.003f, 0.01f, n, 1.0f, d, &mirror) == 0.003f,
          "a flat mirror changed the spread");
    CHECK_NEAR(spm_ref_cone_bounce(&g, &round, 0.003f, 0.01f, n, 1.0f, d, &mirror),
               0.003 + 2.0 * 0.01 / r, 1e-6, "a mirror of curvature 1/R: + 2 w / R");

    /* refraction into glass of 1.5 at 40 degrees: d(theta_t)/d(theta_i) */
    double ti = 40.0 * M_PI / 180.0, eta = 1.5, h = 1e-5;
    double tt = asin(sin(ti) / eta);
    double fd = (asin(sin(ti + h) / eta) - asin(sin(ti - h) / eta)) / (2.0 * h);
    float din[3] = {(float)sin(ti), 0.0f, (float)-cos(ti)};
    spm_ref_bsample refr = {{(float)sin(tt), 0.0f, (float)-cos(tt)}, 1.0f, 1.0f, 0.0f, 0.0f, 1, 1};
    CHECK_NEAR(spm_ref_cone_bounce(&g, &flat, 0.003f, 0.01f, n, (float)eta, din, &refr),
               0.003 * fd, 1e-8, "refraction scales the spread by Snell's derivative");
    CHECK_NEAR(spm_ref_cone_bounce(&g, &round, 0.003f, 0.01f, n, (float)eta, din, &refr),
               0.003 * fd + (1.0 - 1.0 / eta) * 0.01 / r, 1e-8,
               "a curved refraction adds |1 - 1/e| w / R");
    /* and back out: the inverse scale */
    spm_ref_bsample out = {{(float)sin(ti), 0.0f, (float)-cos(ti)}, 1.0f, 1.0f, 0.0f, 0.0f, 1, 0};
    float dt[3] = {(float)sin(tt), 0.0f, (float)-cos(tt)};
    CHECK_NEAR(spm_ref_cone_bounce(&g, &flat, 0.003f, 0.01f, n, (float)(1.0 / eta), dt, &out),
               0.003 / fd, 1e-8, "leaving the glass undoes it");

    /* a Lambertian lobe along the normal: density 1/pi, sqrt(1 / (pi p)) = 1 */
    spm_ref_bsample diffuse = {{0.0f, 0.0f, 1.0f}, 1.0f, 1.0f, (float)(1.0 / M_PI), 1.0f, 0, 0};
    CHECK_NEAR(spm_ref_cone_bounce(&g, &flat, 0.003f, 0.01f, n, 1.0f, d, &diffuse),
               0.003 + SPM_CONE_LOBE * 1.0, 1e-6, "a Lambertian bounce widens by a radian's share");
    /* a diffuse lobe (pdf -1: cosine-sampled) at 60 degrees: density 1 / (2 pi) */
    spm_ref_bsample cosine = {{0.8660254f, 0.0f, 0.5f}, 1.0f, 1.0f, -1.0f, 0.0f, 0, 0};
    CHECK_NEAR(spm_ref_cone_bounce(&g, &flat, 0.003f, 0.01f, n, 1.0f, d, &cosine),
               0.003 + SPM_CONE_LOBE * sqrt(2.0), 1e-6,
               "a cosine-sampled bounce at 60 degrees widens by sqrt 2's share");
    TEST_END();
}
