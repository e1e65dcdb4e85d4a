/* A ray leaving a closed box's wall from a point on one of its edges or
 * corners, into the box, must hit the box: a walk inside a closed box never
 * leaves it. The points are exact edge and corner points and hit points
 * (o + t d, as the renderer computes them) of rays aimed at edges and
 * corners from inside; the rays leave them in many directions on the
 * inward side of the face they lie on, as closest-hit rays and as shadow
 * rays towards a light outside the box (always occluded). Each set runs
 * through the CPU reference's BVH, brute force and the kernel
 * (kernels/rays.cl, the renderer's traversal), on boxes of size 1e-3, 1 and
 * 1e3 and on one far from the origin: no escape may depend on the unit. */
#include "bench_rays.h"
#include "cl_testlib.h"
#include "geomtest_scene.h"
#include "testutil.h"
#include "geometry_vec3.h"

#define NDIR 48 /* directions per point */

typedef struct {
    float lo[3], hi[3], mid[3];
} box;

/* The box's six faces (two triangles each), then a light triangle outside it. */
static void box_scene(spm_scene *s, spm_geometry *g, const box *b, spm_u32 *light)
{
    ts_init(s);
    int m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.5), -1);
    ts_box(s, m, b->lo, b->hi, 0);
    float w = b->hi[0] - b->lo[0], y = b->hi[1] + 2 * w;
    ts_tri(s, m, (float[]){b->mid[0] - 9 * w, y, b->mid[2] - 9 * w},
           (float[]){b->mid[0] + 9 * w, y, b->mid[2] - 9 * w}, (float[]){b->mid[0], y, b->mid[2] + 9 * w});
    spm_error err;
    if (spm_geometry_build(s, g, &err)) {
        CHECK(0, "box scene: %s", err.msg);
        exit(1);
    }
    for (int i = 0; i < g->ntris; i++)
        if (g->tris[i].v0[1] == y)
            *light = (spm_u32)i;
}

/* A triangle of the box holding p (within 1e-6 of the box's size in double),
 * its inward normal in n_in; -1 when none. */
static int face_of(const spm_geometry *g, const box *b, const float p[3], float n_in[3])
{
    double size = (double)b->hi[0] - b->lo[0];
    for (int i = 0; i < g->ntris; i++) {
        const spm_tri *t = &g->tris[i];
        double e0[3], e1[3], q[3], c[3], n2 = 0, b1 = 0, b2 = 0, h = 0, side = 0;
        for (int k = 0; k < 3; k++)
            e0[k] = (double)t->v1[k] - t->v0[k], e1[k] = (double)t->v2[k] - t->v0[k],
            q[k] = (double)p[k] - t->v0[k];
        for (int k = 0; k < 3; k++) {
            int u = (k + 1) % 3, v = (k + 2) % 3;
            c[k] = e0[u] * e1[v] - e0[v] * e1[u];
            n2 += c[k] * c[k];
        }
        for (int k = 0; k < 3; k++) {
            int u = (k + 1) % 3, v = (k + 2) % 3;
            b1 += (q[u] * e1[v] - q[v] * e1[u]) * c[k] / n2;
            b2 += (e0[u] * q[v] - e0[v] * q[u]) * c[k] / n2;
            h += q[k] * c[k] / sqrt(n2);
            side += ((double)b->mid[k] - p[k]) * c[k];
        }
        double tol = 1e-6 * size / sqrt(sqrt(n2));
        if (fabs(h) < 1e-6 * size && b1 > -tol && b2 > -tol && 1 - b1 - b2 > -tol &&
            g->tris[i].v0[1] < b->hi[1] + size) {
            for (int k = 0; k < 3; k++)
                n_in[k] = (float)(side > 0 ? c[k] : -c[k]);
            v3_normalise(n_in, n_in);
            return i;
        }
    }
    return -1;
}

/* NDIR rays from p on face f (inward normal n) into the box: closest-hit
 * rays, then as many shadow rays towards the light. */
static void leave(spm_rayset *rs, const float p[3], int f, const float n[3], spm_u32 light,
                  unsigned *seed)
{
    for (int k = 0; k < NDIR; k++) {
        float d[3];
        do {
            for (int i = 0; i < 3; i++)
                d[i] = 2 * ts_rand(seed) - 1;
        } while (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 1 ||
                 d[0] * n[0] + d[1] * n[1] + d[2] * n[2] <= 0);
        if (k < 6) /* grazing: nearly in the face's plane */
            for (int i = 0; i < 3; i++)
                d[i] += -(d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) * n[i] * 0.9999f;
        v3_normalise(d, d);
        spm_ray *r = &rs->rays[rs->n++];
        memcpy(r->o, p, sizeof r->o);
        memcpy(r->d, d, sizeof r->d);
        r->skip = (spm_u32)f;
        r->emitter = k % 2 ? light : SPM_RAY_CLOSEST;
    }
}

/* Points on the box's twelve edges (corners included) and hit points near
 * them; returns the ray set, closest-hit rays first. */
