/* Dispersive glass (docs/METHODS.md "Dispersion") on both backends, on the
 * bundled N-SF11 sphere in the Cornell box (scenes/sf11_sphere.scene):
 *  - the kernel's trace against the reference's, path by path: the same
 *    committed wavelength and 1 / pdf in the same vertex word of every
 *    committed path (the draw is integer: no tolerance), and the paths
 *    diverge no more than test_cl_dielectric allows;
 *  - the committed wavelengths are stratified over a pixel's samples
 *    (include/spm_rng.h spm_rng_stratified_u32): the SPP = 16 samples of a
 *    pixel are its first 2^4, whose draws lie exactly 2^28 apart, i.e. 25
 *    of the 400 bins, so the bins of a pixel's committed paths are distinct
 *    and equal mod 25, on both backends (16 independent draws would be so
 *    with odds below 25^-1 per extra committed path);
 *  - every mode's shade kernel against the reference's shading of the same
 *    records, committed paths included (rgb's records are traced apart: it
 *    commits none, tracing the glass at n_d).
 * The scene's index table is checked against the Sellmeier formula in double
 * at three wavelengths (the table is what both backends read). */
#include "testutil.h"
#include "cl_testlib.h"
#include "dispersion.h"

#define SEED 11u
#define W 24
#define H 24
#define SPP 16
/* as test_cl_dielectric: a few ulps of cos/sin may move a ray across an edge */
#define MAX_DIVERGENT_FRACTION 1e-3
/* The shade kernels fuse and reorder (test_cl_shade); a committed path's one
 * lane is walked without contraction but with OpenCL's exp and the kernel's
 * own Fresnel (3-4 ulp): bound 1e-4 relative to the path's largest
 * component, as test_cl_dielectric's. Measured: 1.3e-6 over every path
 * (truth's 400-lane sums), 0 on the committed paths (clear glass and
 * Lambertian walls: products and sums in the same order, no exp). */
#define SHADE_REL 1e-4

static size_t committed(const spm_path *p, spm_u32 *bin, float *iw)
{
    for (spm_u32 j = 0; j < p->h.nvert; j++)
        if (SPM_VX_LAMBDA(p->x[j]) != SPM_NONE) {
            *bin = SPM_VX_LAMBDA(p->x[j]);
            *iw = p->x[j].light;
            return j + 1;
        }
    return 0;
}

/* A pixel's committed bins (paths pixel * SPP .. + SPP - 1): distinct and
 * equal mod SPM_TRUTH_BINS / SPP. Returns the pixels with two or more
 * committed paths; counts the pixels that break the strata in *bad. */
static size_t strata_check(const spm_path *paths, size_t npix, size_t *bad)
{
    size_t tested = 0;
    *bad = 0;
    for (size_t px = 0; px < npix; px++) {
        int seen[SPM_TRUTH_BINS] = {0}, mod = -1, ncom = 0, broken = 0;
        for (size_t k = 0; k < SPP; k++) {
            spm_u32 b;
            float iw;
            if (!committed(&paths[px * SPP + k], &b, &iw))
                continue;
            ncom++;
            broken |= seen[b]++ > 0;
            if (mod < 0)
                mod = (int)(b % (SPM_TRUTH_BINS / SPP));
            broken |= (int)(b % (SPM_TRUTH_BINS / SPP)) != mod;
        }
        tested += ncom >= 2;
        *bad += ncom >= 2 && broken;
    }
    return tested;
}

static void test_table(const cl_test_scene *s)
{
    const spm_glass *g = spm_glass_find("N-SF11");
    CHECK(g != NULL, "the catalogue has N-SF11");
    CHECK(s->geom.ndisp == 1, "one dispersive glass (%d)", s->geom.ndisp);
    if (!g || s->geom.ndisp != 1)
        return;
    /* n^2 = 1 + sum B l^2 / (l^2 - C), l in um; Schott's N-SF11 n_F 1.80645 at
     * 486.13 nm, n_C 1.77599 at 656.27 nm: bins 106 and 276 (their centres
     * 0.37 and 0.23 nm off: dn/dl < 3e-4 per nm there) */
    static const int bins[3] = {106, 207, 276};
    static const double want[3] = {1.80645, 1.78472, 1.77599};
    for (int i = 0; i < 3; i++) {
        double l = spm_disp_bin_nm(bins[i]) * 1e-3, n2 = 1.0;
        for (int k = 0; k < 3; k++)
            n2 += g->b[k] * l * l / (l * l - g->c[k]);
        float n = s->geom.disp[bins[i]];
        printf("N-SF11 at %.1f nm: table %.6f, Sellmeier %.6f, catalogue %.5f\n",
               spm_disp_bin_nm(bins[i]), n, sqrt(n2), want[i]);
        CHECK(fabs(n - sqrt(n2)) < 1e-6, "table against the formula");
        CHECK(fabs(n - want[i]) < 1.5e-4, "table against the catalogue's n");
    }
}

