/* The coated material on both backends:
 *  - a smooth coated sphere with a white base in a uniform background is
 *    invisible: every path that meets it carries, on average, exactly the
 *    background (Fo + (1 - Fo) (1 - Fdr_e) / (eta^2 (1 - Fdr_i)) = 1 only
 *    when Fdr_i is the average of the Fresnel the kernels sample; at index
 *    2.5 Mitsuba's polynomial fit of Fdr would make it 3 % brighter);
 *  - a rough coated plane with a white base under a uniform sky, a white
 *    furnace: the mean of its paths against the directional albedo of the
 *    model integrated here numerically (single-scatter GGX loses energy, so
 *    the albedo is below 1), both from this file's own quadratures; the same
 *    with a grey base (0.5), smooth and rough, whose diffuse part is the
 *    nonlinear R / (1 - Fdr_i R) (a vertex recording R instead of its
 *    derived colour fails it);
 *  - the kernel's trace against the reference's, path by path, on a box
 *    with a smooth and a rough coated object (records, the vertex words,
 *    level bytes), and each mode's shade kernel against the reference's
 *    shading of the same records. */
#include "typebox_testlib.h"

#define SEED 7u

/* ---- the model, in double, from its formulas (kernels/coated.clh) -------- */
static double fresnel(double eta, double c)
{
    double s2 = (1.0 - c * c) / (eta * eta);
    if (s2 >= 1.0)
        return 1.0;
    double ct = sqrt(1.0 - s2);
    double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* integral of F(eta, mu) 2 mu dmu over [0, 1], midpoint rule on 2^20 cells
 * (against 2^21: changes below 1e-9) */
static double fdr(double eta)
{
    const int n = 1 << 20;
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        double mu = (i + 0.5) / n;
        s += fresnel(eta, mu) * 2.0 * mu;
    }
    return s / n;
}

static double lambda(double a, double z)
{
    double t2 = (1.0 - z * z) / (z * z);
    return 0.5 * (-1.0 + sqrt(1.0 + a * a * t2));
}

/* The directional albedo of a grey base R under a GGX coating (alpha a,
 * index eta) at cos_o: the specular lobe's integral of
 * F(wo.h) D(h) G2 / (4 cos_o) over the hemisphere (midpoint in cos_i and phi,
 * 512 x 512: against 1024 x 1024 the albedo moves by < 2e-4; a = 0: F(cos_o))
 * plus the diffuse lobe's (1 - Fo) (1 - Fdr_e) R / (eta^2 (1 - Fdr_i R)),
 * Mitsuba's nonlinear plastic. */
static double albedo(double a, double eta, double co, double fi, double fe, double R)
{
    double dif = (1.0 - fresnel(eta, co)) * (1.0 - fe) * R / (eta * eta * (1.0 - fi * R));
    if (a == 0.0)
        return fresnel(eta, co) + dif;
    const int n = 512;
    double so = sqrt(1.0 - co * co), spec = 0.0;
    for (int i = 0; i < n; i++) {
        double ci = (i + 0.5) / n, si = sqrt(1.0 - ci * ci);
        for (int k = 0; k < n; k++) {
            double ph = 2.0 * M_PI * (k + 0.5) / n;
            double wi[3] = {si * cos(ph), si * sin(ph), ci}, wo[3] = {so, 0.0, co};
            double h[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
            double l = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
            for (int c = 0; c < 3; c++)
                h[c] /= l;
            double t = h[2] * h[2] * (a * a - 1.0) + 1.0, d = a * a / (M_PI * t * t);
            double g2 = 1.0 / (1.0 + lambda(a, co) + lambda(a, ci));
            double ch = wo[0] * h[0] + wo[2] * h[2];
            spec += fresnel(eta, ch) * d * g2 / (4.0 * co); /* f cos_i, dw = dcos_i dphi */
        }
    }
    spec *= (1.0 / n) * (2.0 * M_PI / n);
    return spec + dif;
}

/* Renders scene `path` (w x h, spp) in truth on backend `cl` (0: the CPU
 * reference), into paths and xyz (n of each). */
static int render(cl_test_scene *s, int cl, int w, int h, int spp, spm_path *paths, float *xyz)
{
    size_t n = (size_t)w * h * spp;
    spm_trace_params p = cl_test_params(s, SEED, 0, (spm_u32)spp);
    uint8_t *levels = spm_xcalloc(n, 1);
    int rc = 0;
    if (!cl) {
        spm_ref_trace(&s->geom, s->tables.materials, NULL, &p, paths, levels);
        memset(levels, 0, n);
        spm_ref_shade(&s->tables, SPM_MODE_TRUTH, &p, 0, paths, levels, n, xyz);
    } else {
        spm_cl_renderer *r;
        spm_error err;
        rc = spm_cl_create(0, &s->geom, &s->tables, SPM_MODE_TRUTH, SEED, &r, &err);
        if (!rc) {
            rc = spm_cl_trace(r, 0, (spm_u32)spp, paths, levels, &err) ||
                 spm_cl_shade(r, 0, (spm_u32)spp, paths, levels, xyz, &err);
            spm_cl_destroy(r);
        }
        if (rc)
            printf("opencl: %s\n", err.msg);
    }
    free(levels);
    return rc;
}

static double bg_y(const cl_test_scene *s)
{
    const float *bg = s->tables.truth + (size_t)s->tables.bg_up * SPM_TRUTH_BINS;
    double y = 0.0;
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        y += bg[b] * s->tables.cmf_truth[1][b];
    return y;
}

/* ---- the invisible sphere ------------------------------------------------- */
#define SW 48
#define SH 48

static void write_sphere(const char *path, double eta)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return;
    fprintf(f, "image %d %d\ncamera position 0 0 -3 direction 0 0 1 fov 40\n"
               "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\n"
               "spectrum white equal\n"
               "material coat coated reflect white ior %.17g\n"
               "background both sky 1\n", SW, SH, eta);
    /* a UV sphere of radius 1: 24 bands of 48 quads (fans at the poles) */
    const int nt = 24, np = 48;
    for (int i = 0; i < nt; i++)
        for (int k = 0; k < np; k++) {
            double v[4][3];
            for (int c = 0; c < 4; c++) {
                double th = M_PI * (i + (c == 2 || c == 3)) / nt;
                double ph = 2.0 * M_PI * (k + (c == 1 || c == 2)) / np;
                v[c][0] = sin(th) * cos(ph), v[c][1] = cos(th), v[c][2] = sin(th) * sin(ph);
            }
            if (i > 0)
                fprintf(f, "tri coat %.9g %.9g %.9g  %.9g %.9g %.9g  %.9g %.9g %.9g\n", v[0][0],
                        v[0][1], v[0][2], v[1][0], v[1][1], v[1][2], v[2][0], v[2][1], v[2][2]);
            if (i < nt - 1)
                fprintf(f, "tri coat %.9g %.9g %.9g  %.9g %.9g %.9g  %.9g %.9g %.9g\n", v[0][0],
                        v[0][1], v[0][2], v[2][0], v[2][1], v[2][2], v[3][0], v[3][1], v[3][2]);
        }
    fclose(f);
}

