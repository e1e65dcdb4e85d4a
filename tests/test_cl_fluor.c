/* Fluorescence, kernel against CPU reference path by path: scenes/
 * fluorescent.scene traced by the reference, shaded by every mode's kernel
 * that renders fluorescence (truth, ref, ml, mlc, rgb) and by the reference,
 * per path. And the matrices' level test: a flat input through the level-l
 * matrix gives the level-l bin means of the 1 nm product (tables.h fluor:
 * a coarse entry is the mean over the output bin of the sum over the input
 * bin). Each check is shown to see the fluorescence: enough paths meet a
 * fluorescent vertex, and the reference with the matrices' blocks zeroed
 * differs on them. */
#include "cl_testlib.h"
#include "fluor_tables.h"
#include "testutil.h"

#define W 20
#define H 16
#define SPP 5
#define SEED 5u

/* The kernel takes the same products and sums in the same order as the
 * reference, but fuses each multiply-add (one rounding instead of two): a
 * matrix-vector product over n lanes of positive terms then differs by at
 * most n/2 ulps of its result, typically a few (the roundings are not all
 * one way), per fluorescent vertex; the XYZ sum adds 4 + 2 log2(n) ulps as in
 * test_cl_shade.c. rgb's 3 x 3 has negative entries: its bound is taken of
 * the largest component, as there. Measured worst: printed below. */
static double ulps_allowed(int lanes, int nfluor_vertices)
{
    return 4.0 + 2.0 * log2((double)lanes) + 0.5 * lanes * nfluor_vertices;
}

static int fluor_vertices(const spm_path *p, int first)
{
    int n = 0;
    for (spm_u32 j = 0; j < p->h.nvert; j++) {
        spm_u32 r = p->v[j].ids & 0xFFFFu;
        if (r == SPM_NONE)
            break;
        n += r >= (spm_u32)first;
    }
    return n;
}

static void check_mode(const cl_test_scene *s, int mode)
{
    const spm_mode_desc *d = spm_mode(mode);
    size_t n = (size_t)W * H * SPP;
    spm_path *paths = spm_xcalloc(n, sizeof *paths);
    uint8_t *levels = spm_xcalloc(n, 1);
    float *ref = spm_xcalloc(3 * n, sizeof *ref), *got = spm_xcalloc(3 * n, sizeof *got);
    float *plain = spm_xcalloc(3 * n, sizeof *plain);
    spm_trace_params p = cl_test_params(s, SEED, 0, SPP);
    spm_ref_trace(&s->geom, s->tables.materials, cl_test_lvlk(&s->tables, mode), &p, paths, levels);
    spm_shade_table tabs[SPM_NUM_LEVELS];
    int lanes = 0;
    for (int sl = 0; sl < spm_mode_nslots(d); sl++) {
        spm_shade_table_build(d, &s->tables, sl, &tabs[sl]);
        lanes = tabs[sl].lanes > lanes ? tabs[sl].lanes : lanes;
    }
    spm_ref_shade_tables(d, tabs, &p, 0, paths, levels, n, ref);
    for (int sl = 0; sl < spm_mode_nslots(d); sl++) /* the matrices' fluorescent parts gone */
        memset(tabs[sl].rows + (size_t)tabs[sl].ncolours * tabs[sl].stride, 0,
               tabs[sl].fluor_floats * sizeof(float));
    spm_ref_shade_tables(d, tabs, &p, 0, paths, levels, n, plain);
    for (int sl = 0; sl < spm_mode_nslots(d); sl++)
        spm_shade_table_free(&tabs[sl]);

    spm_cl_renderer *r;
    spm_error err;
    if (spm_cl_create(0, &s->geom, &s->tables, mode, SEED, &r, &err)) {
        CHECK(0, "%s: spm_cl_create: %s", d->name, err.msg);
        goto done;
    }
    int rc = spm_cl_shade(r, p.first_sample, SPP, paths, levels, got, &err);
    CHECK(rc == 0, "%s: spm_cl_shade: %s", d->name, err.msg);
    spm_cl_destroy(r);

    size_t bad = 0, fl = 0, moved = 0, worst_i = 0;
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        int nf = fluor_vertices(&paths[i], s->tables.fluor_first);
        double m = 0.0, allowed = ulps_allowed(lanes, nf);
        for (int c = 0; c < 3; c++)
            m = fmax(m, fabs((double)ref[3 * i + c]));
        fl += nf > 0 && m > 0.0;
        moved += nf > 0 && fabs((double)plain[3 * i + 1] - (double)ref[3 * i + 1]) > 1e-3 * m;
        double ulp = m > 0.0 ? m * ldexp(1.0, -23) : ldexp(1.0, -149);
        for (int c = 0; c < 3; c++) {
            double e = fabs((double)got[3 * i + c] - (double)ref[3 * i + c]) / ulp;
            bad += !(e <= allowed);
            if (!(e <= worst)) {
                worst = e;
                worst_i = i;
            }
        }
    }
    printf("%-5s: %zu paths, %zu lit with a fluorescent vertex (%zu changed by its matrix), "
           "worst %.2f ulps (path %zu)\n", d->name, n, fl, moved, worst, worst_i);
    CHECK(fl > n / 4, "%s: too few fluorescent paths to compare (%zu)", d->name, fl);
    CHECK(moved > fl / 4, "%s: the matrices change only %zu of %zu paths", d->name, moved, fl);
    CHECK(bad == 0, "%s: %zu components beyond the bound (worst %.1f ulps at path %zu: %g %g %g vs "
          "%g %g %g)", d->name, bad, worst, worst_i, got[3 * worst_i], got[3 * worst_i + 1],
          got[3 * worst_i + 2], ref[3 * worst_i], ref[3 * worst_i + 1], ref[3 * worst_i + 2]);
