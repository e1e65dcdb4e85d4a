/* Area-preserving resampling into 1 nm truth bins, the spectral levels derived
 * from them, and the bin-integrated CIE 1931 weights. All arithmetic in double. */
#include "spectrum.h"
#include "csv.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Integral over [a, b] of the line through (x0, y0) and (x1, y1), restricted
 * to the segment [x0, x1]; 0 when they do not overlap. */
static double segment_integral(double x0, double y0, double x1, double y1, double a, double b)
{
    double lo = a > x0 ? a : x0, hi = b < x1 ? b : x1;
    if (hi <= lo)
        return 0.0;
    double slope = (y1 - y0) / (x1 - x0);
    double ylo = y0 + slope * (lo - x0), yhi = y0 + slope * (hi - x0);
    return 0.5 * (ylo + yhi) * (hi - lo);
}

/* Truth bin i holds the mean (bin width 1 nm, so the integral) of the
 * piecewise-linear function through the n points, zero outside them. */
static void integrate_truth(const double *x, const double *y, size_t n, double *nm1)
{
    size_t k = 0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double a = SPM_LAMBDA_MIN + i, b = a + 1.0, sum = 0.0;
        while (k + 1 < n && x[k + 1] <= a)
            k++;
        for (size_t j = k; j + 1 < n && x[j] < b; j++)
            sum += segment_integral(x[j], y[j], x[j + 1], y[j + 1], a, b);
        nm1[i] = sum;
    }
}

int spm_spectrum_from_samples(const double *wl, const double *val, size_t n, spm_kind kind,
                              const char *what, spm_spectrum *out, spm_error *err)
{
    size_t inside = 0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(wl[i]) || !isfinite(val[i])) {
            spm_errorf(err, "%s: sample %zu is not a finite number", what, i + 1);
            return 1;
        }
        if (val[i] < 0) {
            spm_errorf(err, "%s: negative value %g at %g nm", what, val[i], wl[i]);
            return 1;
        }
        if (i > 0 && wl[i] <= wl[i - 1]) {
            spm_errorf(err, "%s: wavelengths must increase strictly (%g nm after %g nm)", what,
                       wl[i], wl[i - 1]);
            return 1;
        }
        inside += wl[i] >= SPM_LAMBDA_MIN && wl[i] <= SPM_LAMBDA_MAX;
    }
    if (inside == 0) {
        if (n == 0)
            spm_errorf(err, "%s: no samples", what);
        else
            spm_errorf(err, "%s: no samples inside %d-%d nm (data spans %g-%g nm)", what,
                       SPM_LAMBDA_MIN, SPM_LAMBDA_MAX, wl[0], wl[n - 1]);
        return 1;
    }
    /* Partial coverage: a reflectance continues at its end values, an emission
     * stops (zero outside its samples, which integrate_truth gives for free). */
    double *x = spm_xmalloc((n + 2) * sizeof *x), *y = spm_xmalloc((n + 2) * sizeof *y);
    size_t m = 0;
    int lo_gap = wl[0] > SPM_LAMBDA_MIN, hi_gap = wl[n - 1] < SPM_LAMBDA_MAX;
    if (lo_gap || hi_gap)
        spm_warnf("%s: samples cover %g-%g nm only; %s", what, wl[0], wl[n - 1],
                  kind == SPM_KIND_REFLECTANCE ? "extended by the end values"
                                               : "zero outside them");
    if (lo_gap && kind == SPM_KIND_REFLECTANCE) {
        x[m] = SPM_LAMBDA_MIN;
        y[m++] = val[0];
    }
    for (size_t i = 0; i < n; i++, m++) {
        x[m] = wl[i];
        y[m] = val[i];
    }
    if (hi_gap && kind == SPM_KIND_REFLECTANCE) {
        x[m] = SPM_LAMBDA_MAX;
        y[m++] = val[n - 1];
    }
    out->kind = kind;
    integrate_truth(x, y, m, out->nm1);
    free(x);
    free(y);
    return 0;
}

void spm_spectrum_constant(double value, spm_kind kind, spm_spectrum *out)
{
    out->kind = kind;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        out->nm1[i] = value;
}

