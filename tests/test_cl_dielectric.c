/* The dielectric on both backends:
 *  - a smooth clear glass sphere in a uniform background is invisible: every
 *    path, through the glass or past it, sees the background at weight 1 (the
 *    reflect/refract choice by F carries weight 1, the refraction's 1 / e^2
 *    entering cancels the e^2 leaving), so its truth XYZ is the background's,
 *    path by path, kernel and reference (but for the few paths trapped by
 *    total internal reflection between the facets until the record is full);
 *  - a glass slab seen from above against a background below only: the mean
 *    of the paths' truth Y against the Fresnel-Beer-Lambert transmittance
 *    T = (1 - R)^2 e^-a / (1 - R^2 e^-2a), a = sigma(lambda) d / cos_t, R the
 *    Fresnel reflectance at each path's camera angle, both in double here,
 *    within four standard errors of the paths' own spread;
 *  - a rough absorbing slab in another unit (coordinates times 2^10 or 2^-10,
 *    the density divided by the same) renders the same per-path XYZ;
 *  - the kernel's trace against the reference's, path by path, on a box with
 *    a smooth clear and a rough absorbing glass block (records, the vertex
 *    words, level bytes), and each mode's shade kernel against the
 *    reference's shading of the same records. */
#include "typebox_testlib.h"

#define SEED 7u

/* Fresnel of a dielectric interface, relative index e, incidence cosine c (double) */
static double fresnel_d(double c, double e)
{
    double s2 = (1.0 - c * c) / (e * e);
    if (s2 >= 1.0)
        return 1.0;
    double ct = sqrt(1.0 - s2);
    double rs = (c - e * ct) / (c + e * ct), rp = (e * c - ct) / (e * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* Trace and shade (truth) n paths of scene s on the backend (0 cpu, 1 opencl). */
static int render_paths(cl_test_scene *s, const spm_trace_params *p, int spp, int opencl,
                        spm_path *paths, uint8_t *levels, float *xyz)
{
    size_t n = (size_t)p->cam.width * (size_t)p->cam.height * (size_t)spp;
    if (!opencl) {
        spm_ref_trace(&s->geom, s->tables.materials, NULL, p, paths, levels);
        memset(levels, 0, n);
        spm_ref_shade(&s->tables, SPM_MODE_TRUTH, p, 0, paths, levels, n, xyz);
        return 0;
    }
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s->geom, &s->tables, SPM_MODE_TRUTH, SEED, &r, &err)) {
        CHECK(0, "spm_cl_create: %s", err.msg);
        return 1;
    }
    int rc = spm_cl_trace(r, 0, (spm_u32)spp, paths, levels, &err) ||
             spm_cl_shade(r, 0, (spm_u32)spp, paths, levels, xyz, &err);
    CHECK(rc == 0, "opencl: %s", err.msg);
    spm_cl_destroy(r);
    return rc;
}

/* A uv sphere of rings x segs quads (poles as fans), front faces outward. */
static void write_sphere(FILE *f, const char *mat, double r, int rings, int segs)
{
    for (int i = 0; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double p[4][3];
            for (int k = 0; k < 4; k++) {
                int ii = i + (k >= 2), jj = j + (k == 1 || k == 2);
                double th = M_PI * ii / rings, ph = 2.0 * M_PI * jj / segs;
                p[k][0] = r * sin(th) * cos(ph);
                p[k][1] = r * cos(th);
                p[k][2] = r * sin(th) * sin(ph);
            }
            /* (p0, p1, p2) and (p0, p2, p3) face outward: d/dphi x d/dtheta points out
             * (the first is degenerate at the top pole, the second at the bottom) */
            if (i > 0)
                fprintf(f, "tri %s %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", mat, p[0][0],
                        p[0][1], p[0][2], p[1][0], p[1][1], p[1][2], p[2][0], p[2][1], p[2][2]);
            if (i < rings - 1)
                fprintf(f, "tri %s %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", mat, p[0][0],
                        p[0][1], p[0][2], p[2][0], p[2][1], p[2][2], p[3][0], p[3][1], p[3][2]);
        }
}

/* Float rounding through a few refractions (1 / e^2 then e^2: 1 + a few ulps)
 * and 400-lane sums: measured worst 2.4e-6 relative; bound 1e-4. A weight
 * off by a Fresnel factor (the choice by F weighed by F again) is off by
 * 4 % or more at every refracted path. */
#define SPHERE_REL 1e-4

