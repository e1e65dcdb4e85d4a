/* Colour difference between two images (docs/METHODS.md "Comparing images"):
 * optional N x N box blur of both (linear light), one white for both (D65
 * chromaticity, Yn = 99.9th percentile of the first image's Y after the blur unless
 * given), per-pixel CIEDE2000 and Delta E*ab, and their statistics. */
#ifndef SPM_COMPARE_H
#define SPM_COMPARE_H
#include "image_io.h"
#include "util.h"

#define SPM_COMPARE_WHITE_PERCENTILE 99.9
#define SPM_COMPARE_BUCKETS 6  /* [0,1) [1,2) [2,3) [3,4) [4,5) [5,inf): disjoint, as the thesis' tables */

typedef struct {
    int blur;        /* window side N (odd); 0 or 1: no blur */
    double white_y;  /* > 0: Yn given; 0: from the first image */
} spm_compare_opts;

typedef struct {
    double mean, median, p95, p99, max;
    long long buckets[SPM_COMPARE_BUCKETS];
} spm_de_stats;

typedef struct {
    int width, height;
    double white_y;      /* the Yn used */
    long long nonfinite; /* NaN/Inf input values, replaced by 0 before the blur */
    spm_de_stats de00, deab;
    double *de00_map;    /* per-pixel CIEDE2000, width*height */
} spm_compare_result;

/* N x N box blur in place; near the border each pixel is the mean over the part of
 * its window inside the image (no padding, so a uniform image stays uniform). */
void spm_box_blur(spm_image *img, int n);

/* Compares a (reference) with b; a and b are blurred in place. 0, or fills err
 * (different sizes, even blur, no usable white). */
int spm_compare_images(spm_image *a, spm_image *b, const spm_compare_opts *opts,
                       spm_compare_result *res, spm_error *err);
void spm_compare_result_free(spm_compare_result *res);
#endif
