/* The environment map on the CPU (host/scene/envmap.h, the reference's
 * host/cpu/refcpu_light_envmap.c), on maps the test writes:
 *  - where a direction falls: Mitsuba 3's equirectangular convention (the
 *    top row up, the centre column along +z, a quarter along +x; `rotate`
 *    turning +z toward +x), each texel's luminance its grey value times the
 *    scale, written here independently of the reader;
 *  - the bilinear lookup: the mean of the texels an escape draws at points
 *    between texel centres (across the seam at u = 0 and by the poles)
 *    against the interpolation computed here; and the distribution's
 *    support: a positive density wherever the interpolation has light;
 *  - the palette: a grey map is one colour, a two-colour map two, each within
 *    a small distance in u'v' of its RGB's chromaticity;
 *  - chi-squared: the directions the map's distribution draws (through the
 *    contract's light_sample_emission) against the density an escaping ray
 *    is given for MIS (light_escape / the selection's pmf), whose integral
 *    over the sphere must be 1, on a map with a small sun, a black band and
 *    a rotation (tests/chi2_testlib.h);
 *  - strategies: under a map with a soft sun, a rough gold and a rough coated
 *    sphere on a rough diffuse floor render the same mean with MIS, light
 *    samples alone and the materials' sampling alone (SPECMIP_TEST_STRATEGY,
 *    as tests/test_strategies.c), which sees an MIS weight at an escape that
 *    does not match the light sample's density, and a distribution that
 *    misses where the interpolation reaches into black texels (the map's
 *    black columns). */
#include <string.h>
#include "chi2_testlib.h"
#include "colour.h"
#include "envmap_testlib.h"
#include "geometry.h"
#include "refcpu_lights.h"
#include "render_testlib.h"
#include <unistd.h>

/* a scene of one small far triangle (a scene needs one) under the map */
static int load(const char *map, const char *opts, spm_scene *s, spm_geometry *g)
{
    char line[1024];
    snprintf(line, sizeof line, "background map %s %s", map, opts);
    return envmap_test_scene("envmap_test.scene", line, s, g);
}

/* load() under a map of w x h texels fn writes first; 1 (a failure) when either fails */
static int write_load(const char *map, int w, int h, envmap_texel_fn fn, const char *opts,
                      spm_scene *s, spm_geometry *g)
{
    int rc = envmap_write_hdr(map, w, h, fn) || load(map, opts, s, g);
    CHECK(rc == 0, "the scene under %s loads", map);
    return rc;
}

/* the map an escaping ray of direction d meets, drawn by path n's numbers */
static spm_u32 escape(const spm_geometry *g, const spm_emitter *e, const float d[3], spm_u32 n,
                      float *scale, float *pdf)
{
    spm_ref_key k = {7u, 3u, n};
    return spm_ref_light_escape_ENVMAP(g, e, e->pdf, d, &k, 1u, scale, pdf);
}

static void grey_ramp(int i, int j, int w, int h, float rgb[3])
{
    (void)h;
    rgb[0] = rgb[1] = rgb[2] = (float)(1 + i + w * j) / 8.0f;
    envmap_quantise(rgb);
}

/* the direction of map coordinates (u, v) under a rotation of rot degrees
 * about +y, from Mitsuba 3's convention: theta = pi v from +y, and phi =
 * 2 pi u from -z toward +x, so u = 1/4 is +x and u = 1/2 is +z */
static void direction(double u, double v, double rot, double d[3])
{
    double th = M_PI * v, ph = 2.0 * M_PI * u, r = rot * M_PI / 180.0;
    double x = sin(th) * sin(ph), y = cos(th), z = -sin(th) * cos(ph);
    d[0] = cos(r) * x + sin(r) * z; /* +z turns toward +x */
    d[1] = y;
    d[2] = -sin(r) * x + cos(r) * z;
}

/* the ramp's texel (i, j), columns wrapping and rows clamped */
static double ramp_at(int i, int j, int w, int h)
{
    float c[3];
    grey_ramp((i + w) % w, j < 0 ? 0 : j >= h ? h - 1 : j, w, h, c);
    return c[0];
}

/* The bilinear interpolation at (u, v) of a w x h map's texel values at(i,
 * j) (columns wrapping, rows clamped, centres at k + 1/2) */
static double bilerp(double (*at)(int, int, int, int), double u, double v, int w, int h)
{
    double x = u * w - 0.5, y = v * h - 0.5;
    int i = (int)floor(x), j = (int)floor(y);
    double fx = x - i, fy = y - j;
    return (1 - fx) * (1 - fy) * at(i, j, w, h) + fx * (1 - fy) * at(i + 1, j, w, h) +
           (1 - fx) * fy * at(i, j + 1, w, h) + fx * fy * at(i + 1, j + 1, w, h);
}

