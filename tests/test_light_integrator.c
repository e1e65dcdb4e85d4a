/* The light integrator (--integrator light) on the CPU reference:
 *  - light tracing and path tracing converge to the same image of the
 *    Cornell box, and of a glossy one (its boxes a rough gold conductor and
 *    a rough coated blue: importance-mode eval and sample of both types),
 *    and of the box lit by a point light (a delta no camera ray meets), and
 *    of two fluorescent scenes (re-radiation along the light subpaths in
 *    light-flow order: scenes/fluorescent.scene, and fluor_relay.scene, whose
 *    red needs two dyes' matrices applied in the light's order):
 *    per pixel, the means of K independent renders (seeds) of each, within
 *    their joint standard error measured from the K renders;
 *  - its film does not depend on the split: one backend and two from the
 *    same plan give the same film bit for bit;
 *  - the fixed-point sum of a chunk's splats (film_splat.h) does not depend
 *    on their order, where a float sum in the same two orders does, and a
 *    chunk mixing splats 2^50 apart (2^30 and 2^-20) sums them as its unit says. */
#include <math.h>
#include <stdio.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>
#include "backend_cpu.h"
#include "film_splat.h"
#include "render_plan.h"
#include "render_run.h"
#include "scene.h"
#include "tables.h"
#include "testutil.h"
#include "integrator_testlib.h"

#define SIDE 16
#define K 32      /* independent renders of each integrator */
#define SPP 64    /* samples per pixel of each */
#define Z_MAX 5.0 /* per pixel and channel, Student's t with K - 1 = 31 degrees:
                     two-sided 2e-5, 1.5 % over the 768 values */

typedef it_scene scene;

static int load(scene *s, const char *path)
{
    return it_load(s, path, SIDE);
}

static int plan_for(spm_render_plan *p, const scene *s, int mode, int integrator, spm_u32 seed)
{
    return it_plan(p, s, mode, integrator, seed);
}

/* One pass of SPP samples per pixel: its XYZ per pixel (the pass sums over SPP) */
static int render_xyz(const scene *s, int mode, int integrator, spm_u32 seed, double *y)
{
    return it_render_xyz(s, mode, integrator, seed, SPP, y);
}

/* the glossy box: its boxes a rough gold conductor and a rough coated blue */
static const char *const glossy[][2] = {
    {"material short_box ", "material short_box conductor au_eta au_k alpha 0.25\n"},
    {"material tall_box ", "material tall_box coated reflect blue_sky ior 1.5 alpha 0.2\n"},
    {"spectrum equal ", "spectrum equal equal\nspectrum au_eta file metal_Au_eta.csv\n"
                        "spectrum au_k file metal_Au_k.csv\n"}};
/* the box lit by a point light in place of its area light (its power the
 * area light's flux, 1000 pi 0.0137 W), 0.2 below the ceiling: 0.05 below
 * it, the ceiling's hot spot makes the path tracer's indirect light so
 * heavy-tailed that 32 renders underestimate its spread (two corner pixels
 * at 6 standard errors while the image's totals agree within 1) */
static const char *const point[][2] = {
    {"quad light ", "light point 0.278 0.35 0.2795 equal 43\n"}};