/* The mean ratio of a path's Y to the background's over the paths that meet
 * the object, and its standard error. */
static void ratio_stats(const spm_path *paths, const float *xyz, size_t n, double ybg,
                        const double *want, double *mean, double *se, size_t *met)
{
    double s = 0.0, s2 = 0.0;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (paths[i].h.nvert == 0)
            continue;
        double r = xyz[3 * i + 1] / ybg - (want ? want[i] : 1.0);
        s += r;
        s2 += r * r;
        m++;
    }
    *met = m;
    *mean = m ? s / (double)m : 0.0;
    *se = m > 1 ? sqrt((s2 / (double)m - *mean * *mean) / (double)(m - 1)) : 1.0;
}

/* 4 standard errors: a render that is right fails 6 times in 10^5 */
#define NSIGMA 4.0

static void test_sphere(double eta, int spp)
{
    const char *path = "coated_sphere.scene";
    write_sphere(path, eta);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, SW, SH)) {
        CHECK(0, "the sphere scene loads");
        return;
    }
    size_t n = (size_t)SW * SH * spp;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    double ybg = bg_y(&s);
    for (int cl = 0; cl < 2; cl++) {
        if (render(&s, cl, SW, SH, spp, paths, xyz)) {
            CHECK(0, "the sphere renders (%s)", cl ? "opencl" : "cpu");
            continue;
        }
        double mean, se;
        size_t met, diffuse = 0;
        for (size_t i = 0; i < n; i++)
            diffuse += paths[i].h.nvert > 0 && paths[i].v[0].ids != 0xFFFFFFFFu &&
                       (paths[i].v[0].ids & 0xFFFFu) == s.tables.materials[0].refl;
        ratio_stats(paths, xyz, n, ybg, NULL, &mean, &se, &met);
        printf("sphere eta %.2f (%s): %zu paths meet it (%zu diffuse), mean / background - 1 = "
               "%.5f +- %.5f\n", eta, cl ? "opencl" : "cpu", met, diffuse, mean, se);
        CHECK(met > n / 3 && diffuse > met / 3, "too few paths meet the sphere's base");
        CHECK(fabs(mean) <= NSIGMA * se, "eta %.2f (%s): the sphere is not invisible: %.5f +- %.5f",
              eta, cl ? "opencl" : "cpu", mean, se);
    }
    free(paths);
    free(xyz);
    cl_test_scene_close(&s);
}

/* ---- the rough white furnace ------------------------------------------- */
#define PW 16
#define PH 12
#define NTAB 64