/* the mean luminance of BILIN_N escapes at points between texel centres
 * against the bilinear interpolation of the texels' (times the scale, 2):
 * within BILIN_Z standard errors of the draws (normal; 5 leaves 1 in 10^6
 * of a correct lookup failing at each point) */
#define BILIN_N 20000
#define BILIN_Z 5.0

/* the mean over BILIN_N paths' draws of the luminance an escape along d
 * meets; *se its standard error */
static double mean_escape(const spm_geometry *g, const spm_emitter *e, const float d[3], double *se)
{
    double m = 0.0, m2 = 0.0;
    for (spm_u32 n = 0; n < BILIN_N; n++) {
        float sc, pdf;
        escape(g, e, d, n, &sc, &pdf);
        m += sc / BILIN_N, m2 += (double)sc * sc / BILIN_N;
    }
    *se = sqrt(fmax(m2 - m * m, 0.0) / (BILIN_N - 1));
    return m;
}

static void test_mapping(void)
{
    const int w = 16, h = 8;
    CHECK(envmap_write_hdr("envmap_ramp.hdr", w, h, grey_ramp) == 0, "write the map");
    for (int rot = 0; rot < 2; rot++) {
        spm_scene s;
        spm_geometry g;
        if (load("envmap_ramp.hdr", rot ? "scale 2 rotate 90" : "scale 2", &s, &g)) {
            CHECK(0, "the ramp scene loads");
            continue;
        }
        CHECK(s.env && s.env->ncolours == 1, "a grey map is one palette colour (%d)",
              s.env ? s.env->ncolours : -1);
        const spm_emitter *e = &g.emitters[g.nemitters - 1];
        CHECK(e->kind == SPM_LIGHT_ENVMAP, "the map is the selection's last light");
        int bad = 0;
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                double d[3];
                float df[3], scale, pdf, c[3];
                direction((i + 0.5) / w, (j + 0.5) / h, rot ? 90.0 : 0.0, d);
                for (int k = 0; k < 3; k++)
                    df[k] = (float)d[k];
                grey_ramp(i, j, w, h, c);
                spm_u32 col = escape(&g, e, df, 0u, &scale, &pdf);
                bad += col != (spm_u32)s.env->first || fabs(scale - 2.0 * c[0]) > 1e-5 * scale;
            }
        CHECK(bad == 0, "rotate %d: %d texels not where the convention puts them", rot * 90, bad);
        /* anchors: +y is the top row, and the direction the centre column
         * looks along is +z, or +x turned by 90 degrees */
        float up[3] = {0.0f, 1.0f, 0.0f}, n = 1.0f / sqrtf(1.01f);
        float ctr[3] = {rot ? n : 0.0f, -0.1f * n, rot ? 0.0f : n};
        float sc, pdf, c[3];
        escape(&g, e, up, 0u, &sc, &pdf);
        grey_ramp(0, 0, w, h, c);
        CHECK(sc >= 2.0f * c[0] && sc <= 2.0f * (c[0] + (float)w / 8.0f), "+y: the top row");
        double se, m = mean_escape(&g, e, ctr, &se);
        double want = 2.0 * bilerp(ramp_at, 0.5, acos(-0.1 / sqrt(1.01)) / M_PI, w, h);
        CHECK(fabs(m - want) <= BILIN_Z * se, "the centre column: %g, want %g", m, want);
        spm_geometry_free(&g);
        spm_scene_free(&s);
    }
}

static void test_bilinear(void)
{
    const int w = 16, h = 8;
    spm_scene s;
    spm_geometry g;
    if (envmap_write_hdr("envmap_ramp.hdr", w, h, grey_ramp) ||
        load("envmap_ramp.hdr", "scale 2 rotate 90", &s, &g)) {
        CHECK(0, "the ramp scene loads");
        return;
    }
    const spm_emitter *e = &g.emitters[g.nemitters - 1];
    /* (u, v): inside the map, across the seam at u = 0, above the top
     * row's centre (clamped), below the bottom row's */
    static const double pts[][2] = {{0.37, 0.41}, {0.71, 0.66}, {0.01, 0.3},
                                    {0.995, 0.55}, {0.2, 0.02}, {0.6, 0.97}};
    for (size_t p = 0; p < sizeof pts / sizeof pts[0]; p++) {
        double d[3], want = 2.0 * bilerp(ramp_at, pts[p][0], pts[p][1], w, h);
        float df[3];
        direction(pts[p][0], pts[p][1], 90.0, d);
        for (int k = 0; k < 3; k++)
            df[k] = (float)d[k];
        double se, m = mean_escape(&g, e, df, &se);
        printf("bilinear at (%.3f, %.3f): mean %.5f (se %.5f), interpolated %.5f\n", pts[p][0],
               pts[p][1], m, se, want);
        CHECK(fabs(m - want) <= BILIN_Z * se + 1e-6 * want,
              "bilinear at (%.3f, %.3f): mean %.5f, want %.5f (%.1f se)", pts[p][0], pts[p][1], m,
              want, se > 0.0 ? fabs(m - want) / se : 0.0);
    }
    spm_geometry_free(&g);
    spm_scene_free(&s);
}

