/* The scale tests' scene and checks (test_scale_invariance.c on the CPU
 * reference, test_cl_scale_invariance.c on OpenCL): an open box with a small
 * ceiling light and a closed mesh of ~5000 small triangles (a UV sphere), every
 * coordinate and the eye multiplied by one factor. Light transport does not
 * depend on the unit, so
 *  - by a power of two, which float arithmetic carries exactly when nothing
 *    compares with an absolute bound, the records and images must be
 *    bit-identical (scale_check_exact);
 *  - by 10^-3 and 10^3, where every coordinate rounds differently, the
 *    images must agree within Monte Carlo noise (scale_check_noise). */
#ifndef SPM_SCALE_TESTLIB_H
#define SPM_SCALE_TESTLIB_H
#include <math.h>
#include "geomtest_scene.h"
#include "testutil.h"

#define SC_SIZE 16
#define SC_SEED 5u
#define SC_RINGS 40 /* the sphere: latitude bands */
#define SC_SEGS 64  /* and longitude segments: 2 * 64 * 39 = 4992 triangles */

typedef struct {
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    int mesh_colour; /* the sphere's reflectance colour (its hits are counted) */
} sc_world;

static inline void sc_pt(float out[3], double scale, double x, double y, double z)
{
    out[0] = (float)(x * scale);
    out[1] = (float)(y * scale);
    out[2] = (float)(z * scale);
}

/* 0, or prints why and returns 1. */
static inline int sc_world_build(sc_world *w, double scale)
{
    spm_scene *s = &w->s;
    ts_init(s);
    s->width = s->height = SC_SIZE;
    sc_pt(s->eye, scale, 0.5, 0.5, -1.0);
    s->dir[0] = 0.0f, s->dir[1] = 0.0f, s->dir[2] = 1.0f;
    int wall = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.7), -1);
    w->mesh_colour = ts_colour(s, SPM_KIND_REFLECTANCE, 0.5);
    int ball = ts_material(s, w->mesh_colour, -1);
    int lamp = ts_material(s, -1, ts_colour(s, SPM_KIND_EMISSION, 20.0));
    float p[8][3];
    for (int i = 0; i < 8; i++)
        sc_pt(p[i], scale, i & 1, (i >> 1) & 1, (i >> 2) & 1);
    ts_quad(s, wall, p[0], p[4], p[5], p[1]); /* floor */
    ts_quad(s, wall, p[2], p[3], p[7], p[6]); /* ceiling */
    ts_quad(s, wall, p[0], p[2], p[6], p[4]); /* x = 0 */
    ts_quad(s, wall, p[1], p[5], p[7], p[3]); /* x = 1 */
    ts_quad(s, wall, p[4], p[6], p[7], p[5]); /* back, z = 1; the front is open */
    float l[4][3];
    sc_pt(l[0], scale, 0.4, 0.99, 0.4);
    sc_pt(l[1], scale, 0.6, 0.99, 0.4);
    sc_pt(l[2], scale, 0.6, 0.99, 0.6);
    sc_pt(l[3], scale, 0.4, 0.99, 0.6);
    ts_quad(s, lamp, l[0], l[1], l[2], l[3]); /* facing down */
    ts_sphere(s, ball, (const double[]){0.5 * scale, 0.32 * scale, 0.55 * scale}, 0.3 * scale,
              SC_RINGS, SC_SEGS);
    spm_error err;
    if (spm_geometry_build(s, &w->g, &err)) {
        printf("scale %g: geometry: %s\n", scale, err.msg);
        ts_free(s);
        return 1;
    }
    ts_tables(s, &w->t);
    return 0;
}

static inline void sc_world_free(sc_world *w)
{
    spm_tables_free(&w->t);
    spm_geometry_free(&w->g);
    ts_free(&w->s);
}

/* One render of a world: per path its record, level byte and XYZ (3 floats),
 * and per pixel the sum of its samples' XYZ, as the backend computes them. */