static void test_sphere(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/sf11_sphere.scene", SPM_SOURCE_DIR);
    cl_test_scene s;
    if (cl_test_scene_load(&s, path, W, H)) {
        CHECK(0, "the N-SF11 sphere loads");
        return;
    }
    test_table(&s);
    size_t n = (size_t)W * H * SPP;
    spm_path *gp = spm_xcalloc(n, sizeof *gp), *cp = spm_xcalloc(n, sizeof *cp);
    uint8_t *gl = spm_xcalloc(n, 1), *cl = spm_xcalloc(n, 1);
    float *ref = spm_xcalloc(3 * n, sizeof *ref), *got = spm_xcalloc(3 * n, sizeof *got);
    for (int mode = 0; mode < SPM_MODE_COUNT; mode++) {
        const spm_mode_desc *md = spm_mode(mode);
        spm_cl_renderer *r;
        spm_error err;
        if (spm_cl_create(0, &s.geom, &s.tables, mode, SEED, &r, &err)) {
            CHECK(0, "spm_cl_create: %s", err.msg);
            continue;
        }
        spm_trace_params p = cl_test_params(&s, SEED, 0, SPP);
        p.disperse = !md->one_index; /* the render plan's rule */
        spm_ref_trace(&s.geom, s.tables.materials, cl_test_lvlk(&s.tables, mode), &p, cp, cl);
        if (mode == 0 || md->one_index) {
            int rc = spm_cl_trace(r, 0, SPP, gp, gl, &err);
            CHECK(rc == 0, "spm_cl_trace: %s", err.msg);
            size_t diverged = 0, ncom = 0, same = 0, lam_diff = 0;
            for (size_t i = 0; i < n; i++) {
                int d = cl_test_path_differs(&gp[i], &cp[i]);
                diverged += d;
                spm_u32 bg = SPM_NONE, bc = SPM_NONE;
                float wg = 0.0f, wc = 0.0f;
                size_t jg = committed(&gp[i], &bg, &wg), jc = committed(&cp[i], &bc, &wc);
                ncom += jc != 0;
                /* the draw is at the same vertex whenever the paths agree up to it */
                if (jc && jg == jc) {
                    same++;
                    lam_diff += bg != bc || wg != wc;
                } else if (jc && !d) {
                    lam_diff++;
                }
            }
            printf("%s trace: %zu paths, %zu committed (%zu compared), %zu diverged, %zu "
                   "committed words differ\n", md->name, n, ncom, same, diverged, lam_diff);
            if (md->one_index)
                CHECK(ncom == 0, "%s commits no path (%zu did)", md->name, ncom);
            else
                CHECK(ncom > n / 20, "too few committed paths (%zu of %zu)", ncom, n);
            CHECK(lam_diff == 0, "%zu committed wavelengths differ", lam_diff);
            if (!md->one_index) {
                size_t bad_g, bad_c, tg = strata_check(gp, (size_t)W * H, &bad_g),
                                     tc = strata_check(cp, (size_t)W * H, &bad_c);
                printf("%s strata: %zu and %zu pixels of 2+ committed paths (kernel, reference), "
                       "%zu and %zu off their strata\n", md->name, tg, tc, bad_g, bad_c);
                CHECK(tg > 20 && tc > 20, "too few pixels to test the strata (%zu, %zu)", tg, tc);
                CHECK(bad_g == 0 && bad_c == 0, "committed bins not stratified: %zu pixels "
                      "(kernel), %zu (reference)", bad_g, bad_c);
            }
            CHECK((double)diverged <= MAX_DIVERGENT_FRACTION * (double)n, "%zu paths diverged",
                  diverged);
        }
        spm_ref_shade(&s.tables, mode, &p, 0, cp, cl, n, ref);
        int rc = spm_cl_shade(r, 0, SPP, cp, cl, got, &err);
        CHECK(rc == 0, "%s: spm_cl_shade: %s", md->name, err.msg);
        double worst = 0.0, wc = 0.0;
        size_t bad = rc ? 0 : cl_test_shade_diff(ref, got, n, SHADE_REL, &worst);
        /* the committed paths alone: their worst, and that they are not all black */
        size_t lit = 0;
        for (size_t i = 0; !rc && i < n; i++) {
            spm_u32 b;
            float iw;
            if (!committed(&cp[i], &b, &iw))
                continue;
            double w1;
            cl_test_shade_diff(ref + 3 * i, got + 3 * i, 1, SHADE_REL, &w1);
            wc = fmax(wc, w1);
            lit += ref[3 * i + 1] > 0.0f;
        }
        printf("sphere shade %-5s: worst %.3g relative (committed paths: %.3g, %zu lit)\n",
               md->name, worst, wc, lit);
        CHECK(bad == 0, "%s: %zu components beyond %g (worst %.3g)", md->name, bad, SHADE_REL,
              worst);
        if (!md->one_index)
            CHECK(lit > 50, "%s: committed paths that see light (%zu)", md->name, lit);
        spm_cl_destroy(r);
    }
    free(gp);
    free(cp);
    free(gl);
    free(cl);
    free(ref);
    free(got);
    cl_test_scene_close(&s);
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    test_sphere();
    TEST_END();
}