/* 1 where the striped map's texel (i, j) (columns wrapping, rows clamped) has light */
static double striped_lit(int i, int j, int w, int h)
{
    float c[3];
    envmap_striped((i + w) % w, j < 0 ? 0 : j >= h ? h - 1 : j, w, h, c);
    return c[0] + c[1] + c[2] > 0.0f;
}

/* The distribution's support: an escape's density is positive wherever the
 * interpolation has light, on a map whose every other column is black (a
 * distribution of the texels' own luminance misses half of each black
 * column's width on either side), at SUPPORT_N directions uniform in
 * (u, v) under a rotation. */
#define SUPPORT_N 20000

static void test_support(void)
{
    const int w = 32, h = 16;
    spm_scene s;
    spm_geometry g;
    if (write_load("envmap_striped.hdr", w, h, envmap_striped, "rotate 30", &s, &g))
        return;
    const spm_emitter *e = &g.emitters[g.nemitters - 1];
    int lit = 0, missed = 0;
    spm_u32 st = 0x5e99u;
    for (int n = 0; n < SUPPORT_N; n++) {
        double u = (spm_mix32(st++) >> 8) / 16777216.0, v = (spm_mix32(st++) >> 8) / 16777216.0;
        double d[3];
        float df[3], sc, pdf;
        direction(u, 0.02 + 0.96 * v, 30.0, d); /* away from the poles, where sin(theta) -> 0 */
        for (int k = 0; k < 3; k++)
            df[k] = (float)d[k];
        escape(&g, e, df, (spm_u32)n, &sc, &pdf);
        if (bilerp(striped_lit, u, 0.02 + 0.96 * v, w, h) > 1e-4) {
            lit++;
            missed += !(pdf > 0.0f);
        }
    }
    printf("support: %d of %d directions have light, %d of them density 0\n", lit, SUPPORT_N,
           missed);
    CHECK(lit > SUPPORT_N / 2 && missed == 0,
          "%d of %d directions with light have density 0 (the distribution misses them)", missed,
          lit);
    spm_geometry_free(&g);
    spm_scene_free(&s);
}

static void two_colours(int i, int j, int w, int h, float rgb[3])
{
    (void)j, (void)h;
    int red = i < w / 2;
    rgb[0] = red ? 2.0f : 0.1f, rgb[1] = red ? 0.3f : 0.4f, rgb[2] = red ? 0.2f : 1.5f;
}

/* the palette's chromaticity error on a map of two colours, one cell each:
 * the lift's alone, polished to CIEDE2000 0.01 (rgb2spec_table.h), about
 * 1e-4 in u'v'; measured 4.6e-7 */
#define DUV_MAX 1e-4

static void test_palette(void)
{
    spm_scene s;
    spm_geometry g;
    if (write_load("envmap_two.hdr", 8, 4, two_colours, "", &s, &g))
        return;
    printf("palette: %d colours, u'v' error max %.2e, mean %.2e\n", s.env->ncolours,
           s.env->duv_max, s.env->duv_mean);
    CHECK(s.env->ncolours >= 2 && s.env->ncolours <= 8,
          "two colours, the nodes of their cells: 2 to 8 in the palette (%d)", s.env->ncolours);
    CHECK(s.env->duv_max < DUV_MAX, "u'v' error %.3g", s.env->duv_max);
    spm_geometry_free(&g);
    spm_scene_free(&s);
}

/* Two colours in one palette cell (face red, a = 2, b = 1 on the grid of
 * 16): shapes (1, .15, .10) on the left half at twice the luminance and
 * (1, .184, .117) on the right. */
static void one_cell(int i, int j, int w, int h, float rgb[3])
{
    (void)j, (void)h;
    int left = i < w / 2;
    rgb[0] = left ? 2.0f : 1.0f, rgb[1] = left ? 0.30f : 0.184f, rgb[2] = left ? 0.20f : 0.117f;
    envmap_quantise(rgb);
}

