/* The watertightness and tiny-triangle cases (test_watertight.c on the CPU
 * reference, test_cl_watertight.c on the kernel's traversal through the ray
 * replay): rays with what each must hit.
 *  - tiny: one triangle of 1e-8 m^2 (legs 1e-4 and 2e-4), rays aimed at its
 *    centroid from 0 to 89.99 degrees off its normal must hit it, rays aimed
 *    at a point one leg beyond its edges must miss;
 *  - sphere: a closed UV sphere of 4992 triangles (at scale 1 and shrunk by
 *    10^4 to triangles of ~2e-12 m^2), rays from outside through each shared
 *    vertex and through points of each shared edge, up to 75 degrees off the
 *    inward radial: the ray enters the closed mesh there, so it must hit one
 *    of the triangles that share that vertex or edge;
 *  - grid: a cube whose faces are 8 x 8 grids of squares split in two, every
 *    vertex a multiple of 1/4: rays along an axis and along diagonals through
 *    its vertices and edge midpoints, where the test's edge functions come
 *    out exactly 0 (the rule that 0 is inside for both triangles). */
#ifndef SPM_WATERTIGHT_TESTLIB_H
#define SPM_WATERTIGHT_TESTLIB_H
#include "geomtest_scene.h"
#include "testutil.h"

enum { WT_HIT, WT_MISS };

typedef struct {
    int kind;         /* WT_HIT: a triangle with vertices a and b (a vertex: a == b); WT_MISS */
    float a[3], b[3];
} wt_want;

typedef struct {
    const char *name;
    spm_scene s;
    spm_geometry g;
    spm_ray *rays;
    wt_want *want;
    size_t n, cap;
} wt_case;

static inline void wt_add(wt_case *c, const float o[3], const float d[3], int kind,
                          const float a[3], const float b[3])
{
    if (c->n == c->cap) {
        c->cap = c->cap ? 2 * c->cap : 1024;
        c->rays = realloc(c->rays, c->cap * sizeof *c->rays);
        c->want = realloc(c->want, c->cap * sizeof *c->want);
    }
    spm_ray *r = &c->rays[c->n];
    wt_want *w = &c->want[c->n++];
    memset(r, 0, sizeof *r);
    memset(w, 0, sizeof *w);
    memcpy(r->o, o, sizeof r->o);
    memcpy(r->d, d, sizeof r->d);
    r->skip = 0xFFFFFFFFu;
    r->emitter = SPM_RAY_CLOSEST;
    w->kind = kind;
    if (a)
        memcpy(w->a, a, sizeof w->a);
    if (b)
        memcpy(w->b, b, sizeof w->b);
}

