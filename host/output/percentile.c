#include "percentile.h"
#include <math.h>
#include <stdlib.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void spm_sort_doubles(double *v, size_t n)
{
    qsort(v, n, sizeof *v, cmp_double);
}

double spm_percentile_sorted(const double *v, size_t n, double p)
{
    if (n == 0)
        return 0.0;
    double rank = (p <= 0 ? 0 : p >= 100 ? 100 : p) / 100.0 * (double)(n - 1);
    size_t lo = (size_t)floor(rank);
    size_t hi = lo + 1 < n ? lo + 1 : lo;
    double t = rank - (double)lo;
    return v[lo] + t * (v[hi] - v[lo]);
}