static double planck(double kelvin, double nm)
{
    const double c2 = 1.4387768775e-2; /* second radiation constant, m K (CODATA 2018) */
    double m = nm * 1e-9;
    return 1.0 / (pow(m, 5) * (exp(c2 / (m * kelvin)) - 1.0));
}

void spm_spectrum_blackbody(double kelvin, spm_spectrum *out)
{
    /* Bin means by Simpson's rule, relative to the value at 560 nm (as CIE A is). */
    double ref = planck(kelvin, 560.0);
    out->kind = SPM_KIND_EMISSION;
    for (int i = 0; i < SPM_TRUTH_BINS; i++) {
        double a = SPM_LAMBDA_MIN + i;
        out->nm1[i] =
            (planck(kelvin, a) + 4.0 * planck(kelvin, a + 0.5) + planck(kelvin, a + 1.0)) /
            (6.0 * ref);
    }
}

void spm_spectrum_scale(spm_spectrum *s, double f)
{
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        s->nm1[i] *= f;
}

void spm_spectrum_multiply(spm_spectrum *s, const spm_spectrum *by)
{
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        s->nm1[i] *= by->nm1[i];
}

void spm_spectrum_level(const spm_spectrum *s, int level, double *out)
{
    if (level == 0) {
        memcpy(out, s->nm1, sizeof s->nm1);
        return;
    }
    const int w = SPM_TRUTH_BINS / SPM_NM5_BINS;
    double l1[SPM_NM5_BINS];
    for (int b = 0; b < SPM_NM5_BINS; b++) {
        double sum = 0.0;
        for (int j = 0; j < w; j++)
            sum += s->nm1[b * w + j];
        l1[b] = sum / w;
    }
    /* Each coarser level averages pairs of the finer one, in place. */
    for (int l = 2; l <= level; l++)
        for (int b = 0; b < SPM_LEVEL_BINS(l); b++)
            l1[b] = 0.5 * (l1[2 * b] + l1[2 * b + 1]);
    memcpy(out, l1, (size_t)SPM_LEVEL_BINS(level) * sizeof *out);
}

double spm_spectrum_mean(const spm_spectrum *s)
{
    double sum = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        sum += s->nm1[i];
    return sum / SPM_TRUTH_BINS;
}

double spm_spectrum_max(const spm_spectrum *s)
{
    double m = s->nm1[0];
    for (int i = 1; i < SPM_TRUTH_BINS; i++)
        m = s->nm1[i] > m ? s->nm1[i] : m;
    return m;
}

/* ---- CIE 1931 weights ------------------------------------------------------ */

/* Spectra from CSV tables: one value column, checked row by row so every
 * error names its file and line. */
int spm_spectrum_from_csv(const spm_csv *c, int col, const char *path, spm_kind kind,
                          spm_spectrum *out, spm_error *err)
{
    size_t n = c->nrows;
    double *wl = spm_xmalloc(n * sizeof *wl), *val = spm_xmalloc(n * sizeof *val);
    int rc = 0;
    for (size_t r = 0; r < n && !rc; r++) {
        wl[r] = c->data[r * (size_t)c->ncols];
        val[r] = c->data[r * (size_t)c->ncols + (size_t)col];
        if (r > 0 && wl[r] <= wl[r - 1]) {
            spm_errorf(err, "%s:%d: wavelengths must increase strictly (%g nm after %g nm)",
                       path, c->line[r], wl[r], wl[r - 1]);
            rc = 1;
        } else if (val[r] < 0) {
            spm_errorf(err, "%s:%d: negative %s %g in column %s", path, c->line[r],
                       kind == SPM_KIND_EMISSION ? "emission" : "reflectance", val[r],
                       c->names[col]);
            rc = 1;
        }
    }
    if (!rc) {
        /* Coverage problems concern the whole column: report them at its first row. */
        char what[1100];
        snprintf(what, sizeof what, "%s:%d", path, c->line[0]);
        rc = spm_spectrum_from_samples(wl, val, n, kind, what, out, err);
    }
    free(wl);
    free(val);
    return rc;
}

