/* The fluorescent surface's 1 nm model (fluor.h). */
#include "fluor.h"
#include <string.h>

static const double *bins_of(const spm_scene *sc, int c)
{
    return c >= 0 ? sc->colours[c].s.nm1 : NULL;
}

/* Z[i] = sum over o > i of e[o]: the emission left above bin i. */
static void tail_sums(const double *e, double *Z)
{
    double acc = 0.0;
    for (int i = SPM_TRUTH_BINS - 1; i >= 0; i--) {
        Z[i] = acc;
        acc += e ? e[i] : 0.0;
    }
}

void spm_fluor_matrix_1nm(const spm_scene *sc, const spm_scene_material *m, double *F)
{
    const double *A = bins_of(sc, m->col2), *e = bins_of(sc, m->col3);
    double Z[SPM_TRUTH_BINS], y = m->p[SPM_FLUOR_P_YIELD];
    tail_sums(e, Z);
    memset(F, 0, sizeof *F * SPM_TRUTH_BINS * SPM_TRUTH_BINS);
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        if (!(Z[i] > 0.0) || !A)
            continue;
        double k = y * A[i] / Z[i]; /* YIELD A(i) / Z(i) */
        for (int o = i + 1; o < SPM_TRUTH_BINS; o++)
            F[(size_t)o * SPM_TRUTH_BINS + i] = k * e[o];
    }
}

void spm_fluor_diagonal(const spm_scene *sc, const spm_scene_material *m, spm_spectrum *out)
{
    const double *S = bins_of(sc, m->refl), *A = bins_of(sc, m->col2);
    memset(out, 0, sizeof *out);
    out->kind = SPM_KIND_REFLECTANCE;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        out->nm1[i] = (S ? S[i] : 0.0) * (1.0 - (A ? A[i] : 0.0));
}

double spm_fluor_albedo(const spm_scene *sc, const spm_scene_material *m)
{
    const double *A = bins_of(sc, m->col2), *e = bins_of(sc, m->col3);
    double Z[SPM_TRUTH_BINS], y = m->p[SPM_FLUOR_P_YIELD], sum = 0.0;
    spm_spectrum D;
    tail_sums(e, Z);
    spm_fluor_diagonal(sc, m, &D);
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        sum += D.nm1[i] + (Z[i] > 0.0 && A ? y * A[i] : 0.0);
    return sum / SPM_TRUTH_BINS;
}
