/* The rough diffuse material (EON) on both backends:
 *  - a white (rho = 1) rough diffuse sphere under a uniform sky is
 *    invisible: EON conserves energy, every path that meets it carries on
 *    average exactly the background (roughness 0.5 and 1);
 *  - a grey rough plane (rho = 0.5) under a uniform sky: the mean of its
 *    paths against its directional albedo rho E(mu) + rho_ms (1 - E(mu)),
 *    E the single-scattering term's albedo integrated here numerically from
 *    the paper's f_ss and E_avg its cosine-weighted mean, rho_ms =
 *    rho^2 E_avg / (1 - rho (1 - E_avg)) (a vertex recording rho instead of
 *    its derived colour fails it);
 *  - roughness 0 is the Lambertian: the same scene with 'reflect' alone
 *    traces the same paths and shades the same pixels, bit for bit;
 *  - the kernel's trace against the reference's, path by path, on
 *    scenes/roughdiffuse.scene (records, level bytes), and each mode's shade
 *    kernel against the reference's shading of the same records. */
#include "cl_testlib.h"
#include "testutil.h"

#define SEED 11u
#define NSIGMA 4.0 /* 4 standard errors: a render that is right fails 6 times in 10^5 */

/* ---- the model's single-scattering term, from the paper, in double -------- */
static double fss(double r, double mo, double mi, double cphi)
{
    double so = sqrt(1.0 - mo * mo), si = sqrt(1.0 - mi * mi);
    double s = so * si * cphi; /* wi.wo - mu_i mu_o */
    double t = s > 0.0 ? fmax(mi, mo) : 1.0;
    double a = 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * M_PI)) * r);
    return a * (1.0 + r * s / t) / M_PI;
}

/* its directional albedo at mu: midpoint rule in (cos_i, phi), 512 x 256 (at
 * 1024 x 512 it moves by < 3e-5) */
static double ess(double r, double mu)
{
    const int n = 512, np = 256;
    double e = 0.0;
    for (int i = 0; i < n; i++) {
        double mi = (i + 0.5) / n;
        for (int k = 0; k < np; k++)
            e += fss(r, mu, mi, cos(M_PI * (k + 0.5) / np)) * mi;
    }
    return e * (1.0 / n) * (2.0 * M_PI / np);
}

/* ---- the white sphere ----------------------------------------------------- */
#define SW 48
#define SH 48

static int load_written(cl_test_scene *s, const char *path, const char *text, int w, int h,
                        const char *sphere_mat)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fputs(text, f);
    if (sphere_mat)
        cl_test_write_sphere(f, sphere_mat);
    fclose(f);
    return cl_test_scene_load(s, path, w, h);
}

static int multiple_first(const spm_path *p, void *ctx)
{
    return p->h.nvert > 0 && (p->v[0].ids & 0xFFFFu) == *(const spm_u32 *)ctx;
}

static void test_sphere(double r, int spp)
{
    char text[512];
    snprintf(text, sizeof text,
             "image %d %d\ncamera position 0 0 -3 direction 0 0 1 fov 40\n"
             "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\nspectrum white equal\n"
             "material clay roughdiffuse reflect white roughness %.17g\nbackground both sky 1\n",
             SW, SH, r);
    cl_test_scene s;
    if (load_written(&s, "roughdiffuse_sphere.scene", text, SW, SH, "clay")) {
        CHECK(0, "the sphere scene loads");
        return;
    }
    size_t n = (size_t)SW * SH * spp;
    spm_u32 ms = s.tables.materials[0].col2;
    cl_test_furnace_result res[2];
    cl_test_furnace(&s, SEED, SW, SH, spp, NULL, multiple_first, &ms, res);
    for (int cl = 0; cl < 2; cl++) {
        const cl_test_furnace_result *q = &res[cl];
        CHECK(!q->failed, "the sphere renders (%s)", cl ? "opencl" : "cpu");
        printf("white sphere r %.2f (%s): %zu paths meet it (%zu first vertices multiple), "
               "mean / background - 1 = %.5f +- %.5f\n", r, cl ? "opencl" : "cpu", q->met,
               q->counted, q->mean, q->se);
        CHECK(q->met > n / 3 && q->counted > q->met / 50,
              "too few paths meet the sphere's two terms");
        CHECK(fabs(q->mean) <= NSIGMA * q->se, "r %.2f (%s): the white sphere is not invisible: "
              "%.5f +- %.5f", r, cl ? "opencl" : "cpu", q->mean, q->se);
    }
    cl_test_scene_close(&s);
}