static void test_sphere(void)
{
    const char *path = "glass_sphere.scene";
    FILE *f = fopen(path, "w");
    if (!f) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    fprintf(f, "image 16 16\ncamera position 0 0 -3 direction 0 0 1 fov 30\n"
               "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\n"
               "material glass dielectric ior 1.5\n"
               "background both sky 1\n");
    write_sphere(f, "glass", 1.0, 24, 48);
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, 16, 16)) {
        CHECK(0, "the sphere scene loads");
        return;
    }
    const int spp = 16;
    size_t n = (size_t)16 * 16 * spp;
    spm_trace_params p = cl_test_params(&s, SEED, 0, (spm_u32)spp);
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    double bg[3] = {0, 0, 0};
    const float *sky = s.tables.truth + (size_t)s.tables.bg_up * SPM_TRUTH_BINS;
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        for (int ch = 0; ch < 3; ch++)
            bg[ch] += sky[b] * s.tables.cmf_truth[ch][b];
    for (int be = 0; be < 2; be++) {
        if (render_paths(&s, &p, spp, be, paths, levels, xyz))
            break;
        size_t through = 0, bad = 0, trunc = 0, refl = 0;
        double worst = 0.0;
        for (size_t i = 0; i < n; i++) {
            through += paths[i].h.nvert >= 2;
            refl += paths[i].h.nvert == 1;
            if (paths[i].h.end == SPM_END_TRUNCATED) {
                trunc++;
                continue;
            }
            for (int ch = 0; ch < 3; ch++) {
                double e = fabs(xyz[3 * i + ch] - bg[ch]) / bg[1];
                worst = fmax(worst, e);
                bad += !(e <= SPHERE_REL);
            }
        }
        printf("sphere (%s): %zu paths, %zu through the glass, %zu reflected off it, %zu "
               "truncated; worst %.3g relative to the background\n",
               be ? "opencl" : "cpu", n, through, refl, trunc, worst);
        CHECK(through > n / 3 && refl > 10, "too few paths meet the glass (%zu, %zu)", through, refl);
        /* a ray entering the faceted sphere near its outline can be trapped by
         * total internal reflection between facets (a smooth sphere traps none):
         * measured 10 of 4096, at the image's corners; they end truncated, dark */
        CHECK(trunc <= n / 100, "%zu paths truncated", trunc);
        CHECK(bad == 0, "%zu components differ from the background (worst %.3g)", bad, worst);
    }
    free(paths);
    free(levels);
    free(xyz);
    cl_test_scene_close(&s);
}

#define SLAB_D 0.1
#define SLAB_IOR 1.5

static void test_slab(void)
{
    const char *path = "glass_slab.scene";
    FILE *f = fopen(path, "w");
    if (!f) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    /* the slab between y = -d and 0, fronts outward (up, down); the camera
     * looks down; the background below only (a reflected ray sees nothing) */
    fprintf(f, "image 24 24\ncamera position 0 1 0.001 direction 0 -1 0.0001 fov 50\n"
               "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\n"
               "spectrum tint inline 380 0.5 450 2.0 520 8.0 580 12.0 650 3.0 780 0.5 end\n"
               "material glass dielectric ior %g absorb tint 1\n"
               "quad glass -100 0 -100  -100 0 100  100 0 100  100 0 -100\n"
               "quad glass -100 %g -100  100 %g -100  100 %g 100  -100 %g 100\n"
               "background down sky 1\n",
            SLAB_IOR, -SLAB_D, -SLAB_D, -SLAB_D, -SLAB_D);
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, 24, 24)) {
        CHECK(0, "the slab scene loads");
        return;
    }
    const int spp = 64;
    size_t n = (size_t)24 * 24 * spp;
    spm_trace_params p = cl_test_params(&s, SEED, 0, (spm_u32)spp);
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    const float *sky = s.tables.truth + (size_t)s.tables.bg_down * SPM_TRUTH_BINS;
    const float *sig = s.tables.truth + (size_t)s.tables.materials[0].refl * SPM_TRUTH_BINS;
    double want = 0.0;
    for (size_t i = 0; i < n; i++) {
        double d[3];
        cl_test_camera_dir(&p, i, d);
        double c = fabs(d[1]); /* the slab's normal is +y */
        double R = fresnel_d(c, SLAB_IOR);
        double ct = sqrt(1.0 - (1.0 - c * c) / (SLAB_IOR * SLAB_IOR));
        for (int b = 0; b < SPM_TRUTH_BINS; b++) {
            double a = sig[b] * SLAB_D / ct, t = exp(-a);
            want += (1.0 - R) * (1.0 - R) * t / (1.0 - R * R * t * t) * sky[b] *
                    s.tables.cmf_truth[1][b];
        }
    }
    want /= (double)n;
    double sky_y = 0.0;
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        sky_y += sky[b] * s.tables.cmf_truth[1][b];
    for (int be = 0; be < 2; be++) {
        if (render_paths(&s, &p, spp, be, paths, levels, xyz))
            break;
        double m = 0.0, m2 = 0.0;
        size_t deep = 0;
        for (size_t i = 0; i < n; i++) {
            m += xyz[3 * i + 1];
            m2 += (double)xyz[3 * i + 1] * xyz[3 * i + 1];
            deep += paths[i].h.nvert >= 4; /* an internal reflection and out */
        }
        m /= (double)n;
        double se = sqrt(fmax(m2 / (double)n - m * m, 0.0) / (double)n);
        printf("slab (%s): mean Y %.6f, Fresnel-Beer-Lambert %.6f (background %.4f, no absorption "
               "would be ~%.4f), standard error %.2g, %zu paths reflected inside\n",
               be ? "opencl" : "cpu", m, want, sky_y, sky_y * 0.92, se, deep);
        CHECK(deep > 0, "no path reflected inside the slab");
        CHECK(fabs(m - want) <= 4.0 * se + 1e-6 * want, "slab: %g vs %g (se %g)", m, want, se);
    }
    free(paths);
    free(levels);
    free(xyz);
    cl_test_scene_close(&s);
}