static void converge(const scene *s, const char *name)
{
    enum { NP = 3 * SIDE * SIDE }; /* X, Y and Z of every pixel */
    static double y[NP], sum[2][NP], sum2[2][NP];
    memset(sum, 0, sizeof sum);
    memset(sum2, 0, sizeof sum2);
    for (int integ = 0; integ < 2; integ++)
        for (spm_u32 k = 0; k < K; k++) {
            /* seeds of their own: the two estimates independent */
            if (render_xyz(s, SPM_MODE_REF, integ, 1000u * (spm_u32)(integ + 1) + k, y))
                return;
            for (int i = 0; i < NP; i++)
                sum[integ][i] += y[i], sum2[integ][i] += y[i] * y[i];
        }
    /* per channel c: the image's total and its variance, per integrator */
    double worst = 0.0, tot[3][2] = {{0}}, var_tot[3][2] = {{0}}, se_rel[2] = {0.0, 0.0};
    int bad = 0;
    for (int i = 0; i < NP; i++) {
        double m[2], v[2]; /* the mean of the K renders and its variance */
        for (int a = 0; a < 2; a++) {
            m[a] = sum[a][i] / K;
            v[a] = fmax(0.0, sum2[a][i] / K - m[a] * m[a]) / (K - 1);
            tot[i % 3][a] += m[a], var_tot[i % 3][a] += v[a];
            se_rel[a] += m[a] > 0.0 ? sqrt(v[a]) / m[a] / NP : 0.0;
        }
        double z = (m[1] - m[0]) / sqrt(v[0] + v[1] + 1e-30);
        worst = fmax(worst, fabs(z));
        bad += !(fabs(z) <= Z_MAX);
    }
    printf("%s %dx%d, %d renders of %d spp each: per pixel and channel worst |z| %.2f, mean "
           "relative standard error light %.2f %% path %.2f %%\n",
           name, SIDE, SIDE, K, SPP, worst, 100.0 * se_rel[1], 100.0 * se_rel[0]);
    for (int c = 0; c < 3; c++) {
        double zt = (tot[c][1] - tot[c][0]) / sqrt(var_tot[c][0] + var_tot[c][1]);
        printf("  %c over the image: light %.5f path %.5f (%+.3f %%, z %.2f)\n", "XYZ"[c],
               tot[c][1] / (NP / 3), tot[c][0] / (NP / 3), 100.0 * (tot[c][1] / tot[c][0] - 1.0),
               zt);
        CHECK(tot[c][0] > 0.0 && tot[c][1] > 0.0, "%s: nothing rendered", name);
        CHECK(fabs(zt) <= 4.0, "%s: the image's %c differs by %.2f standard errors", name,
              "XYZ"[c], zt);
    }
    CHECK(bad == 0, "%s: %d pixel channels differ beyond %.1f standard errors (worst %.2f)", name,
          bad, Z_MAX, worst);
}

/* One render of spp samples per pixel in passes of 4 with nb backends of one plan. */
static void film_of(const spm_render_plan *p, int nb, int spp, spm_film *film)
{
    spm_error err;
    spm_backend *b[2];
    for (int i = 0; i < nb; i++)
        b[i] = spm_backend_cpu_create(p, &err);
    spm_film_init(film, p->geom->cam.width, p->geom->cam.height, &err);
    spm_run_opts o;
    memset(&o, 0, sizeof o);
    o.spp = spp;
    o.spp_per_pass = 4;
    spm_run_result r;
    CHECK(spm_render_run(b, nb, p->npix, &o, film, &r, &err) == 0, "render: %s", err.msg);
    CHECK(r.spp_done == spp, "%d of %d samples per pixel", r.spp_done, spp);
    for (int i = 0; i < nb; i++)
        b[i]->destroy(b[i]);
}

static void split_invariant(const scene *s)
{
    spm_render_plan p;
    if (plan_for(&p, s, SPM_MODE_ML, SPM_INTEGRATOR_LIGHT, 7u))
        return;
    spm_film one, two;
    film_of(&p, 1, 24, &one);
    film_of(&p, 2, 24, &two);
    size_t n = p.npix * 3;
    double total = 0.0;
    for (size_t i = 0; i < n; i++)
        total += one.sum[i];
    CHECK(total > 0.0, "an empty film");
    CHECK(!memcmp(one.sum, two.sum, n * sizeof *one.sum),
          "the film of two backends differs from one backend's");
    spm_film_free(&one);
    spm_film_free(&two);
    spm_render_plan_free(&p);
}

