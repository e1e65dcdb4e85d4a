/* Lights picked by power (spm_shared.h spm_emitter): the table's pdf against
 * a count of picks over many draws of the render's own random numbers, the
 * per-triangle light pdf of a built scene against the emitters' powers, and
 * the CPU reference converging to the same floor brightness as MiniLight's
 * uniform pick, with less noise. */
#include "geomtest_scene.h"
#include "testutil.h"
#include "spm_rng.h"

/* Chi-square of picks counted over 2^20 draws of SPM_DIM_EMITTER (the
 * trace stage's dimension and bits) against the table's pdf. */
static double pick_chi2(const spm_emitter *em, int n, long draws, long *count)
{
    memset(count, 0, (size_t)n * sizeof *count);
    for (long i = 0; i < draws; i++) {
        spm_u32 u24 = spm_rng_u32(11u, (spm_u32)i, 3u, SPM_DIM_VERTEX(1) + SPM_DIM_EMITTER) >> 8;
        count[spm_emitter_search(em, (spm_u32)n, u24)]++;
    }
    double chi2 = 0.0;
    for (int i = 0; i < n; i++) {
        double want = (double)draws * em[i].pdf;
        chi2 += (count[i] - want) * (count[i] - want) / want;
    }
    return chi2;
}

static void test_table(void)
{
    enum { N = 61 };
    spm_emitter em[N];
    double w[N], total = 0.0;
    for (int i = 0; i < N; i++) { /* one strong light among 60 weak ones of 5 powers */
        w[i] = i == 17 ? 1000.0 : 1.0 + 3.0 * (i % 5);
        total += w[i];
        em[i].tri = (spm_u32)i;
    }
    CHECK(spm_emitter_table_build(em, w, N) == 1, "unequal powers are picked by power");
    for (int i = 0; i < N; i++) /* rounding to counts of 2^-24, plus the rest to the strongest */
        CHECK(fabs(em[i].pdf - w[i] / total) <= (N + 1.0) / SPM_EMIT_CDF_ONE,
              "emitter %d: pdf %.7g, power share %.7g", i, em[i].pdf, w[i] / total);
    long count[N], draws = 1L << 20;
    double chi2 = pick_chi2(em, N, draws, count);
    /* 60 degrees of freedom: mean 60, sd 11; 60 + 6 sd is never reached by
     * chance (p < 1e-6), an off-by-one or a wrong bound in the search is
     * (the weak emitters' expectations are 700-9000 picks: a count moved
     * between neighbours shows in the thousands) */
    printf("pick counts against the pdf: chi2 %.1f (60 dof)\n", chi2);
    CHECK(chi2 < 60.0 + 6.0 * sqrt(120.0), "chi2 %.1f over 60 degrees of freedom", chi2);

    /* equal powers: MiniLight's uniform pick, k = (uint)(u * n) */
    for (int i = 0; i < N; i++)
        w[i] = 2.5;
    CHECK(spm_emitter_table_build(em, w, N) == 0, "equal powers are picked uniformly");
    CHECK(em[5].inv_pdf == (float)N, "uniform pick: 1 / pdf = n (%g)", em[5].inv_pdf);
}

/* A floor under three lights: a dim sphere of many small triangles, a
 * strong small quad, a dim large quad. */
static void scene_lights(spm_scene *s)
{
    ts_init(s);
    int floor_m = ts_material(s, ts_colour(s, SPM_KIND_REFLECTANCE, 0.5), -1);
    int dim = ts_material(s, -1, ts_colour(s, SPM_KIND_EMISSION, 0.5));
    int strong = ts_material(s, -1, ts_colour(s, SPM_KIND_EMISSION, 400.0));
    ts_quad(s, floor_m, (float[]){-2, 0, -2}, (float[]){-2, 0, 2}, (float[]){2, 0, 2},
            (float[]){2, 0, -2});
    ts_sphere(s, dim, (double[]){1.0, 0.5, 0.0}, 0.3, 12, 24);
    /* facing down (seen from below counter-clockwise) */
    ts_quad(s, strong, (float[]){-1.0f, 1, -0.1f}, (float[]){-0.8f, 1, -0.1f},
            (float[]){-0.8f, 1, 0.1f}, (float[]){-1.0f, 1, 0.1f});
    ts_quad(s, dim, (float[]){-2, 1.5f, -2}, (float[]){0, 1.5f, -2}, (float[]){0, 1.5f, 2},
            (float[]){-2, 1.5f, 2});
    memcpy(s->eye, (float[]){0, 0.9f, -0.9f}, sizeof s->eye);
    memcpy(s->dir, (float[]){0, -1, 0.6f}, sizeof s->dir);
    s->fov_deg = 60.0f;
    s->width = s->height = 4;
}