static void test_furnace(double a, double eta, double R)
{
    const char *path = "coated_plane.scene";
    FILE *f = fopen(path, "w");
    if (!f) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    fprintf(f, "image %d %d\ncamera position 0 1 -1 direction 0 -1 1 fov 70\n"
               "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\n"
               "spectrum white equal\n"
               "material coat coated reflect white %.17g ior %.17g alpha %.17g\n"
               "quad coat -100 0 -100  -100 0 100  100 0 100  100 0 -100\n"
               "background up sky 1\n", PW, PH, R, eta, a);
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, PW, PH)) {
        CHECK(0, "the plane scene loads");
        return;
    }
    const int spp = 256;
    size_t n = (size_t)PW * PH * spp;
    spm_trace_params p = cl_test_params(&s, SEED, 0, (spm_u32)spp);
    double fi = fdr(1.0 / eta), fe = fdr(eta), tab[NTAB + 1], lo = 1.0, hi = 0.0;
    double *want = spm_xcalloc(n, sizeof *want);
    for (size_t i = 0; i < n; i++) {
        double d[3];
        tb_camera_dir(&p, i, d);
        lo = fmin(lo, fabs(d[1]));
        hi = fmax(hi, fabs(d[1]));
    }
    for (int k = 0; k <= NTAB; k++) /* the albedo at cosines across [lo, hi], linear between */
        tab[k] = albedo(a, eta, lo + (hi - lo) * k / NTAB, fi, fe, R);
    for (size_t i = 0; i < n; i++) {
        double d[3];
        tb_camera_dir(&p, i, d);
        double u = (fabs(d[1]) - lo) / (hi - lo) * NTAB;
        int k = (int)u < NTAB ? (int)u : NTAB - 1;
        want[i] = tab[k] + (u - k) * (tab[k + 1] - tab[k]);
    }
    printf("furnace alpha %.2f eta %.2f base %.2f: albedo %.4f at cos %.3f, %.4f at cos %.3f\n", a, eta,
           R, tab[0], lo, tab[NTAB], hi);
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    double ybg = bg_y(&s);
    for (int cl = 0; cl < 2; cl++) {
        if (render(&s, cl, PW, PH, spp, paths, xyz)) {
            CHECK(0, "the plane renders (%s)", cl ? "opencl" : "cpu");
            continue;
        }
        double mean, se;
        size_t met;
        ratio_stats(paths, xyz, n, ybg, want, &mean, &se, &met);
        printf("furnace (%s): %zu paths, mean of (path / background - albedo) = %.5f +- %.5f\n",
               cl ? "opencl" : "cpu", met, mean, se);
        CHECK(met == n, "every path meets the plane (%zu of %zu)", met, n);
        CHECK(fabs(mean) <= NSIGMA * se, "alpha %.2f (%s): the furnace is off its albedo: "
              "%.5f +- %.5f", a, cl ? "opencl" : "cpu", mean, se);
    }
    free(want);
    free(paths);
    free(xyz);
    cl_test_scene_close(&s);
}

/* ---- kernel against reference ------------------------------------------- */
static int ext_differs(const spm_path *a, const spm_path *b)
{
    for (spm_u32 j = 0; j < a->h.nvert; j++) {
        const spm_vertex_ext *x = &a->x[j], *y = &b->x[j];
        if (x->ids != y->ids || x->light != y->light || x->lobe != y->lobe ||
            !cl_test_close_rel(x->hit_c, y->hit_c))
            return 1;
    }
    return 0;
}

/* The shade kernels fuse and reorder as test_cl_shade explains; a coated
 * vertex adds no spectral arithmetic of its own. Bound as test_cl_conductor's. */
#define SHADE_REL 1e-4

/* the specular coating's vertices (those of its white colour) in the
 * reference's records */
typedef struct {
    size_t spec, hits, lights;
} coat_counts;

static void coat_count(const cl_test_scene *s, const spm_path *g, const spm_path *c, int diverged,
                       void *ctx)
{
    coat_counts *k = ctx;
    (void)g, (void)diverged;
    spm_u32 white = SPM_NONE;
    for (int m = 0; m < s->tables.nmaterials; m++)
        if (SPM_MAT_TAG(s->tables.materials[m]) == SPM_MAT_COATED)
            white = s->tables.materials[m].col2;
    for (spm_u32 j = 0; j < c->h.nvert; j++) {
        int is = (c->v[j].ids & 0xFFFFu) == white;
        k->spec += is;
        k->hits += SPM_VX_HIT(c->x[j]) != SPM_NONE;
        k->lights += is && (c->v[j].ids >> 16) != SPM_NONE;
    }
}

static void coat_report(size_t n, void *ctx)
{
    const coat_counts *k = ctx;
    printf("box: %zu specular coating vertices (%zu light samples, %zu lobe hits)\n", k->spec,
           k->lights, k->hits);
    CHECK(k->spec > n / 50 && k->hits > 5 && k->lights > 50, "too little coating transport");
}

static void test_box(void)
{
    coat_counts k = {0, 0, 0};
    tb_box b = {"coated_box.scene", 32, 32, 32, SEED, SHADE_REL, ext_differs, coat_count,
                coat_report, &k};
    tb_box_run(&b);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_sphere(2.5, 32);
    test_sphere(1.5, 32);
    test_furnace(0.3, 1.5, 1.0);
    test_furnace(0.6, 2.5, 1.0);
    test_furnace(0.0, 1.5, 0.5); /* a grey base: its effective colour R / (1 - Fdr_i R) */
    test_furnace(0.2, 1.5, 0.5);
    test_box();
    TEST_END();
}