/* The ray from o towards p (direction normalised in double, then float). */
static inline void wt_aim(wt_case *c, const double o[3], const float p[3], int kind,
                          const float a[3], const float b[3])
{
    double d[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    float of[3] = {(float)o[0], (float)o[1], (float)o[2]};
    float df[3] = {(float)(d[0] / l), (float)(d[1] / l), (float)(d[2] / l)};
    wt_add(c, of, df, kind, a, b);
}

static inline int wt_build(wt_case *c)
{
    spm_error err;
    if (spm_geometry_build(&c->s, &c->g, &err)) {
        printf("%s: geometry: %s\n", c->name, err.msg);
        return 1;
    }
    return 0;
}

static inline void wt_free(wt_case *c)
{
    spm_geometry_free(&c->g);
    ts_free(&c->s);
    free(c->rays);
    free(c->want);
    memset(c, 0, sizeof *c);
}

static inline void wt_init(wt_case *c, const char *name)
{
    memset(c, 0, sizeof *c);
    c->name = name;
    ts_init(&c->s);
}

/* One triangle of area 1e-8 in the plane z = 0.1, normal +z. */
static inline int wt_tiny(wt_case *c)
{
    wt_init(c, "1e-8 m^2 triangle");
    int m = ts_material(&c->s, ts_colour(&c->s, SPM_KIND_REFLECTANCE, 0.5), -1);
    const float v0[3] = {0.3f, 0.2f, 0.1f}, v1[3] = {0.3001f, 0.2f, 0.1f},
                v2[3] = {0.3f, 0.2002f, 0.1f};
    ts_tri(&c->s, m, v0, v1, v2);
    /* the centroid, and points one leg beyond each edge (outside) */
    double cen[3], out[3][3];
    for (int k = 0; k < 3; k++) {
        cen[k] = ((double)v0[k] + v1[k] + v2[k]) / 3.0;
        out[0][k] = 2.0 * v1[k] - (double)v0[k];           /* beyond v1 along edge v0 v1 */
        out[1][k] = 2.0 * v2[k] - (double)v0[k];           /* beyond v2 */
        out[2][k] = (double)v1[k] + v2[k] - (double)v0[k]; /* across the hypotenuse */
    }
    const double deg[] = {0.0, 60.0, 85.0, 89.0, 89.9, 89.99};
    for (size_t i = 0; i < sizeof deg / sizeof deg[0]; i++)
        for (int az = 0; az < 8; az++) {
            double th = deg[i] * M_PI / 180.0, ph = az * M_PI / 4.0 + 0.1;
            double dir[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
            for (int tgt = 0; tgt < 4; tgt++) {
                const double *p = tgt == 0 ? cen : out[tgt - 1];
                double o[3];
                for (int k = 0; k < 3; k++)
                    o[k] = p[k] + dir[k]; /* 1 away, on the front side */
                float pf[3] = {(float)p[0], (float)p[1], (float)p[2]};
                if (tgt == 0)
                    wt_aim(c, o, pf, WT_HIT, v0, v1);
                else
                    wt_aim(c, o, pf, WT_MISS, NULL, NULL);
            }
        }
    return wt_build(c);
}

/* A unit vector at angle th from n, turned about n by ph. */
static inline void wt_cone(const double n[3], double th, double ph, double out[3])
{
    double a[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0}, u[3], w[3];
    u[0] = n[1] * a[2] - n[2] * a[1], u[1] = n[2] * a[0] - n[0] * a[2], u[2] = n[0] * a[1] - n[1] * a[0];
    double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++)
        u[k] /= l;
    w[0] = n[1] * u[2] - n[2] * u[1], w[1] = n[2] * u[0] - n[0] * u[2], w[2] = n[0] * u[1] - n[1] * u[0];
    for (int k = 0; k < 3; k++)
        out[k] = n[k] * cos(th) + (u[k] * cos(ph) + w[k] * sin(ph)) * sin(th);
}

/* Rays through point p of the sphere (centre cen, radius r) from outside:
 * origins r/2 from p along directions up to 75 degrees off the outward radial. */
static inline void wt_sphere_rays(wt_case *c, unsigned *rng, const double cen[3], double r,
                                  const float p[3], const float a[3], const float b[3])
{
    double n[3] = {p[0] - cen[0], p[1] - cen[1], p[2] - cen[2]};
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++)
        n[k] /= l;
    for (int i = 0; i < 2; i++) {
        double th = (i == 0 ? 0.0 : 75.0 * ts_rand(rng)) * M_PI / 180.0, e[3], o[3];
        wt_cone(n, th, 2.0 * M_PI * ts_rand(rng), e);
        for (int k = 0; k < 3; k++)
            o[k] = p[k] + 0.5 * r * e[k];
        wt_aim(c, o, p, WT_HIT, a, b);
    }
}

static inline int wt_sphere(wt_case *c, const char *name, double scale)
{
    enum { RINGS = 40, SEGS = 64 };
    wt_init(c, name);
    int m = ts_material(&c->s, ts_colour(&c->s, SPM_KIND_REFLECTANCE, 0.5), -1);
    double cen[3] = {0.1 * scale, 0.2 * scale, 0.3 * scale}, r = 0.5 * scale;
    ts_sphere(&c->s, m, cen, r, RINGS, SEGS);
    unsigned rng = 12345u;
    /* every edge of every triangle (shared ones twice, from each side's
     * order) at its midpoint and one random point, and every vertex */
    for (int t = 0; t < c->s.ntris; t++)
        for (int e = 0; e < 3; e++) {
            const float *a = c->s.tris[t].p[e], *b = c->s.tris[t].p[(e + 1) % 3];
            wt_sphere_rays(c, &rng, cen, r, a, a, a);
            for (int h = 0; h < 2; h++) {
                float f = h == 0 ? 0.5f : 0.01f + 0.98f * ts_rand(&rng), p[3];
                for (int k = 0; k < 3; k++)
                    p[k] = a[k] + (b[k] - a[k]) * f;
                wt_sphere_rays(c, &rng, cen, r, p, a, b);
            }
        }
    return wt_build(c);
}