static void test_light_pdf(void)
{
    spm_scene s;
    scene_lights(&s);
    spm_geometry g;
    spm_error err;
    CHECK(spm_geometry_build(&s, &g, &err) == 0, "build: %s", err.msg);
    CHECK(g.emit_power == 1, "three lights of different power are picked by power");
    /* per triangle: its share of the power, area * e (Y is e times the CMF's
     * integral for a flat emission), within the table's rounding: a count of
     * 2^-24 each, and the rest of 2^24 (at most one count per emitter) */
    double total = 0.0, sum = 0.0, worst = 0.0;
    for (int i = 0; i < g.ntris; i++) {
        int c = s.materials[g.tris[i].material].emit;
        total += c >= 0 ? g.tris[i].area * s.colours[c].s.nm1[200] : 0.0;
    }
    for (int i = 0; i < g.ntris; i++) {
        int c = s.materials[g.tris[i].material].emit;
        double share = c >= 0 ? g.tris[i].area * s.colours[c].s.nm1[200] / total : 0.0;
        sum += g.light_pdf[i];
        worst = fmax(worst, fabs(g.light_pdf[i] - share));
    }
    CHECK(fabs(sum - 1.0) < 1e-6, "the light pdfs sum to 1: %.9f", sum);
    CHECK(worst <= (g.nemitters + 1.0) / SPM_EMIT_CDF_ONE, "light pdf off its power share by %.3g",
          worst);
    spm_geometry_free(&g);
    ts_free(&s);
}

typedef ts_ystats stats;

/* The scene's mean path Y with the CPU reference (ref mode), picking by
 * power or, uniform != 0, uniformly (the table rebuilt for equal powers). */
static stats render(const spm_scene *s, int uniform, spm_u32 spp, spm_u32 seed)
{
    stats st = {0, 0, 0, 0, 0};
    spm_geometry g;
    spm_error err;
    if (spm_geometry_build(s, &g, &err)) {
        CHECK(0, "build: %s", err.msg);
        return st;
    }
    if (uniform) {
        double *w = malloc((size_t)g.nemitters * sizeof *w);
        for (int i = 0; i < g.nemitters; i++)
            w[i] = 1.0;
        g.emit_power = spm_emitter_table_build(g.emitters, w, g.nemitters);
        free(w);
    }
    st = ts_ref_y(s, &g, spp, seed);
    spm_geometry_free(&g);
    return st;
}

static void test_convergence(void)
{
    spm_scene s;
    scene_lights(&s);
    stats pw = render(&s, 0, 4000, 21u), pw2 = render(&s, 0, 4000, 22u);
    stats un = render(&s, 1, 4000, 21u);
    printf("floor Y: by power %.5f (sem %.5f), seed 2 %.5f (sem %.5f); uniform %.5f (sem %.5f)\n",
           pw.mean, pw.sem, pw2.mean, pw2.sem, un.mean, un.sem);
    /* the noise floor: two seeds of the same pick differ by their standard
     * errors; the two picks must agree to the same measure, 5 combined
     * standard errors (false alarm about 1 in 1.7 million) */
    double tol = 5.0 * sqrt(pw.sem * pw.sem + un.sem * un.sem);
    CHECK(fabs(pw.mean - pw2.mean) <= 5.0 * sqrt(pw.sem * pw.sem + pw2.sem * pw2.sem),
          "two seeds by power: %.5f vs %.5f", pw.mean, pw2.mean);
    CHECK(fabs(pw.mean - un.mean) <= tol, "by power %.5f vs uniform %.5f (tol %.5f)", pw.mean,
          un.mean, tol);
    /* and the point of it: the strong light is sampled far more often */
    CHECK(pw.sem < 0.5 * un.sem, "by power is less noisy: sem %.5f vs uniform %.5f", pw.sem,
          un.sem);
    ts_free(&s);
}

int main(void)
{
    test_table();
    test_light_pdf();
    test_convergence();
    TEST_END();
}
