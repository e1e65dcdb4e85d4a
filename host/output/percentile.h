/* Percentiles of a sample, shared by tone mapping and image comparison. */
#ifndef SPM_PERCENTILE_H
#define SPM_PERCENTILE_H
#include <stddef.h>

/* Sorts v[0..n) ascending (NaNs must have been removed). */
void spm_sort_doubles(double *v, size_t n);
/* p-th percentile (0..100) of an ascending array, linearly interpolated between
 * the order statistics at rank p/100*(n-1) (the common "type 7" definition). 0 if n == 0. */
double spm_percentile_sorted(const double *v, size_t n, double p);
#endif
