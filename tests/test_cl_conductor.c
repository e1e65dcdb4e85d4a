/* The conductor on both backends:
 *  - a smooth conductor plane under a uniform background: every path is the
 *    camera ray, one mirror bounce and the background, so its XYZ in truth is
 *    sum over the 1 nm bins of F(eta, k, cos) bg cmf / mean (0 when Russian
 *    roulette ends it), with F the complex Fresnel in double and cos from the
 *    camera ray recomputed here -- per path, kernel and reference;
 *  - the kernel's trace against the reference's, path by path, on a box with
 *    a smooth and a rough conductor (records, the conductor's words, level
 *    bytes), and each mode's shade kernel against the reference's shading of
 *    the same records. */
#include <complex.h>
#include "typebox_testlib.h"

#define SEED 5u

static double fresnel_complex(double eta, double k, double c)
{
    double complex n = eta + I * k;
    double complex ct = csqrt(1.0 - (1.0 - c * c) / (n * n));
    double complex rs = (c - n * ct) / (c + n * ct), rp = (n * c - ct) / (n * c + ct);
    return 0.5 * (creal(rs * conj(rs)) + creal(rp * conj(rp)));
}

/* Float sums of 400 lanes and a float Fresnel (3e-6 absolute, test_conductor):
 * measured worst 1.1e-6 relative to the path's largest component; bound 1e-4. */
#define PLANE_REL 1e-4

static void check_plane_paths(const cl_test_scene *s, const spm_trace_params *p, const spm_path *paths,
                              const float *xyz, size_t n, const char *who)
{
    const spm_tables *t = &s->tables;
    const spm_material *m = &t->materials[0];
    for (int i = 0; i < t->nmaterials; i++)
        if (SPM_MAT_TAG(t->materials[i]) == SPM_MAT_CONDUCTOR)
            m = &t->materials[i];
    const float *eta = t->truth + (size_t)m->refl * SPM_TRUTH_BINS;
    const float *kk = t->truth + (size_t)m->col2 * SPM_TRUTH_BINS;
    const float *bg = t->truth + (size_t)t->bg_up * SPM_TRUTH_BINS;
    double worst = 0.0;
    size_t bounced = 0, bad = 0;
    for (size_t i = 0; i < n; i++) {
        double d[3];
        cl_test_camera_dir(p, i, d);
        double c = fabs(d[1]); /* the plane's normal is +y */
        spm_u32 pixel, sample;
        spm_ref_path_key(p, i, &pixel, &sample);
        int survives = spm_rng(p->seed, pixel, sample, SPM_DIM_VERTEX(0) + SPM_DIM_RR) < m->mean;
        double want[3] = {0, 0, 0};
        for (int b = 0; survives && b < SPM_TRUTH_BINS; b++) {
            double l = fresnel_complex(eta[b], kk[b], c) * bg[b] * m->inv_mean;
            for (int ch = 0; ch < 3; ch++)
                want[ch] += l * t->cmf_truth[ch][b];
        }
        bounced += survives && paths[i].h.nvert == 1;
        double big = fmax(fabs(want[0]), fmax(fabs(want[1]), fabs(want[2])));
        for (int ch = 0; ch < 3; ch++) {
            double e = fabs(xyz[3 * i + ch] - want[ch]) / (big > 0.0 ? big : 1.0);
            worst = fmax(worst, e);
            bad += !(e <= PLANE_REL);
        }
    }
    printf("plane (%s): %zu paths, %zu reflected, worst %.3g relative\n", who, n, bounced, worst);
    CHECK(bounced > n / 4, "%s: too few reflected paths (%zu)", who, bounced);
    CHECK(bad == 0, "%s: %zu components off the closed form (worst %.3g)", who, bad, worst);
}

