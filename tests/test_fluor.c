/* The fluorescent model at 1 nm (host/scene/fluor.h) on scenes/
 * fluorescent.scene's dyes: no light below its wavelength (M[o][i] = 0 for
 * o <= i), each column sums to YIELD A(i) where emission lies above bin i and
 * to 0 where none does (the emission truncated to o > i and normalised
 * there), so no column puts out more than it takes in with the diagonal
 * SPEC (1 - A); and Russian roulette's albedo is the mean column sum.
 * An emission shape measured over part of the range only is an emission:
 * zero outside its samples (docs/SCENE_FORMAT.md "Spectra files"), so a dye
 * whose shape is given over 380-400 nm emits nothing above 400 nm. */
#include <math.h>
#include <stdlib.h>
#include <unistd.h>
#include "fluor.h"
#include "testutil.h"

static void check_material(const spm_scene *sc, const spm_scene_material *m)
{
    double *F = spm_xcalloc((size_t)SPM_TRUTH_BINS * SPM_TRUTH_BINS, sizeof *F);
    spm_fluor_matrix_1nm(sc, m, F);
    const double *A = sc->colours[m->col2].s.nm1, *e = sc->colours[m->col3].s.nm1;
    const double *S = sc->colours[m->refl].s.nm1;
    double y = m->p[SPM_FLUOR_P_YIELD], worst = 0.0, upper = 0.0, total = 0.0;
    int zero_cols = 0, most = 0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double sum = 0.0, above = 0.0;
        for (int o = 0; o < SPM_TRUTH_BINS; o++) {
            double v = F[(size_t)o * SPM_TRUTH_BINS + i];
            sum += v;
            if (o <= i)
                upper = fmax(upper, fabs(v));
        }
        for (int o = i + 1; o < SPM_TRUTH_BINS; o++)
            above += e[o];
        double want = above > 0.0 ? y * A[i] : 0.0;
        zero_cols += !(above > 0.0);
        worst = fmax(worst, fabs(sum - want));
        double out = sum + S[i] * (1.0 - A[i]);
        most = out > 1.0 + 1e-12 ? i + 1 : most;
        total += out;
    }
    printf("%s: worst |column sum - YIELD A| %.3g, largest entry at o <= i %.3g, %d columns "
           "without emission above, albedo %.6f\n", m->name, worst, upper, zero_cols,
           total / SPM_TRUTH_BINS);
    CHECK(worst <= 1e-12, "%s: a column sums to %g away from YIELD A(i)", m->name, worst);
    CHECK(upper == 0.0, "%s: light at or below its input wavelength (%g)", m->name, upper);
    CHECK(most == 0, "%s: column %d puts out more than it takes in", m->name, most - 1);
    CHECK(fabs(total / SPM_TRUTH_BINS - spm_fluor_albedo(sc, m)) <= 1e-12,
          "%s: albedo %g is not the mean column sum %g", m->name, spm_fluor_albedo(sc, m),
          total / SPM_TRUTH_BINS);
    free(F);
}

/* A shape given at 380, 390 and 400 nm only, under a flat absorption. */
static void check_partial_shape(void)
{
    char path[] = "/tmp/spm_fluor_shapeXXXXXX";
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f) {
        CHECK(0, "cannot write a scene at %s", path);
        return;
    }
    fprintf(f, "image 4 4\ncamera position 0 0 0  direction 0 0 1  fov 40\nspectrum half equal\n"
               "spectrum violet inline 380 0.2 390 1 400 0.5 end\n"
               "material dye reflect half fluoresce half violet 0.8\n"
               "material lamp emit half\n"
               "tri dye 0 0 1  1 0 1  0 1 1\n"
               "tri lamp 0 0 -1  0 1 -1  1 0 -1\n");
    fclose(f);
    spm_scene sc;
    spm_error err;
    int rc = spm_scene_load(path, &sc, &err);
    unlink(path);
    if (rc) {
        CHECK(0, "%s", err.msg);
        return;
    }
    const spm_scene_material *m = &sc.materials[0];
    const double *e = sc.colours[m->col3].s.nm1;
    double inside = 0.0, outside = 0.0;
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        *(b < 400 - SPM_LAMBDA_MIN ? &inside : &outside) += e[b];
    printf("partial shape: %.4f inside 380-400 nm, %.4f above\n", inside, outside);
    CHECK(inside > 5.0 && outside == 0.0, "a shape over 380-400 nm: %g inside, %g above (zero "
          "outside its samples, as an emission)", inside, outside);
    check_material(&sc, m);
    spm_scene_free(&sc);
}

int main(void)
{
    check_partial_shape();
    char path[1024];
    spm_scene sc;
    spm_error err;
    spm_quiet_warnings = 1;
    if (spm_scene_load(spm_data_path("scenes/fluorescent.scene", path, sizeof path), &sc, &err)) {
        CHECK(0, "%s", err.msg);
        TEST_END();
    }
    int n = 0;
    for (int m = 0; m < sc.nmaterials; m++)
        if (sc.materials[m].type == (int)SPM_MAT_FLUOR) {
            check_material(&sc, &sc.materials[m]);
            n++;
        }
    CHECK(n == 2, "%d fluorescent materials, not 2", n);
    spm_scene_free(&sc);
    TEST_END();
}
