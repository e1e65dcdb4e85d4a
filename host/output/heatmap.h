/* False-colour map of per-pixel Delta E with a colour bar at its right.
 * The scale is fixed, 0 to SPM_HEATMAP_MAX (larger values get the top colour), so
 * maps of different runs can be set side by side. The bar has a tick mark at every
 * integer and labels (a built-in 3x5 pixel digit font) at the even ones. */
#ifndef SPM_HEATMAP_H
#define SPM_HEATMAP_H
#include "util.h"

#define SPM_HEATMAP_MAX 10.0

/* 8-bit sRGB colour of a Delta E value. */
void spm_heatmap_colour(double de, unsigned char rgb[3]);
/* Canvas size for a width x height map (map at the top left, bar to the right). */
void spm_heatmap_size(int width, int height, int *canvas_w, int *canvas_h);
/* Writes the map of de[width*height] (8-bit, format by extension). 0, or fills err. */
int spm_heatmap_write(const char *path, int width, int height, const double *de, spm_error *err);
#endif