/* ---- the grey furnace ----------------------------------------------------- */
#define PW 16
#define PH 12

typedef struct {
    double r, rho, rms;
} eon_model;

/* rho E(mu) + rho_ms (1 - E(mu)) */
static double eon_albedo(void *ctx, double mu)
{
    const eon_model *m = ctx;
    double e = ess(m->r, mu);
    return m->rho * e + m->rms * (1.0 - e);
}

static void test_furnace(double r, double rho)
{
    char text[512];
    snprintf(text, sizeof text,
             "image %d %d\ncamera position 0 1 -1 direction 0 -1 1 fov 70\n"
             "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\nspectrum white equal\n"
             "material clay roughdiffuse reflect white %.17g roughness %.17g\n"
             "quad clay -100 0 -100  -100 0 100  100 0 100  100 0 -100\n"
             "background up sky 1\n", PW, PH, rho, r);
    cl_test_scene s;
    if (load_written(&s, "roughdiffuse_plane.scene", text, PW, PH, NULL)) {
        CHECK(0, "the plane scene loads");
        return;
    }
    const int spp = 256;
    size_t n = (size_t)PW * PH * spp;
    double eavg = 0.0, lo, hi;
    for (int i = 0; i < 256; i++) { /* E_avg = int E(mu) 2 mu dmu, midpoint */
        double mu = (i + 0.5) / 256;
        eavg += ess(r, mu) * 2.0 * mu / 256;
    }
    eon_model m = {r, rho, rho * rho * eavg / (1.0 - rho * (1.0 - eavg))};
    double *want = cl_test_plane_want(&s, SEED, spp, eon_albedo, &m, &lo, &hi);
    printf("furnace r %.2f rho %.2f: E_avg %.5f, rho_ms %.5f; albedo %.4f at cos %.3f, %.4f at "
           "cos %.3f\n", r, rho, eavg, m.rms, eon_albedo(&m, lo), lo, eon_albedo(&m, hi), hi);
    cl_test_furnace_result res[2];
    cl_test_furnace(&s, SEED, PW, PH, spp, want, NULL, NULL, res);
    for (int cl = 0; cl < 2; cl++) {
        const cl_test_furnace_result *q = &res[cl];
        CHECK(!q->failed, "the plane renders (%s)", cl ? "opencl" : "cpu");
        printf("furnace (%s): %zu paths, mean of (path / background - albedo) = %.5f +- %.5f\n",
               cl ? "opencl" : "cpu", q->met, q->mean, q->se);
        CHECK(q->met == n, "every path meets the plane (%zu of %zu)", q->met, n);
        CHECK(fabs(q->mean) <= NSIGMA * q->se, "r %.2f rho %.2f (%s): the furnace is off its "
              "albedo: %.5f +- %.5f", r, rho, cl ? "opencl" : "cpu", q->mean, q->se);
    }
    free(want);
    cl_test_scene_close(&s);
}

/* ---- roughness 0 is the Lambertian ---------------------------------------- */
#define LW 24
#define LH 24
#define LSPP 16

