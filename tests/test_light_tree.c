/* The light tree's selection (host/geometry/light_tree.c built, the CPU
 * reference's walk host/cpu/refcpu_light_tree.c) on a scene of many
 * triangle lights of mixed power and orientation, point and spot lights and
 * a distant light beside the tree:
 *  - the pmf of every light at random shading points is above 0 and they
 *    sum to 1;
 *  - with one light, the pmf is the power table's (1) everywhere;
 *  - the pmfs are continuous in the shading point (a choice that switches
 *    at a threshold is flipped by the float differences between devices);
 *  - chi-squared of the lights the pick draws at a shading point against
 *    the pmf the same walk gives each, and each pick's claimed pmf against
 *    it. */
#include <string.h>
#include "chi2_testlib.h"
#include "geomtest_scene.h"
#include "geometry.h"
#include "light_tree.h"
#include "refcpu_lights.h"

#define ALPHA 0.01
#define NTRI 400
#define NPOINTS 40
#define CHI2_POINTS 4
#define CHI2_DRAWS 400000L

static spm_scene_light pl[3];

/* NTRI small triangles in [-1, 1]^3 facing random ways, of emissions 0.1 to
 * 1000; a floor; a point, a spot and (with beside) a distant light */
static int build(spm_scene *s, spm_geometry *g, spm_tables *t, int ntri, int beside)
{
    uint64_t seed = 17;
    ts_init(s);
    int floor_m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.5), -1);
    ts_quad(s, floor_m, (float[]){-5, -1, -5}, (float[]){-5, -1, 5}, (float[]){5, -1, 5},
            (float[]){5, -1, -5});
    int mats[4];
    for (int k = 0; k < 4; k++)
        mats[k] = ts_material(s, -1, ts_colour(s, SPM_KIND_EMISSION, pow(10.0, k - 1.0)));
    for (int i = 0; i < ntri; i++) {
        float v[3][3];
        double c[3] = {2 * chi2_u01(&seed) - 1, 2 * chi2_u01(&seed) - 1, 2 * chi2_u01(&seed) - 1};
        for (int a = 0; a < 3; a++)
            for (int k = 0; k < 3; k++)
                v[a][k] = (float)(c[k] + 0.1 * (chi2_u01(&seed) - 0.5));
        ts_tri(s, mats[(int)(4 * chi2_u01(&seed)) & 3], v[0], v[1], v[2]);
    }
    int white = ts_colour(s, SPM_KIND_EMISSION, 1.0);
    int nl = 0;
    if (ntri > 1) {
        pl[nl] = (spm_scene_light){.kind = SPM_LIGHT_POINT, .colour = white};
        memcpy(&pl[nl].p[SPM_LIGHT_P_POS], (float[]){0.3f, 0.9f, -0.2f}, 3 * sizeof(float));
        pl[nl++].p[SPM_LIGHT_P_SCALE] = 2.0f;
        pl[nl] = (spm_scene_light){.kind = SPM_LIGHT_SPOT, .colour = white};
        memcpy(&pl[nl].p[SPM_LIGHT_P_POS], (float[]){-0.5f, 0.5f, 0.5f}, 3 * sizeof(float));
        memcpy(&pl[nl].p[SPM_LIGHT_P_DIR], (float[]){0.0f, -1.0f, 0.0f}, 3 * sizeof(float));
        pl[nl].p[SPM_LIGHT_P_A] = 0.6f;
        pl[nl].p[SPM_LIGHT_P_B] = 0.4f;
        pl[nl].p[SPM_LIGHT_P_C] = cosf(0.6f);
        pl[nl++].p[SPM_LIGHT_P_SCALE] = 5.0f;
    }
    if (beside) {
        pl[nl] = (spm_scene_light){.kind = SPM_LIGHT_DISTANT, .colour = white};
        memcpy(&pl[nl].p[SPM_LIGHT_P_DIR], (float[]){0.0f, -1.0f, 0.0f}, 3 * sizeof(float));
        pl[nl++].p[SPM_LIGHT_P_SCALE] = 1.0f;
    }
    s->lights = pl;
    s->nlights = nl;
    spm_error err;
    if (spm_geometry_build(s, g, &err)) {
        CHECK(0, "build: %s", err.msg);
        return 1;
    }
    ts_tables(s, t);
    spm_light_tree_attach(g, t->materials);
    return 0;
}

static void scene_free(spm_scene *s, spm_geometry *g, spm_tables *t)
{
    s->lights = NULL; /* static */
    spm_tables_free(t);
    spm_geometry_free(g);
    ts_free(s);
}