/* The slab in another unit: every coordinate times 2^10 or 2^-10 and the
 * density divided by it renders the same paths and the same per-path XYZ bit
 * for bit on the reference (power-of-two scaling is exact, the hit test has
 * no absolute length, and sigma d is the same product), as
 * test_scale_invariance checks for Lambertian scenes. */
static int slab_render(double k, const char *path, spm_path *paths, uint8_t *levels, float *xyz)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 1;
    fprintf(f, "image 16 16\ncamera position 0 %.17g %.17g direction 0 -1 0.3 fov 50\n"
               "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\n"
               "spectrum tint inline 380 0.5 450 2.0 520 8.0 580 12.0 650 3.0 780 0.5 end\n"
               "material glass dielectric ior %g absorb tint %.17g alpha 0.3\n"
               "material floor reflect sky 0.5\n"
               "quad glass %.17g 0 %.17g  %.17g 0 %.17g  %.17g 0 %.17g  %.17g 0 %.17g\n"
               "quad glass %.17g %.17g %.17g  %.17g %.17g %.17g  %.17g %.17g %.17g  %.17g %.17g %.17g\n"
               "quad floor %.17g %.17g %.17g  %.17g %.17g %.17g  %.17g %.17g %.17g  %.17g %.17g %.17g\n"
               "background both sky 1\n",
            k, 0.001 * k, SLAB_IOR, 1.0 / k, -10 * k, -10 * k, -10 * k, 10 * k, 10 * k, 10 * k,
            10 * k, -10 * k, -10 * k, -SLAB_D * k, -10 * k, 10 * k, -SLAB_D * k, -10 * k, 10 * k,
            -SLAB_D * k, 10 * k, -10 * k, -SLAB_D * k, 10 * k, -10 * k, -0.5 * k, -10 * k,
            -10 * k, -0.5 * k, 10 * k, 10 * k, -0.5 * k, 10 * k, 10 * k, -0.5 * k, -10 * k);
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, 16, 16))
        return 1;
    spm_trace_params p = cl_test_params(&s, SEED, 0, 8);
    spm_ref_trace(&s.geom, s.tables.materials, NULL, &p, paths, levels);
    memset(levels, 0, (size_t)16 * 16 * 8);
    spm_ref_shade(&s.tables, SPM_MODE_TRUTH, &p, 0, paths, levels, (size_t)16 * 16 * 8, xyz);
    cl_test_scene_close(&s);
    return 0;
}

static void test_slab_scale(void)
{
    size_t n = (size_t)16 * 16 * 8;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *x1 = spm_xcalloc(3 * n, sizeof *x1), *xk = spm_xcalloc(3 * n, sizeof *xk);
    size_t inside = 0;
    if (slab_render(1.0, "glass_slab_1.scene", paths, levels, x1)) {
        CHECK(0, "the scaled slab renders");
    } else {
        for (size_t i = 0; i < n; i++)
            for (spm_u32 j = 0; j < paths[i].h.nvert; j++)
                inside += (SPM_VX_KIND(paths[i].x[j]) == SPM_FK_ABSORB) && paths[i].x[j].lobe > 0.0f;
        const double ks[] = {1.0 / 1024, 1024.0};
        for (int a = 0; a < 2; a++) {
            int rc = slab_render(ks[a], "glass_slab_k.scene", paths, levels, xk);
            int same = !rc && !memcmp(x1, xk, 3 * n * sizeof *x1);
            printf("slab at scale %g (density / %g): per-path XYZ %s (%zu segments inside)\n",
                   ks[a], ks[a], same ? "identical" : "differs", inside);
            CHECK(same, "slab at scale %g renders as at 1", ks[a]);
        }
        CHECK(inside > n / 4, "too few segments inside (%zu)", inside);
    }
    free(paths);
    free(levels);
    free(x1);
    free(xk);
}