static void test_plane(void)
{
    const char *path = "conductor_plane.scene";
    FILE *f = fopen(path, "w");
    if (!f) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    /* synthetic optical constants; the camera looks down at the plane y = 0 */
    fprintf(f, "image 16 12\ncamera position 0 1 -1 direction 0 -1.3 1 fov 40\n"
               "spectrum eta inline 380 1.6 450 1.3 520 0.8 580 0.35 650 0.2 780 0.16 end\n"
               "spectrum kk inline 380 1.9 450 1.9 520 2.0 580 2.6 650 3.5 780 4.9 end\n"
               "spectrum sky inline 380 0.5 550 1.0 780 2.0 end\n"
               "material metal conductor eta kk\n"
               "quad metal -100 0 -100  -100 0 100  100 0 100  100 0 -100\n"
               "background up sky 1\n");
    fclose(f);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, 16, 12)) {
        CHECK(0, "the plane scene loads");
        return;
    }
    const int spp = 8;
    size_t n = (size_t)16 * 12 * spp;
    spm_trace_params p = cl_test_params(&s, SEED, 0, (spm_u32)spp);
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *xyz = spm_xcalloc(3 * n, sizeof *xyz);
    spm_ref_trace(&s.geom, s.tables.materials, NULL, &p, paths, levels);
    memset(levels, 0, n);
    spm_ref_shade(&s.tables, SPM_MODE_TRUTH, &p, 0, paths, levels, n, xyz);
    check_plane_paths(&s, &p, paths, xyz, n, "cpu");
    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s.geom, &s.tables, SPM_MODE_TRUTH, SEED, &r, &err) == 0) {
        int rc = spm_cl_trace(r, 0, (spm_u32)spp, paths, levels, &err) ||
                 spm_cl_shade(r, 0, (spm_u32)spp, paths, levels, xyz, &err);
        CHECK(rc == 0, "opencl: %s", err.msg);
        if (!rc)
            check_plane_paths(&s, &p, paths, xyz, n, "opencl");
        spm_cl_destroy(r);
    } else {
        CHECK(0, "spm_cl_create: %s", err.msg);
    }
    free(paths);
    free(levels);
    free(xyz);
    cl_test_scene_close(&s);
}

static int ext_differs(const spm_path *a, const spm_path *b)
{
    for (spm_u32 j = 0; j < a->h.nvert; j++) {
        const spm_vertex_ext *x = &a->x[j], *y = &b->x[j];
        int last = j + 1 == a->h.nvert && a->h.end == SPM_END_TRUNCATED; /* no bounce on the CPU */
        if (x->ids != y->ids || !cl_test_close_rel(x->light, y->light) ||
            !cl_test_close_rel(x->hit_c, y->hit_c) ||
            (!last && !cl_test_close_rel(x->lobe, y->lobe)))
            return 1;
    }
    return 0;
}

/* The shade kernels fuse and reorder as test_cl_shade explains, and the
 * conductor's Fresnel in float (contracted in the kernel, not in the
 * reference) adds a few ulps per lane at each conductor vertex: measured
 * worst 1.5e-6 (truth) relative to the largest component; bound 1e-4. */
#define SHADE_REL 1e-4

/* the conductor's vertices in the reference's records */
typedef struct {
    size_t cond, hits, lights, nv;
} cond_counts;

static void cond_count(const cl_test_scene *s, const spm_path *g, const spm_path *c, int diverged,
                       void *ctx)
{
    cond_counts *k = ctx;
    (void)s, (void)g, (void)diverged;
    k->nv += c->h.nvert;
    for (spm_u32 j = 0; j < c->h.nvert; j++) {
        int is = SPM_VX_KIND(c->x[j]) == SPM_FK_FRESNEL;
        k->cond += is;
        k->hits += SPM_VX_HIT(c->x[j]) != SPM_NONE;
        k->lights += is && (c->v[j].ids >> 16) != SPM_NONE;
    }
}

static void cond_report(size_t n, void *ctx)
{
    const cond_counts *k = ctx;
    printf("box: %.3f vertices a path, %zu conductor vertices (%zu light samples, %zu lobe "
           "hits)\n", (double)k->nv / (double)n, k->cond, k->lights, k->hits);
    /* the device record a path reads and writes: its header, and per vertex
     * spm_vertex, plus spm_vertex_ext in a scene with a conductor */
    printf("record: %.1f bytes a path (%.1f without the conductor's words)\n",
           sizeof(spm_dev_head) + (double)k->nv / (double)n *
                                    (sizeof(spm_vertex) + sizeof(spm_vertex_ext)),
           sizeof(spm_dev_head) + (double)k->nv / (double)n * sizeof(spm_vertex));
    CHECK(k->cond > n / 10 && k->hits > 20 && k->lights > 100, "too little conductor transport");
}

static void test_box(void)
{
    cond_counts k = {0, 0, 0, 0};
    tb_box b = {"conductor_box.scene", 24, 24, 16, SEED, SHADE_REL, ext_differs, cond_count,
                cond_report, &k};
    tb_box_run(&b);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_plane();
    test_box();
    TEST_END();
}