typedef struct {
    size_t n;
    spm_path *paths;
    uint8_t *levels;
    float *xyz;
    float *image;
} sc_render;

static inline void sc_render_alloc(sc_render *r, int spp)
{
    r->n = (size_t)SC_SIZE * SC_SIZE * (size_t)spp;
    r->paths = spm_xcalloc(r->n, sizeof *r->paths);
    r->levels = spm_xcalloc(r->n, 1);
    r->xyz = spm_xcalloc(3 * r->n, sizeof *r->xyz);
    r->image = spm_xcalloc(3 * (size_t)SC_SIZE * SC_SIZE, sizeof *r->image);
}

static inline void sc_render_free(sc_render *r)
{
    free(r->paths);
    free(r->levels);
    free(r->xyz);
    free(r->image);
}

/* The records that matter (head without padding, the written vertices) equal bit for bit. */
static inline int sc_same_record(const spm_path *a, const spm_path *b)
{
    if (memcmp(&a->h, &b->h, offsetof(spm_path_head, pad0)))
        return 0;
    return !memcmp(a->v, b->v, a->h.nvert * sizeof a->v[0]);
}

/* A discrete difference: another length, ending, colour or emitter (the
 * path took another turn), not only a weight's last bits. */
static inline int sc_path_turns(const spm_path *a, const spm_path *b)
{
    if (a->h.nvert != b->h.nvert || a->h.end != b->h.end || a->h.first_emit != b->h.first_emit ||
        a->h.bg != b->h.bg)
        return 1;
    for (spm_u32 j = 0; j < a->h.nvert; j++)
        if (a->v[j].ids != b->v[j].ids)
            return 1;
    return 0;
}

/* The scene must exercise what is compared: camera rays that hit the mesh,
 * lit vertices, bounces. */
static inline void sc_check_busy(const char *what, const sc_world *w, const sc_render *r)
{
    size_t mesh = 0, lit = 0, verts = 0;
    for (size_t i = 0; i < r->n; i++) {
        const spm_path *p = &r->paths[i];
        mesh += p->h.nvert > 0 && (p->v[0].ids & 0xFFFFu) == (spm_u32)w->mesh_colour;
        verts += p->h.nvert;
        for (spm_u32 j = 0; j < p->h.nvert; j++)
            lit += (p->v[j].ids >> 16) != SPM_NONE;
    }
    printf("%s: %zu paths, %zu first hits on the mesh, %zu vertices, %zu lit\n", what, r->n, mesh,
           verts, lit);
    CHECK(mesh > r->n / 10 && lit > r->n / 2 && verts > r->n, "%s: the scene is exercised", what);
}

/* Renders at 2^-10, 1 and 2^10 (every coordinate and the eye) must be the
 * same bit for bit: records, level bytes, per-path XYZ and the image. */
static inline void sc_check_exact(const char *backend, const sc_render r[3], const sc_world *w1)
{
    static const char *names[3] = {"2^-10", "1", "2^10"};
    sc_check_busy(backend, w1, &r[1]);
    for (int k = 0; k < 3; k += 2) {
        size_t rec = 0, lev = 0;
        for (size_t i = 0; i < r[1].n; i++) {
            rec += !sc_same_record(&r[k].paths[i], &r[1].paths[i]);
            lev += r[k].levels[i] != r[1].levels[i];
        }
        int xyz = memcmp(r[k].xyz, r[1].xyz, 3 * r[1].n * sizeof(float)) != 0;
        int img = memcmp(r[k].image, r[1].image, 3 * SC_SIZE * SC_SIZE * sizeof(float)) != 0;
        printf("%s, scale %s against 1: %zu of %zu records differ, %zu level bytes, "
               "per-path XYZ %s, image %s\n", backend, names[k], rec, r[1].n, lev,
               xyz ? "differs" : "identical", img ? "differs" : "identical");
        CHECK(rec == 0 && lev == 0 && !xyz && !img, "%s: scale %s renders as scale 1 bit for bit",
              backend, names[k]);
    }
}

