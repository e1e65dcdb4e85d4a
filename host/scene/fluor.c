/* The fluorescent surface's 1 nm model (fluor.h). */
#include "fluor.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "csv.h"

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
    if (m->type == (int)SPM_MAT_DONALDSON) {
        int k = (int)m->p[SPM_FLUOR_P_MATRIX];
        memcpy(F, sc->rerad + (size_t)k * SPM_TRUTH_BINS * SPM_TRUTH_BINS,
               sizeof *F * SPM_TRUTH_BINS * SPM_TRUTH_BINS);
        return;
    }
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
    double *F = spm_xcalloc((size_t)SPM_TRUTH_BINS * SPM_TRUTH_BINS, sizeof *F), sum = 0.0;
    spm_spectrum D;
    spm_fluor_matrix_1nm(sc, m, F);
    spm_fluor_diagonal(sc, m, &D);
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        sum += D.nm1[i];
        for (int o = 0; o < SPM_TRUTH_BINS; o++)
            sum += F[(size_t)o * SPM_TRUTH_BINS + i];
    }
    free(F);
    return sum / SPM_TRUTH_BINS;
}

/* ---- measured matrices ------------------------------------------------------ */

/* The sample interval holding x: wl[k] <= x < wl[k + 1], or -1 outside. */
static int interval(const double *wl, int n, double x)
{
    if (!(x >= wl[0]) || !(x < wl[n - 1]))
        return -1;
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (wl[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The fluorescent part at (lo, li) nm: bilinear in the samples v[r][c]
 * (row r excitation, column c emission), the diagonal counted 0. */
static double bilinear(const double *wl, int n, const double *v, double lo, double li)
{
    int c = interval(wl, n, lo), r = interval(wl, n, li);
    if (c < 0 || r < 0)
        return 0.0;
    double tc = (lo - wl[c]) / (wl[c + 1] - wl[c]), tr = (li - wl[r]) / (wl[r + 1] - wl[r]);
    double q[2][2];
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++)
            q[a][b] = r + a == c + b ? 0.0 : v[(size_t)(r + a) * n + (size_t)(c + b)];
    return (1 - tr) * ((1 - tc) * q[0][0] + tc * q[0][1]) + tr * ((1 - tc) * q[1][0] + tc * q[1][1]);
}

/* Emission wavelengths from the header (em<nm>), increasing; 0 or err. */
static int emission_columns(const char *path, const spm_csv *csv, double *wl, spm_error *err)
{
    for (int c = 1; c < csv->ncols; c++) {
        const char *nm = csv->names[c];
        char *end = NULL;
        double w = strncmp(nm, "em", 2) == 0 ? strtod(nm + 2, &end) : NAN;
        if (!end || *end || !isfinite(w) || (c > 1 && !(w > wl[c - 2]))) {
            spm_errorf(err, "%s:%d: column %d '%s': an emission column is named em<nm> "
                            "(em450, em452.5), wavelengths increasing", path, csv->header_line,
                       c + 1, nm);
            return 1;
        }
        wl[c - 1] = w;
    }
    return 0;
}

/* The samples: square, the same wavelengths both ways, no negative entry and
 * none below the diagonal's wavelength. */
static int check_samples(const char *path, const spm_csv *csv, const double *wl, spm_error *err)
{
    int n = csv->ncols - 1;
    if ((int)csv->nrows != n) {
        spm_errorf(err, "%s:%d: %zu excitation rows for %d emission columns: the matrix must be "
                        "square, the same wavelengths both ways", path, csv->header_line,
                   csv->nrows, n);
        return 1;
    }
    for (int r = 0; r < n; r++) {
        const double *row = csv->data + (size_t)r * csv->ncols;
        if (fabs(row[0] - wl[r]) > 1e-9 * wl[r]) {
            spm_errorf(err, "%s:%d: excitation %g nm: row %d must be at the wavelength of "
                            "column em%g", path, csv->line[r], row[0], r + 1, wl[r]);
            return 1;
        }
        for (int c = 0; c < n; c++) {
            if (row[c + 1] < 0.0) {
                spm_errorf(err, "%s:%d: em%g: negative entry %g", path, csv->line[r], wl[c],
                           row[c + 1]);
                return 1;
            }
            if (c < r && row[c + 1] != 0.0) {
                spm_errorf(err, "%s:%d: em%g: %g below the excitation wavelength %g nm "
                                "(anti-Stokes light is not modelled: the entry must be 0)",
                           path, csv->line[r], wl[c], row[c + 1], row[0]);
                return 1;
            }
        }
    }
    return 0;
}

int spm_fluor_load_donaldson(const char *path, spm_spectrum *diag, double *F, spm_error *err)
{
    spm_csv csv;
    if (spm_csv_load(path, &csv, err))
        return 1;
    int n = csv.ncols - 1, rc = 1;
    double *wl = spm_xcalloc((size_t)n + 1, sizeof *wl);
    double *v = spm_xcalloc((size_t)n * (size_t)n + 1, sizeof *v), *d = spm_xcalloc((size_t)n + 1, sizeof *d);
    if (n < 2) {
        spm_errorf(err, "%s:%d: a matrix needs at least two emission columns", path, csv.header_line);
        goto out;
    }
    if (emission_columns(path, &csv, wl, err) || check_samples(path, &csv, wl, err))
        goto out;
    for (int r = 0; r < n; r++) {
        for (int c = 0; c < n; c++)
            v[(size_t)r * n + c] = csv.data[(size_t)r * csv.ncols + 1 + c];
        d[r] = v[(size_t)r * n + r];
    }
    char what[1100];
    snprintf(what, sizeof what, "%s: the diagonal", path);
    if (spm_spectrum_from_samples(wl, d, (size_t)n, SPM_KIND_REFLECTANCE, what, diag, err))
        goto out;
    /* F[o][i]: the density at the bin centres times the 1 nm bin */
    for (int o = 0; o < SPM_TRUTH_BINS; o++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            F[(size_t)o * SPM_TRUTH_BINS + i] =
                o > i ? bilinear(wl, n, v, SPM_LAMBDA_MIN + o + 0.5, SPM_LAMBDA_MIN + i + 0.5) : 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double out = diag->nm1[i];
        for (int o = 0; o < SPM_TRUTH_BINS; o++)
            out += F[(size_t)o * SPM_TRUTH_BINS + i];
        if (out > 1.0 + 1e-9) {
            spm_errorf(err, "%s: excitation at %d nm puts out %.4g of the light it takes in (the "
                            "diagonal plus the integral of its column over emission, at most 1)",
                       path, SPM_LAMBDA_MIN + i, out);
            goto out;
        }
    }
    rc = 0;
out:
    free(wl);
    free(v);
    free(d);
    spm_csv_free(&csv);
    return rc;
}