done:
    free(paths);
    free(levels);
    free(ref);
    free(got);
    free(plain);
}

/* Flat input: sum_I F_l[O][I] against the mean over O of sum_i F_0[o][i].
 * Float entries summed in double; each entry carries float's rounding
 * (6e-8 relative), so 1e-6 of the row sum bounds the difference. */
static void flat_levels(const spm_tables *t)
{
    for (int f = 0; f < t->nfluor; f++) {
        const float *F0 = t->fluor[0] + (size_t)f * SPM_TRUTH_BINS * SPM_TRUTH_BINS;
        double rowsum0[SPM_TRUTH_BINS], peak = 0.0;
        for (int o = 0; o < SPM_TRUTH_BINS; o++) {
            rowsum0[o] = 0.0;
            for (int i = 0; i < SPM_TRUTH_BINS; i++)
                rowsum0[o] += F0[(size_t)o * SPM_TRUTH_BINS + i];
            peak = fmax(peak, rowsum0[o]);
        }
        CHECK(peak > 1e-3, "matrix %d: no fluorescence to test (peak row sum %g)", f, peak);
        for (int l = 1; l < SPM_NUM_LEVELS; l++) {
            int nb = SPM_LEVEL_BINS(l), w = SPM_TRUTH_BINS / nb;
            const float *Fl = t->fluor[l] + (size_t)f * nb * nb;
            double worst = 0.0;
            for (int o = 0; o < nb; o++) {
                double coarse = 0.0, fine = 0.0;
                for (int i = 0; i < nb; i++)
                    coarse += Fl[(size_t)o * nb + i];
                for (int k = 0; k < w; k++)
                    fine += rowsum0[o * w + k] / w;
                worst = fmax(worst, fabs(coarse - fine));
            }
            printf("matrix %d level %d (%d bins): flat input, worst |coarse - 1 nm means| %.3g "
                   "(peak %.3g)\n", f, l, nb, worst, peak);
            CHECK(worst <= 1e-6 * peak, "matrix %d level %d: flat input off by %g", f, l, worst);
        }
    }
}

int main(void)
{
    if (!cl_test_have_device())
        return 1;
    char path[1024];
    cl_test_scene s;
    if (cl_test_scene_load(&s, spm_data_path("scenes/fluorescent.scene", path, sizeof path), W, H))
        return 1;
    CHECK(s.tables.nfluor == 2, "the scene has %d fluorescent materials, not 2", s.tables.nfluor);
    flat_levels(&s.tables);
    { /* the scene's header says fluorescent surfaces take most vertices: measure */
        size_t n = (size_t)W * H * SPP, all = 0, fl = 0;
        spm_path *paths = spm_xcalloc(n, sizeof *paths);
        uint8_t *levels = spm_xcalloc(n, 1);
        spm_trace_params p = cl_test_params(&s, SEED, 0, SPP);
        spm_ref_trace(&s.geom, s.tables.materials, s.tables.lvlk, &p, paths, levels);
        for (size_t i = 0; i < n; i++)
            for (spm_u32 j = 0; j < paths[i].h.nvert; j++) {
                all++;
                fl += (paths[i].v[j].ids & 0xFFFFu) != SPM_NONE &&
                      (paths[i].v[j].ids & 0xFFFFu) >= (spm_u32)s.tables.fluor_first;
            }
        printf("fluorescent vertices: %zu of %zu (%.1f %%)\n", fl, all, 100.0 * (double)fl / (double)all);
        CHECK(2 * fl >= all, "fluorescent surfaces take %zu of %zu vertices, under half", fl, all);
        free(paths);
        free(levels);
    }
    int modes[] = {SPM_MODE_TRUTH, SPM_MODE_REF, SPM_MODE_ML, SPM_MODE_MLC, SPM_MODE_RGB};
    for (size_t k = 0; k < sizeof modes / sizeof modes[0]; k++)
        check_mode(&s, modes[k]);
    cl_test_scene_close(&s);
    TEST_END();
}
