/* The bench compares renders held in memory: a film as the linear sRGB image
 * the compare API takes, and ΔE statistics of two such images without
 * touching them (spm_compare_images blurs its inputs in place). */
#ifndef SPM_BENCH_IMAGE_H
#define SPM_BENCH_IMAGE_H
#include "compare.h"
#include "film.h"

/* The film's image so far (sum / samples) as linear sRGB. Free with spm_image_free. */
void spm_bench_film_image(const spm_film *film, spm_image *out);

/* ΔE00 statistics of img against ref (ref gives the white) after an N x N blur. */
int spm_bench_delta_e(const spm_image *ref, const spm_image *img, int blur, spm_de_stats *out,
                      spm_error *err);
#endif