static inline int wt_grid(wt_case *c)
{
    enum { N = 8 };
    wt_init(c, "grid cube");
    int m = ts_material(&c->s, ts_colour(&c->s, SPM_KIND_REFLECTANCE, 0.5), -1);
    /* face (axis, side): u, v the other two axes, coordinates -1 + i/4 */
    for (int ax = 0; ax < 3; ax++)
        for (int side = 0; side < 2; side++) {
            int u = (ax + 1) % 3, v = (ax + 2) % 3;
            float pt[N + 1][N + 1][3];
            for (int i = 0; i <= N; i++)
                for (int j = 0; j <= N; j++) {
                    pt[i][j][ax] = side ? 1.0f : -1.0f;
                    pt[i][j][u] = -1.0f + 0.25f * (float)i;
                    pt[i][j][v] = -1.0f + 0.25f * (float)j;
                }
            for (int i = 0; i < N; i++)
                for (int j = 0; j < N; j++) {
                    if ((i + j) % 2) { /* both diagonals occur */
                        ts_tri(&c->s, m, pt[i][j], pt[i + 1][j], pt[i + 1][j + 1]);
                        ts_tri(&c->s, m, pt[i][j], pt[i + 1][j + 1], pt[i][j + 1]);
                    } else {
                        ts_tri(&c->s, m, pt[i][j], pt[i + 1][j], pt[i][j + 1]);
                        ts_tri(&c->s, m, pt[i + 1][j], pt[i + 1][j + 1], pt[i][j + 1]);
                    }
                }
            /* rays into this face through its vertices and edge midpoints
             * (the midpoints of the grid lines, exact multiples of 1/8) */
            float out = side ? 1.0f : -1.0f;
            for (int i = 0; i <= N; i++)
                for (int j = 0; j <= N; j++)
                    for (int h = 0; h < 3; h++) {
                        if ((h == 1 && i == N) || (h == 2 && j == N))
                            continue;
                        const float *a = pt[i][j];
                        const float *b = h == 0 ? a : h == 1 ? pt[i + 1][j] : pt[i][j + 1];
                        float p[3];
                        for (int k = 0; k < 3; k++)
                            p[k] = 0.5f * (a[k] + b[k]);
                        /* along the axis, and (inside the face, where such a ray
                         * goes on into the cube) along two diagonals */
                        int inner = fabsf(p[u]) < 1.0f && fabsf(p[v]) < 1.0f;
                        for (int dk = 0; dk < (inner ? 3 : 1); dk++) {
                            double o[3] = {p[0], p[1], p[2]};
                            o[ax] += 3.0 * out;
                            if (dk == 1)
                                o[u] += 3.0, o[v] += 3.0;
                            if (dk == 2)
                                o[u] -= 1.5, o[v] += 3.0;
                            wt_aim(c, o, p, WT_HIT, a, b);
                        }
                    }
        }
    return wt_build(c);
}

static inline int wt_has_vertex(const spm_tri *t, const float p[3])
{
    return !memcmp(t->v0, p, 3 * sizeof(float)) || !memcmp(t->v1, p, 3 * sizeof(float)) ||
           !memcmp(t->v2, p, 3 * sizeof(float));
}

/* hits[i]: the closest triangle of ray i, or -1 (from either intersector). */
static inline void wt_check(const char *backend, const wt_case *c, const int *hits)
{
    size_t missed = 0, elsewhere = 0, false_hit = 0, want_hit = 0;
    for (size_t i = 0; i < c->n; i++) {
        const wt_want *w = &c->want[i];
        if (w->kind == WT_MISS) {
            false_hit += hits[i] >= 0;
            continue;
        }
        want_hit++;
        if (hits[i] < 0) {
            missed++;
            continue;
        }
        const spm_tri *t = &c->g.tris[hits[i]];
        elsewhere += !wt_has_vertex(t, w->a) || !wt_has_vertex(t, w->b);
    }
    printf("%s, %s: %d triangles, %zu rays (%zu must hit): %zu missed, %zu hit another "
           "triangle, %zu hit where they must miss\n", backend, c->name, c->g.ntris, c->n,
           want_hit, missed, elsewhere, false_hit);
    CHECK(want_hit > 0 && missed == 0 && elsewhere == 0 && false_hit == 0,
          "%s, %s: every ray hits what it must and misses what it must", backend, c->name);
}

/* The cases in order; a case that fails to build is a failed check. */
typedef void (*wt_run_fn)(const wt_case *c);

static inline void wt_all(wt_run_fn run)
{
    wt_case c;
    for (int k = 0; k < 4; k++) {
        int rc = k == 0   ? wt_tiny(&c)
                 : k == 1 ? wt_sphere(&c, "closed sphere", 1.0)
                 : k == 2 ? wt_sphere(&c, "closed sphere at 1e-4", 1e-4)
                          : wt_grid(&c);
        CHECK(rc == 0, "%s builds", c.name);
        if (!rc)
            run(&c);
        wt_free(&c);
    }
}
#endif
