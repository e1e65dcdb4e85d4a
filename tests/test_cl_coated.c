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
    cl_test_write_sphere(f, "coat");
    fclose(f);
}

/* 4 standard errors: a render that is right fails 6 times in 10^5 */
#define NSIGMA 4.0

static int diffuse_first(const spm_path *p, void *ctx)
{
    spm_u32 refl = *(const spm_u32 *)ctx;
    return p->h.nvert > 0 && p->v[0].ids != 0xFFFFFFFFu && (p->v[0].ids & 0xFFFFu) == refl;
}

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
    spm_u32 refl = s.tables.materials[0].refl;
    cl_test_furnace_result res[2];
    cl_test_furnace(&s, SEED, SW, SH, spp, NULL, diffuse_first, &refl, res);
    for (int cl = 0; cl < 2; cl++) {
        const cl_test_furnace_result *r = &res[cl];
        CHECK(!r->failed, "the sphere renders (%s)", cl ? "opencl" : "cpu");
        printf("sphere eta %.2f (%s): %zu paths meet it (%zu diffuse), mean / background - 1 = "
               "%.5f +- %.5f\n", eta, cl ? "opencl" : "cpu", r->met, r->counted, r->mean, r->se);
        CHECK(r->met > n / 3 && r->counted > r->met / 3, "too few paths meet the sphere's base");
        CHECK(fabs(r->mean) <= NSIGMA * r->se, "eta %.2f (%s): the sphere is not invisible: "
              "%.5f +- %.5f", eta, cl ? "opencl" : "cpu", r->mean, r->se);
    }
    cl_test_scene_close(&s);
}

/* ---- the rough white furnace ------------------------------------------- */
#define PW 16
#define PH 12

typedef struct {
    double a, eta, fi, fe, R;
} coat_model;

static double coat_albedo(void *ctx, double mu)
{
    const coat_model *m = ctx;
    return albedo(m->a, m->eta, mu, m->fi, m->fe, m->R);
}

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
    coat_model m = {a, eta, fdr(1.0 / eta), fdr(eta), R};
    double lo, hi;
    double *want = cl_test_plane_want(&s, SEED, spp, coat_albedo, &m, &lo, &hi);
    printf("furnace alpha %.2f eta %.2f base %.2f: albedo %.4f at cos %.3f, %.4f at cos %.3f\n", a,
           eta, R, coat_albedo(&m, lo), lo, coat_albedo(&m, hi), hi);
    cl_test_furnace_result res[2];
    cl_test_furnace(&s, SEED, PW, PH, spp, want, NULL, NULL, res);
    for (int cl = 0; cl < 2; cl++) {
        const cl_test_furnace_result *r = &res[cl];
        CHECK(!r->failed, "the plane renders (%s)", cl ? "opencl" : "cpu");
        printf("furnace (%s): %zu paths, mean of (path / background - albedo) = %.5f +- %.5f\n",
               cl ? "opencl" : "cpu", r->met, r->mean, r->se);
        CHECK(r->met == n, "every path meets the plane (%zu of %zu)", r->met, n);
        CHECK(fabs(r->mean) <= NSIGMA * r->se, "alpha %.2f (%s): the furnace is off its albedo: "
              "%.5f +- %.5f", a, cl ? "opencl" : "cpu", r->mean, r->se);
    }
    free(want);
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