static void test_lambert(void)
{
    const char *head = "camera position 0.5 0.6 -1.2 direction 0 -0.3 1 fov 50\n"
                       "spectrum grey inline 380 0.2 550 0.6 780 0.4 end\nspectrum equal equal\n";
    const char *body =
        "material light reflect grey emit equal 20\nbackground up grey 0.5\n"
        "quad clay -5 0 -5  -5 0 1  5 0 1  5 0 -5\nquad clay -5 0 1  -5 5 1  5 5 1  5 0 1\n"
        "quad light 0.4 0.9 0.6  0.4 0.9 0.4  0.6 0.9 0.4  0.6 0.9 0.6\n";
    const char *mat[2] = {"reflect grey", "roughdiffuse reflect grey roughness 0"};
    size_t n = (size_t)LW * LH * LSPP;
    spm_path *paths[2][2];
    float *xyz[2][2];
    for (int v = 0; v < 2; v++) {
        char text[1024];
        snprintf(text, sizeof text, "image %d %d\n%smaterial clay %s\n%s", LW, LH, head, mat[v],
                 body);
        cl_test_scene s;
        if (load_written(&s, "roughdiffuse_r0.scene", text, LW, LH, NULL)) {
            CHECK(0, "the roughness-0 scene loads (%s)", mat[v]);
            return;
        }
        for (int cl = 0; cl < 2; cl++) {
            paths[v][cl] = spm_xcalloc(n, sizeof(spm_path));
            xyz[v][cl] = spm_xcalloc(3 * n, sizeof(float));
            CHECK(!cl_test_render_truth(&s, cl, SEED, LW, LH, LSPP, paths[v][cl], xyz[v][cl]),
                  "the roughness-0 scene renders");
        }
        cl_test_scene_close(&s);
    }
    for (int cl = 0; cl < 2; cl++) {
        size_t differ = 0, lit = 0;
        for (size_t i = 0; i < n; i++) {
            differ += memcmp(&paths[0][cl][i], &paths[1][cl][i], sizeof(spm_path)) != 0;
            lit += xyz[0][cl][3 * i + 1] > 0.0f;
        }
        int same = !memcmp(xyz[0][cl], xyz[1][cl], 3 * n * sizeof(float));
        printf("roughness 0 against Lambertian (%s): %zu of %zu paths differ, pixels %s, %zu "
               "lit\n", cl ? "opencl" : "cpu", differ, n, same ? "identical" : "differ", lit);
        CHECK(differ == 0 && same && lit > n / 2, "roughness 0 is not the Lambertian (%s)",
              cl ? "opencl" : "cpu");
        for (int v = 0; v < 2; v++)
            free(paths[v][cl]), free(xyz[v][cl]);
    }
}

/* ---- kernel against reference ------------------------------------------- */
#define W 32
#define H 32
#define SPP 16
#define MAX_DIVERGENT_FRACTION 1e-3 /* as test_cl_trace */
#define SHADE_REL 1e-4              /* as test_cl_coated: no spectral arithmetic of its own */

static void trace_compare(void *ctx, const cl_test_scene *s, spm_cl_renderer *r,
                          const spm_path *cp, const uint8_t *cl, size_t n)
{
    size_t diverged = 0, level_diff = 0, ms = 0, ss = 0;
    spm_path *gp = spm_xcalloc(n, sizeof *gp);
    uint8_t *gl = spm_xcalloc(n, 1);
    spm_error err;
    (void)ctx;
    CHECK(spm_cl_trace(r, 0, SPP, gp, gl, &err) == 0, "spm_cl_trace: %s", err.msg);
    for (size_t i = 0; i < n; i++) {
        int d = cl_test_path_differs(&gp[i], &cp[i]);
        diverged += d;
        level_diff += !d && gl[i] != cl[i];
        for (spm_u32 j = 0; j < cp[i].h.nvert; j++)
            for (int m = 0; m < s->tables.nmaterials; m++) {
                spm_material mt = s->tables.materials[m];
                spm_u32 id = cp[i].v[j].ids & 0xFFFFu;
                if (SPM_MAT_TAG(mt) == SPM_MAT_ROUGHDIFFUSE && mt.col2 != SPM_NONE) {
                    ms += id == mt.col2;
                    ss += id == mt.refl;
                }
            }
    }
    printf("scene trace: %zu paths, %zu single- and %zu multiple-scattering rough vertices; "
           "%zu diverged, %zu level bytes differ\n", n, ss, ms, diverged, level_diff);
    CHECK(ms > n / 400 && ss > n / 10, "too little rough diffuse transport");
    CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu paths diverged", diverged);
    CHECK(level_diff == 0, "%zu level bytes differ", level_diff);
    free(gp);
    free(gl);
}

static void test_scene(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/roughdiffuse.scene", SPM_SOURCE_DIR);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "scenes/roughdiffuse.scene loads");
        return;
    }
    int failed = cl_test_modes(&s, SEED, SPP, SHADE_REL, "scene", trace_compare, NULL);
    CHECK(failed == 0, "%d modes shade the scene off the reference", failed);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_sphere(0.5, 16);
    test_sphere(1.0, 16);
    test_furnace(0.6, 0.5);
    test_furnace(1.0, 0.8);
    test_lambert();
    test_scene();
    TEST_END();
}