static spm_rayset edge_rays(const spm_geometry *g, const box *b, spm_u32 light)
{
    spm_rayset rs = {spm_xmalloc(12 * 9 * 2 * NDIR * sizeof(spm_ray)), 0, 0};
    unsigned seed = 17;
    const float us[9] = {0.0f, 1.0f, 0.5f, 0.25f, 0.1f, 1.0f / 3.0f, 0.7f, 0.9f, 0.01f};
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 9; k++) {
                int u = (a + 1) % 3, v = (a + 2) % 3;
                float p[3], n[3];
                p[a] = b->lo[a] + (b->hi[a] - b->lo[a]) * us[k];
                p[u] = c & 1 ? b->hi[u] : b->lo[u];
                p[v] = c & 2 ? b->hi[v] : b->lo[v];
                int f = face_of(g, b, p, n);
                CHECK(f >= 0, "edge point %d %d %d on no face", a, c, k);
                if (f >= 0)
                    leave(&rs, p, f, n, light, &seed);
                /* the hit of a ray from inside aimed at the point */
                float o[3], d[3], t, h[3];
                for (int i = 0; i < 3; i++) {
                    o[i] = b->mid[i] + (b->hi[i] - b->lo[i]) * 0.2f * (ts_rand(&seed) - 0.5f);
                    d[i] = p[i] - o[i];
                }
                v3_normalise(d, d);
                int hit = spm_bvh_intersect(g, o, d, 0xFFFFFFFFu, &t);
                CHECK(hit >= 0, "the ray aimed at edge point %d %d %d left the box", a, c, k);
                if (hit < 0)
                    continue;
                for (int i = 0; i < 3; i++)
                    h[i] = o[i] + d[i] * t;
                float m[3] = {0, 0, 0};
                for (int i = 0; i < 3; i++)
                    m[i] = g->tris[hit].n[i];
                float s = 0;
                for (int i = 0; i < 3; i++)
                    s += (b->mid[i] - h[i]) * m[i];
                for (int i = 0; i < 3; i++)
                    m[i] = s > 0 ? m[i] : -m[i];
                leave(&rs, h, hit, m, light, &seed);
            }
    /* closest-hit rays first */
    size_t nc = 0;
    for (size_t i = 0; i < rs.n; i++)
        if (rs.rays[i].emitter == SPM_RAY_CLOSEST) {
            spm_ray r = rs.rays[nc];
            rs.rays[nc++] = rs.rays[i];
            rs.rays[i] = r;
        }
    rs.nclosest = nc;
    return rs;
}

static int escaped(int h, const spm_ray *r)
{
    return h < 0 || (r->emitter != SPM_RAY_CLOSEST && (spm_u32)h == r->emitter);
}

static void test_box(const char *what, float size, const float at[3])
{
    box b;
    for (int i = 0; i < 3; i++) {
        float ext = size * (i == 0 ? 1.0f : i == 1 ? 0.7f : 1.3f);
        b.lo[i] = at[i] - ext / 2, b.hi[i] = at[i] + ext / 2, b.mid[i] = at[i];
    }
    spm_scene s;
    spm_geometry g;
    spm_u32 light = 0;
    box_scene(&s, &g, &b, &light);
    spm_rayset rs = edge_rays(&g, &b, light);
    int *hk = spm_xmalloc(rs.n * sizeof *hk), *hr = spm_xmalloc(rs.n * sizeof *hr);
    spm_rays_timing tm;
    spm_rays_replay_ref(&g, &rs, hr, &tm);
    size_t ref = 0, brute = 0, kern = 0, differ = 0;
    for (size_t i = 0; i < rs.n; i++) {
        float t;
        ref += escaped(hr[i], &rs.rays[i]);
        brute += escaped(spm_brute_intersect(&g, rs.rays[i].o, rs.rays[i].d, rs.rays[i].skip, &t),
                         &rs.rays[i]);
    }
    char dev[256];
    spm_error err;
    int rc = spm_rays_replay_cl(0, &g, &rs, 0, 0, hk, &tm, dev, sizeof dev, NULL, NULL, &err);
    CHECK(rc == 0, "%s: %s", what, err.msg);
    if (rc == 0) {
        for (size_t i = 0; i < rs.n; i++)
            kern += escaped(hk[i], &rs.rays[i]);
        size_t cb, sb;
        spm_rays_compare(&rs, hk, hr, &cb, &sb);
        differ = cb + sb;
    }
    printf("%-22s %zu rays (%zu closest-hit): escaped reference %zu, brute force %zu, kernel %zu; "
           "kernel differs from reference on %zu\n", what, rs.n, rs.nclosest, ref, brute, kern, differ);
    CHECK(rs.n > 2000 && ref == 0 && brute == 0 && kern == 0 && differ == 0,
          "%s: rays left the closed box (reference %zu, brute %zu, kernel %zu; differ %zu)", what,
          ref, brute, kern, differ);
    free(hk);
    free(hr);
    free(rs.rays);
    spm_geometry_free(&g);
    ts_free(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 77;
    test_box("box of size 1", 1.0f, (float[]){0.1f, 0.2f, 0.3f});
    test_box("box of size 1e-3", 1e-3f, (float[]){1e-4f, 2e-4f, 3e-4f});
    test_box("box of size 1e3", 1e3f, (float[]){100.0f, 200.0f, 300.0f});
    test_box("size 1, 1e3 away", 1.0f, (float[]){1000.3f, -700.1f, 500.7f});
    TEST_END();
}