/* Renders at 10^-3 and 10^3 against scale 1, pixel by pixel on Y: every
 * coordinate rounds differently at each scale, so a few paths take another
 * turn (a ray within rounding of an edge), and the images differ by noise
 * alone. Each pixel mean of spp samples has standard error sqrt(var / spp);
 * the bound is |m_a - m_1| <= 5 sqrt((var_a + var_1) / spp) at every pixel
 * and for the image mean. The two renders use the same random numbers, so
 * their errors are positively correlated and the real spread of the
 * difference is smaller than that (independent renders' bound): for
 * independent Gaussian errors, 5 sigma at one of 257 places would fail once
 * in ~7000 runs; the printed largest |z| shows the margin. An absolute
 * length left in the geometry moves whole regions (the mesh lost at 10^-3,
 * light clamped) far beyond it. */
#define SC_NOISE_Z 5.0

static inline void sc_pixel_stats(const sc_render *r, int spp, double *mean, double *var)
{
    for (int px = 0; px < SC_SIZE * SC_SIZE; px++) {
        double s = 0.0, s2 = 0.0;
        for (int k = 0; k < spp; k++) {
            double y = r->xyz[3 * ((size_t)px * spp + k) + 1];
            s += y;
            s2 += y * y;
        }
        mean[px] = s / spp;
        var[px] = spp > 1 ? (s2 - s * s / spp) / (spp - 1) : 0.0;
    }
}

static inline void sc_check_noise(const char *backend, const sc_render r[3], int spp,
                                  const sc_world *w1)
{
    static const char *names[3] = {"10^-3", "1", "10^3"};
    enum { NPIX = SC_SIZE * SC_SIZE };
    double m[3][NPIX], v[3][NPIX];
    sc_check_busy(backend, w1, &r[1]);
    for (int k = 0; k < 3; k++)
        sc_pixel_stats(&r[k], spp, m[k], v[k]);
    for (int k = 0; k < 3; k += 2) {
        double zmax = 0.0, ma = 0.0, m1 = 0.0, va = 0.0, v1 = 0.0;
        int bad = 0, worst = 0;
        size_t diverged = 0, inexact = 0;
        for (size_t i = 0; i < r[1].n; i++) {
            diverged += sc_path_turns(&r[k].paths[i], &r[1].paths[i]);
            inexact += !sc_same_record(&r[k].paths[i], &r[1].paths[i]);
        }
        for (int px = 0; px < NPIX; px++) {
            double se = sqrt((v[k][px] + v[1][px]) / spp);
            double d = fabs(m[k][px] - m[1][px]);
            double z = se > 0.0 ? d / se : (d > 0.0 ? INFINITY : 0.0);
            bad += !(z <= SC_NOISE_Z);
            if (z > zmax)
                zmax = z, worst = px;
            ma += m[k][px] / NPIX, m1 += m[1][px] / NPIX;
            va += v[k][px] / ((double)NPIX * NPIX), v1 += v[1][px] / ((double)NPIX * NPIX);
        }
        double zimg = fabs(ma - m1) / sqrt((va + v1) / spp);
        printf("%s, scale %s against 1: of %zu paths %zu took another turn, %zu differ in a "
               "weight's bits; image mean Y %.6g vs %.6g (|z| %.3f); largest pixel |z| %.3f "
               "(pixel %d: %.5g vs %.5g)\n", backend, names[k], r[1].n, diverged, inexact, ma, m1,
               zimg, zmax, worst, m[k][worst], m[1][worst]);
        CHECK(bad == 0 && zimg <= SC_NOISE_Z,
              "%s: scale %s within noise of scale 1 (%d pixels beyond %.1f sigma)", backend,
              names[k], bad, SC_NOISE_Z);
    }
}
#endif