/* The colour a texel renders, in expectation its own: the mean XYZ of
 * PICK_N escapes at a texel's centre (each its drawn node's colour of Y = 1
 * times the texel's luminance) against the texel's own RGB in u'v'. A cell
 * mean's colour is off by the two shapes' distance times the other's share
 * of the cell's luminance (the former palette: 5.1e-3 and 8.8e-3); the node
 * pick's offset is its noise, within PICK_Z standard errors of the draws'
 * u'v' (a correct pick fails 1 in 10^6), plus the lift's error DUV_MAX. */
#define PICK_N 20000
#define PICK_Z 5.0

static void uvp(const double xyz[3], double uv[2])
{
    double den = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
    uv[0] = 4.0 * xyz[0] / den, uv[1] = 9.0 * xyz[1] / den;
}

static void test_node_pick(void)
{
    const int w = 8, h = 4;
    spm_scene s;
    spm_geometry g;
    if (write_load("envmap_cell.hdr", w, h, one_cell, "", &s, &g))
        return;
    const spm_emitter *e = &g.emitters[g.nemitters - 1];
    for (int i = 1; i < w; i += 5) {
        float c[3], fd[3];
        double d[3], own[3], in[3], m[3] = {0.0, 0.0, 0.0}, a[2], b[2];
        one_cell(i, 1, w, h, c);
        direction((i + 0.5) / w, 1.5 / h, 0.0, d);
        for (int k = 0; k < 3; k++)
            fd[k] = (float)d[k], in[k] = c[k];
        spm_linear_srgb_to_xyz(in, own);
        int bad = 0;
        double q[2] = {0.0, 0.0}, q2[2] = {0.0, 0.0};
        for (spm_u32 n = 0; n < PICK_N; n++) {
            float sc, pdf;
            double xyz[3], p[2];
            spm_u32 id = escape(&g, e, fd, n, &sc, &pdf);
            if (id == SPM_NONE || id >= (spm_u32)s.ncolours) {
                bad++;
                continue;
            }
            spm_xyz_emission(&s.colours[id].s, xyz);
            uvp(xyz, p);
            for (int k = 0; k < 3; k++)
                m[k] += sc * xyz[k] / PICK_N;
            for (int k = 0; k < 2; k++)
                q[k] += p[k] / PICK_N, q2[k] += p[k] * p[k] / PICK_N;
        }
        double se = sqrt(fmax(q2[0] - q[0] * q[0] + q2[1] - q[1] * q[1], 0.0) / (PICK_N - 1));
        uvp(own, a);
        uvp(m, b);
        double du = hypot(a[0] - b[0], a[1] - b[1]);
        printf("node pick at texel %d: mean u'v' (%.5f, %.5f), own (%.5f, %.5f), off %.2e "
               "(se %.2e); Y %.4f of %.4f\n", i, b[0], b[1], a[0], a[1], du, se, m[1], own[1]);
        CHECK(bad == 0, "every escape meets a colour of the palette (%d do not)", bad);
        CHECK(du < PICK_Z * se + DUV_MAX, "texel %d's expected chromaticity its own: off %.2e u'v'",
              i, du);
    }
    spm_geometry_free(&g);
    spm_scene_free(&s);
}

typedef struct {
    const spm_geometry *g;
    int k;
} env_ctx;

static int sample_map(void *ctx, const double wo[3], const double u[3], double wi[3], double *pdf,
                      double *w)
{
    (void)wo;
    const env_ctx *c = ctx;
    float uf[4] = {(float)u[0], (float)u[1], (float)u[2], 0.5f}, o[3], d[3], pp, pd;
    spm_ref_light_sample_emission(c->g, (spm_u32)c->k, uf, o, d, &pp, &pd);
    for (int k = 0; k < 3; k++)
        wi[k] = -d[k]; /* toward the map */
    *pdf = pd;
    *w = 1.0;
    return pd > 0.0f;
}

static double pdf_map(void *ctx, const double wo[3], const double wi[3])
{
    (void)wo;
    const env_ctx *c = ctx;
    const spm_emitter *e = &c->g->emitters[c->k];
    float d[3] = {(float)wi[0], (float)wi[1], (float)wi[2]}, sc, pdf;
    escape(c->g, e, d, 0u, &sc, &pdf);
    return pdf / e->pdf;
}