int spm_spectrum_load(const char *path, const char *column, spm_kind kind, spm_spectrum *out,
                      spm_error *err)
{
    spm_csv c;
    if (spm_csv_load(path, &c, err))
        return 1;
    int col = 1, rc = 0;
    if (column) {
        col = spm_csv_column(&c, column);
        if (col < 0) {
            spm_errorf(err, "%s:%d: no column named '%s'", path, c.header_line, column);
            rc = 1;
        }
    } else if (c.ncols > 2) {
        spm_errorf(err, "%s:%d: %d value columns (%s, %s, ...): choose one by name", path,
                   c.header_line, c.ncols - 1, c.names[1], c.names[2]);
        rc = 1;
    }
    if (!rc)
        rc = spm_spectrum_from_csv(&c, col, path, kind, out, err);
    spm_csv_free(&c);
    return rc;
}

#define CMF_FILE "spectra/cie1931_2deg_cmf_1nm.csv"

static int cmf_ready;
static double cmf_w[3][SPM_TRUTH_BINS];
static double *cmf_tab;      /* the 1 nm table, rows of (nm, x, y, z) */
static size_t cmf_rows;
static double cmf_norm;      /* 1 / integral of y-bar over 380-780 nm */

int spm_cmf_init(spm_error *err)
{
    if (cmf_ready)
        return 0;
    char path[4096];
    spm_data_path(CMF_FILE, path, sizeof path);
    spm_csv c;
    if (spm_csv_load(path, &c, err))
        return 1;
    spm_spectrum s[3];
    int bad = c.ncols != 4 || c.nrows < 2 || spm_csv_column(&c, "x") != 1 ||
              spm_csv_column(&c, "y") != 2 || spm_csv_column(&c, "z") != 3;
    if (bad)
        spm_errorf(err, "%s:%d: expected columns wavelength,x,y,z and at least two rows", path,
                   c.header_line);
    for (int k = 0; k < 3 && !bad; k++)
        bad = spm_spectrum_from_csv(&c, 1 + k, path, SPM_KIND_EMISSION, &s[k], err);
    if (bad) {
        spm_csv_free(&c);
        return 1;
    }
    double ysum = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        ysum += s[1].nm1[i];
    cmf_norm = 1.0 / ysum;
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < SPM_TRUTH_BINS; i++)
            cmf_w[k][i] = s[k].nm1[i] * cmf_norm;
    cmf_tab = c.data; /* kept for spm_cmf_point; the rest of the table is freed */
    cmf_rows = c.nrows;
    c.data = NULL;
    spm_csv_free(&c);
    cmf_ready = 1;
    return 0;
}

/* The weights are needed by functions that cannot fail; the table is bundled
 * data, so a missing one means a broken installation: stop with its message. */
static void cmf_require(void)
{
    spm_error err;
    if (!cmf_ready && spm_cmf_init(&err)) {
        fprintf(stderr, "specmip: %s\n", err.msg);
        exit(SPM_EXIT_RUNTIME);
    }
}

const double (*spm_cmf_truth(void))[SPM_TRUTH_BINS]
{
    cmf_require();
    return (const double(*)[SPM_TRUTH_BINS])cmf_w;
}

void spm_cmf_level(int level, double out[3][SPM_TRUTH_BINS])
{
    cmf_require();
    int w = SPM_TRUTH_BINS / SPM_LEVEL_BINS(level);
    for (int k = 0; k < 3; k++)
        for (int b = 0; b < SPM_LEVEL_BINS(level); b++) {
            double sum = 0.0;
            for (int j = 0; j < w; j++)
                sum += cmf_w[k][b * w + j];
            out[k][b] = sum;
        }
}

double spm_cmf_y_integral(void)
{
    cmf_require();
    return 1.0 / cmf_norm;
}

void spm_cmf_point(double lambda_nm, double out[3])
{
    cmf_require();
    out[0] = out[1] = out[2] = 0.0;
    const double *t = cmf_tab;
    if (!(lambda_nm >= t[0] && lambda_nm <= t[(cmf_rows - 1) * 4]))
        return;
    size_t lo = 0, hi = cmf_rows - 1; /* binary search: the table may be irregular */
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (t[mid * 4] <= lambda_nm)
            lo = mid;
        else
            hi = mid;
    }
    double f = (lambda_nm - t[lo * 4]) / (t[hi * 4] - t[lo * 4]);
    for (int k = 0; k < 3; k++)
        out[k] = ((1.0 - f) * t[lo * 4 + 1 + k] + f * t[hi * 4 + 1 + k]) * cmf_norm;
}