/* The lengths inside (lobe) of two records of the same path: the largest
 * absolute difference, and whether one is off beyond the weights' relative
 * tolerance. A length is a difference of two hit distances, so where a ray
 * grazes a block's corner inside (lengths of 1e-5 to 1e-2) the rays' float
 * differences (1e-6 relative after several refractions) move it by far more
 * than its own rounding: measured 8 such paths in 9216, worst 3.8e-5 scene
 * units (the box is 0.56 wide; exp(-sigma d) moves by < 1e-3 there); since a
 * ray leaves a surface from a point moved inside its triangle and off its
 * plane (ARCHITECTURE.md "Rays leaving a surface"), whose few float operations
 * each backend rounds its own way, 13 paths, worst 4.6e-5: at most 2 in 1000
 * (LEN_OFF_FRACTION), the absolute bound LEN_ABS as before. */
static double len_diff(const spm_path *a, const spm_path *b, int *off)
{
    double worst = 0.0;
    *off = 0;
    for (spm_u32 j = 0; j < a->h.nvert; j++) {
        float x = a->x[j].lobe, y = b->x[j].lobe;
        worst = fmax(worst, fabs((double)x - y));
        *off |= !cl_test_close_rel(x, y);
    }
    return worst;
}
#define LEN_ABS 2e-4
#define LEN_OFF_FRACTION 2e-3

static int ext_differs(const spm_path *a, const spm_path *b)
{
    for (spm_u32 j = 0; j < a->h.nvert; j++) {
        const spm_vertex_ext *x = &a->x[j], *y = &b->x[j];
        if (x->ids != y->ids || !cl_test_close_rel(x->light, y->light) ||
            !cl_test_close_rel(x->hit_c, y->hit_c))
            return 1;
    }
    return 0;
}

/* The shade kernels fuse and reorder as test_cl_shade explains; exp per lane
 * (OpenCL's exp: 3 ulp) at each absorbing vertex adds a few ulps: bound 1e-4
 * relative to the path's largest component, as the conductor's. */
#define SHADE_REL 1e-4

/* the dielectric's vertices in the reference's records, and the lengths
 * inside of the paths both backends took */
typedef struct {
    size_t diel, hits, lights, inside, len_off;
    double len_worst;
} diel_counts;

static void diel_count(const cl_test_scene *s, const spm_path *g, const spm_path *c, int diverged,
                       void *ctx)
{
    diel_counts *k = ctx;
    (void)s;
    int off = 0;
    if (!diverged)
        k->len_worst = fmax(k->len_worst, len_diff(g, c, &off));
    k->len_off += off;
    for (spm_u32 j = 0; j < c->h.nvert; j++) {
        int is = SPM_VX_KIND(c->x[j]) == SPM_FK_ABSORB;
        k->diel += is;
        k->hits += is && SPM_VX_HIT(c->x[j]) != SPM_NONE;
        k->lights += is && (c->v[j].ids >> 16) != SPM_NONE;
        k->inside += is && c->x[j].lobe > 0.0f;
    }
}

static void diel_report(size_t n, void *ctx)
{
    const diel_counts *k = ctx;
    printf("box: %zu dielectric vertices (%zu light samples, %zu lobe hits, %zu segments "
           "inside)\n", k->diel, k->lights, k->hits, k->inside);
    CHECK(k->diel > n / 10 && k->hits > 20 && k->lights > 50 && k->inside > n / 20,
          "too little dielectric transport");
    printf("lengths inside: %zu paths beyond the relative tolerance, worst %.3g\n", k->len_off,
           k->len_worst);
    CHECK((double)k->len_off <= LEN_OFF_FRACTION * (double)n && k->len_worst <= LEN_ABS,
          "lengths inside: %zu paths off, worst %g", k->len_off, k->len_worst);
}

static void test_box(void)
{
    diel_counts k = {0, 0, 0, 0, 0, 0.0};
    tb_box b = {"glass_box.scene", 24, 24, 16, SEED, SHADE_REL, ext_differs, diel_count,
                diel_report, &k};
    tb_box_run(&b);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_sphere();
    test_slab();
    test_slab_scale();
    test_box();
    TEST_END();
}