/* xorshift, for the splats' values and the shuffle */
static uint64_t rnd(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

static void fixed_point(void)
{
    enum { NPIX = 4, NS = 5000 };
    spm_splats a, b;
    spm_splats_init(&a, 3);
    spm_splats_init(&b, 3);
    uint64_t seed = 12345;
    for (int i = 0; i < NS; i++) { /* values spread over 2^-20 .. 2^20 */
        float *v = spm_splats_push(&a, (uint32_t)(rnd(&seed) % NPIX));
        for (int c = 0; c < 3; c++)
            v[c] = ldexpf((float)(rnd(&seed) % 1000u + 1u) / 1000.0f, (int)(rnd(&seed) % 41u) - 20);
    }
    int *perm = malloc(NS * sizeof *perm); /* b: a's splats in a shuffled order */
    for (int i = 0; i < NS; i++)
        perm[i] = i;
    for (int i = NS - 1; i > 0; i--) {
        int j = (int)(rnd(&seed) % (uint64_t)(i + 1)), t = perm[i];
        perm[i] = perm[j], perm[j] = t;
    }
    for (int i = 0; i < NS; i++)
        memcpy(spm_splats_push(&b, a.px[perm[i]]), &a.v[3 * perm[i]], 3 * sizeof(float));
    float pa[3 * NPIX] = {0}, pb[3 * NPIX] = {0}, fa[3 * NPIX] = {0}, fb[3 * NPIX] = {0};
    for (int i = 0; i < NS; i++) /* the float sums in the same two orders */
        for (int c = 0; c < 3; c++)
            fa[3 * a.px[i] + c] += a.v[3 * i + c], fb[3 * b.px[i] + c] += b.v[3 * i + c];
    spm_splat_acc acc;
    spm_splat_acc_init(&acc, NPIX, 3);
    uint64_t nf = 0;
    spm_splats_add_chunk(&acc, &a, pa, &nf);
    spm_splats_add_chunk(&acc, &b, pb, &nf);
    CHECK(memcmp(fa, fb, sizeof fa) != 0, "the float sums agree: the orders show nothing");
    CHECK(!memcmp(pa, pb, sizeof pa), "the fixed-point sums depend on the order");
    for (int i = 0; i < 3 * NPIX; i++)
        CHECK(fabs(pa[i] - fa[i]) <= 1e-5 * fabs(fa[i]), "sum %d: %.9g, float %.9g", i, pa[i], fa[i]);
    /* a splat 2^30 larger beside 999 small ones (the unit is then 2^(31 + 10 - 62) =
     * 2^-21, so 2^-20 is kept exactly), and a non-finite one */
    a.n = 0;
    float big[3] = {ldexpf(1.0f, 30), 1.0f, 0.0f}, small[3] = {1.0f, ldexpf(1.0f, -20), 0.0f};
    for (int i = 0; i < 1000; i++)
        memcpy(spm_splats_push(&a, 1), i == 500 ? big : small, sizeof small);
    memcpy(spm_splats_push(&a, 2), (float[]){NAN, 1.0f, 1.0f}, sizeof small);
    float pc[3 * NPIX] = {0};
    spm_splats_add_chunk(&acc, &a, pc, &nf);
    CHECK(pc[3] == (float)(ldexp(1.0, 30) + 999.0) && pc[4] == (float)(1.0 + ldexp(999.0, -20)),
          "2^30 beside small splats: %.9g %.9g", pc[3], pc[4]);
    CHECK(nf == 1 && pc[6] == 0.0f, "the non-finite splat: %llu left out", (unsigned long long)nf);
    spm_splat_acc_free(&acc);
    spm_splats_free(&a);
    spm_splats_free(&b);
    free(perm);
}


static void variant(const char *cornell, const char *dir, const char *name,
                    const char *const (*sub)[2], int n)
{
    char path[1200];
    scene s;
    snprintf(path, sizeof path, "%s/%s.scene", dir, name);
    if (!it_write_variant(cornell, path, sub, n) && !load(&s, path)) {
        converge(&s, name);
        it_free(&s);
    }
    remove(path);
}

int main(void)
{
    fixed_point();
    char cornell[1024], dir[] = "/tmp/specmip_light_XXXXXX";
    spm_data_path("scenes/cornell.scene", cornell, sizeof cornell);
    scene s;
    if (load(&s, cornell))
        TEST_END();
    split_invariant(&s);
    converge(&s, "cornell");
    it_free(&s);
    /* fluorescent surfaces under a blue LED and D65: re-radiation in
     * light-flow order on the light subpaths */
    static const char *const fluor_scenes[][2] = {
        {"scenes/fluorescent.scene", "fluorescent"},
        {"tests/data/scenes/fluor_relay.scene", "fluor_relay"}};
    for (int f = 0; f < 2; f++) {
        char fluor[1024];
        spm_data_path(fluor_scenes[f][0], fluor, sizeof fluor);
        if (!load(&s, fluor)) {
            converge(&s, fluor_scenes[f][1]);
            it_free(&s);
        }
    }
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    variant(cornell, dir, "glossy", glossy, 3);
    variant(cornell, dir, "point", point, 1);
    rmdir(dir);
    TEST_END();
}