static void test_chi2(void)
{
    spm_scene s;
    spm_geometry g;
    if (write_load("envmap_sun.hdr", 64, 32, envmap_sun, "rotate 30", &s, &g))
        return;
    env_ctx c = {&g, g.nemitters - 1};
    chi2_sampler smp = {"environment map", &c, sample_map, pdf_map, NULL};
    double wo[3] = {0.0, 0.0, 1.0};
    chi2_run(&smp, wo, 400000, 0x5eed0e00u, 0.01);
    spm_geometry_free(&g);
    spm_scene_free(&s);
}

#define STRAT_SEEDS 6
#define STRAT_SPP 48
#define STRAT_SIZE 24
/* a strategy's mean against MIS's: within Z_MAX standard errors of their
 * per-seed difference (normal, 6 seeds: 4.5 leaves 1 in 100000 of a correct
 * estimator failing) */
#define Z_MAX 4.5

static void test_strategies(void)
{
    FILE *f = envmap_write_hdr("envmap_soft.hdr", 64, 32, envmap_striped) ? NULL
                                                                           : fopen("envmap_strat.scene", "w");
    char cwd[512], path[700];
    if (!f || !getcwd(cwd, sizeof cwd)) {
        CHECK(0, "cannot write the strategies' scene");
        if (f)
            fclose(f);
        return;
    }
    fprintf(f, "image 24 24\ncamera position 0 1.1 -4  direction 0 -0.2 1  fov 40\nspectrum grey equal\n"
               "spectrum au_eta file metal_Au_eta.csv\nspectrum au_k file metal_Au_k.csv\n"
               "material floor roughdiffuse reflect grey 0.5 roughness 0.5\n"
               "material gold conductor au_eta au_k alpha 0.3\n"
               "material paint coated reflect grey 0.6 ior 1.5 alpha 0.2\n"
               "background map envmap_soft.hdr rotate 40\n"
               "quad floor  -60 0 -60  -60 0 60  60 0 60  60 0 -60\n"
               "mesh %s/scenes/materials_sphere.ply material gold scale 0.6 translate -0.7 0.6 0.3\n"
               "mesh %s/scenes/materials_sphere.ply material paint scale 0.6 translate 0.7 0.6 0.3\n",
            SPM_SOURCE_DIR, SPM_SOURCE_DIR);
    fclose(f);
    snprintf(path, sizeof path, "%s/envmap_strat.scene", cwd);
    static const char *const names[3] = {NULL, "light", "lobe"};
    double mean[3][STRAT_SEEDS];
    rt_keep_scene = 1; /* the scene's pretest once, not per strategy and seed */
    for (int st = 0; st < 3; st++)
        for (int k = 0; k < STRAT_SEEDS; k++) {
            if (names[st])
                setenv("SPECMIP_TEST_STRATEGY", names[st], 1);
            else
                unsetenv("SPECMIP_TEST_STRATEGY");
            rt_render_job j = {path, SPM_MODE_RGB, STRAT_SPP, 11u + (spm_u32)k, STRAT_SIZE, 0.0, "cpu"};
            rt_render_out o;
            mean[st][k] = 0.0;
            if (rt_render(&j, &o, NULL, NULL)) {
                CHECK(0, "the strategies' scene renders");
                return;
            }
            for (int p = 0; p < STRAT_SIZE * STRAT_SIZE; p++)
                mean[st][k] += (0.2126 * o.img.rgb[3 * p] + 0.7152 * o.img.rgb[3 * p + 1] +
                                0.0722 * o.img.rgb[3 * p + 2]) / (STRAT_SIZE * STRAT_SIZE);
            free(o.img.rgb);
        }
    unsetenv("SPECMIP_TEST_STRATEGY");
    rt_kept_free();
    rt_keep_scene = 0;
    for (int st = 1; st < 3; st++) {
        double s = 0.0, s2 = 0.0;
        for (int k = 0; k < STRAT_SEEDS; k++) {
            double d = mean[st][k] - mean[0][k];
            s += d, s2 += d * d;
        }
        double m = s / STRAT_SEEDS, se = sqrt((s2 / STRAT_SEEDS - m * m) / (STRAT_SEEDS - 1));
        printf("strategies: %s alone - MIS %.5f (se %.5f) of a mean %.4f\n", names[st], m, se,
               mean[0][0]);
        CHECK(se > 0.0 && fabs(m) <= Z_MAX * se, "%s alone differs from MIS by %.4f (%.1f se)",
              names[st], m, se > 0.0 ? fabs(m) / se : 0.0);
    }
}

int main(void)
{
    test_mapping();
    test_bilinear();
    test_support();
    test_palette();
    test_node_pick();
    test_chi2();
    test_strategies();
    TEST_END();
}