/* a shading point in [-1.5, 1.5]^3 and a unit normal (the geometric normal
 * of triangle `from`, which the walk reads, is set to it) */
static void shading_point(uint64_t *seed, float x[3], float n[3])
{
    double l = 0.0, v[3];
    for (int k = 0; k < 3; k++) {
        x[k] = (float)(3.0 * chi2_u01(seed) - 1.5);
        v[k] = 2.0 * chi2_u01(seed) - 1.0;
        l += v[k] * v[k];
    }
    for (int k = 0; k < 3; k++)
        n[k] = (float)(v[k] / sqrt(l));
}

static void pmf_sums_to_one(void)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    for (int beside = 0; beside < 2; beside++) {
        if (build(&s, &g, &t, NTRI, beside))
            return;
        uint64_t seed = 5;
        double worst = 0.0, least = 1.0;
        for (int q = 0; q < NPOINTS; q++) {
            float x[3], n[3];
            shading_point(&seed, x, n);
            double sum = 0.0;
            for (int e = 0; e < g.nemitters; e++) {
                double p = spm_ref_ltree_pmf(&g, x, n, (spm_u32)e);
                sum += p;
                least = fmin(least, p);
            }
            worst = fmax(worst, fabs(sum - 1.0));
        }
        /* float products along a trail of ~12 nodes, summed over 400 lights:
         * measured within 1.7e-7 */
        printf("pmf sum (%s): worst |sum - 1| %.2g over %d points, least pmf %.3g\n",
               beside ? "with a distant light" : "tree only", worst, NPOINTS, least);
        CHECK(worst <= 1e-4, "pmf sums off 1 by %.3g", worst);
        CHECK(least > 0.0, "a light of power has pmf %g", least);
        scene_free(&s, &g, &t);
    }
}

static void single_light(void)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    if (build(&s, &g, &t, 1, 0))
        return;
    uint64_t seed = 9;
    for (int q = 0; q < NPOINTS; q++) {
        float x[3], n[3], pmf = -1.0f;
        shading_point(&seed, x, n);
        float p = spm_ref_ltree_pmf(&g, x, n, 0u);
        int k = spm_ref_ltree_pick(&g, x, n, (float)chi2_u01(&seed), &pmf);
        CHECK(k == 0 && p == g.emitters[0].pdf && pmf == p,
              "one light: picked %d, pmf %g and %g, power table's %g", k, p, pmf, g.emitters[0].pdf);
    }
    printf("one light: picked, with the power table's pmf, at all %d points\n", NPOINTS);
    scene_free(&s, &g, &t);
}

/* the largest change of a light's pmf between shading points a and b of
 * normal n, relative to the larger */
static double pmf_change(const spm_geometry *g, const float a[3], const float b[3],
                         const float n[3])
{
    double worst = 0.0;
    for (int e = 0; e < g->nemitters; e++) {
        double p = spm_ref_ltree_pmf(g, a, n, (spm_u32)e), q = spm_ref_ltree_pmf(g, b, n, (spm_u32)e);
        if (p != q)
            worst = fmax(worst, fabs(p - q) / fmax(p, q));
    }
    return worst;
}

static void lerp(const float a[3], const float b[3], double t, float x[3])
{
    for (int k = 0; k < 3; k++)
        x[k] = (float)(a[k] + t * (b[k] - a[k]));
}

/* The pmfs are continuous in the shading point: on segments across the
 * scene, the one of SEG_STEPS steps where a pmf changes most is halved
 * SEG_HALVINGS times (to a step of ~2e-7, a few float ulps of the points),
 * keeping the half that changes more. A continuous pmf's change shrinks with
 * the step (measured: 0.19 after 10 halvings, 0.014 after 14, 3.7e-3 after
 * 16, where it meets the points' float resolution); one that switches at a
 * threshold (a child weighing 0, the edge of a box's sphere) keeps its jump
 * (the walk of pbrt-v4's importance with a power fallback: 1). */
#define SEG_COUNT 24
#define SEG_STEPS 200
#define SEG_HALVINGS 16
static void continuous(void)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    if (build(&s, &g, &t, NTRI, 0))
        return;
    uint64_t seed = 31;
    double worst = 0.0, coarse = 0.0;
    for (int q = 0; q < SEG_COUNT; q++) {
        float a[3], b[3], n[3], m[3], x[3], y[3];
        shading_point(&seed, a, n);
        shading_point(&seed, b, m);
        double t0 = 0.0, t1 = 0.0, most = -1.0;
        for (int k = 0; k < SEG_STEPS; k++) {
            lerp(a, b, (double)k / SEG_STEPS, x);
            lerp(a, b, (double)(k + 1) / SEG_STEPS, y);
            double c = pmf_change(&g, x, y, n);
            if (c > most)
                most = c, t0 = (double)k / SEG_STEPS, t1 = (double)(k + 1) / SEG_STEPS;
        }
        coarse = fmax(coarse, most);
        for (int h = 0; h < SEG_HALVINGS; h++) {
            float z[3];
            double tm = 0.5 * (t0 + t1);
            lerp(a, b, t0, x);
            lerp(a, b, tm, z);
            lerp(a, b, t1, y);
            if (pmf_change(&g, x, z, n) >= pmf_change(&g, z, y, n))
                t1 = tm;
            else
                t0 = tm;
        }
        lerp(a, b, t0, x);
        lerp(a, b, t1, y);
        worst = fmax(worst, pmf_change(&g, x, y, n));
    }
    printf("continuity: largest relative pmf change %.3g over a step of 1/%d of a segment, "
           "%.3g after %d halvings (%d segments)\n", coarse, SEG_STEPS, worst, SEG_HALVINGS,
           SEG_COUNT);
    CHECK(worst <= 2e-2, "a pmf jumps by %.3g (relative) between points ~2e-7 apart", worst);
    scene_free(&s, &g, &t);
}

/* Pearson's statistic of the lights picked at x against n pmf, the
 * lights expected below the minimum pooled; the claimed pmf against pmf */
static void chi2_at(const spm_geometry *g, const float x[3], const float nrm[3], uint64_t *seed,
                    double alpha)
{
    int ne = g->nemitters;
    double *obs = calloc((size_t)ne + 1, sizeof *obs), *pmf = calloc((size_t)ne + 1, sizeof *pmf);
    for (int e = 0; e < ne; e++)
        pmf[e] = spm_ref_ltree_pmf(g, x, nrm, (spm_u32)e);
    long none = 0, off = 0;
    for (long i = 0; i < CHI2_DRAWS; i++) {
        float p;
        int k = spm_ref_ltree_pick(g, x, nrm, (float)chi2_u01(seed), &p);
        if (k < 0) {
            none++;
            continue;
        }
        obs[k] += 1.0;
        off += !(fabs(p / pmf[k] - 1.0) <= 1e-5); /* the same walk: the same float */
    }
    double stat = 0.0, po = (double)none, pe = 0.0, mass = 0.0;
    int cells = 0;
    for (int e = 0; e < ne; e++) {
        double ex = pmf[e] * CHI2_DRAWS;
        mass += pmf[e];
        if (ex < CHI2_MIN_EXPECTED) {
            po += obs[e], pe += ex;
        } else {
            stat += (obs[e] - ex) * (obs[e] - ex) / ex;
            cells++;
        }
    }
    pe += CHI2_DRAWS * fmax(0.0, 1.0 - mass);
    if (pe > 0.0) {
        stat += (po - pe) * (po - pe) / pe;
        cells++;
    }
    double pval = st_chi2_sf(stat, cells - 1);
    printf("pick at (%.2f %.2f %.2f): chi2 %.1f over %d cells, p %.3g (reject below %.2g); "
           "%ld of %ld claimed pmfs off\n", x[0], x[1], x[2], stat, cells, pval, alpha, off,
           CHI2_DRAWS);
    CHECK(pval >= alpha, "pick vs pmf: chi2 %.1f over %d cells, p %.3g", stat, cells, pval);
    CHECK(off == 0, "%ld picks claim a pmf other than the walk's", off);
    CHECK(cells >= 20, "only %d cells: the pick spreads over too few lights", cells);
    free(obs);
    free(pmf);
}

static void chi2_pick(double alpha)
{
    spm_scene s;
    spm_geometry g;
    spm_tables t;
    if (build(&s, &g, &t, NTRI, 1))
        return;
    uint64_t seed = 23;
    for (int q = 0; q < CHI2_POINTS; q++) {
        float x[3], n[3];
        shading_point(&seed, x, n);
        chi2_at(&g, x, n, &seed, alpha);
    }
    scene_free(&s, &g, &t);
}

int main(void)
{
    pmf_sums_to_one();
    single_light();
    continuous();
    chi2_pick(st_sidak(ALPHA, CHI2_POINTS));
    TEST_END();
}
