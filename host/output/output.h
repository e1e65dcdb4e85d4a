/* Writing a render: the format follows the file extension (case-insensitive).
 *   .exr .tif .tiff  float32 linear light, sRGB primaries (D65), negative values kept
 *   .png .ppm        tone-mapped 8-bit sRGB (tonemap.h)
 * (OIIO 2.4 reads PFM but has no PFM writer.)
 * Files are written to a temporary name and renamed (image_io.h); a symbolic
 * link is written through to its target. */
#ifndef SPM_OUTPUT_H
#define SPM_OUTPUT_H
#include "film.h"
#include "image_io.h"
#include "tonemap.h"
#include "util.h"

/* Call before rendering: the extension is one of the above with a name before
 * it, the path (or where its symbolic link leads) is not a directory, and its
 * directory exists and is writable. 0, or fills err. */
int spm_output_check(const char *path, spm_error *err);
/* spm_output_check for each, and no file twice, however spelt (./a.png and
 * a.png, a link and its target). 0, or fills err. */
int spm_output_check_all(const char *const *paths, int n, spm_error *err);

/* Writes xyz[3*w*h] (CIE XYZ, rows top to bottom); tm is used by display formats
 * only (NULL: spm_tonemap_default). 0, or fills err. */
int spm_output_write_xyz(const char *path, int width, int height, const float *xyz,
                         const spm_tonemap *tm, spm_error *err);
/* Writes the film's image so far (sum / samples). */
int spm_output_write_film(const char *path, const spm_film *film, const spm_tonemap *tm,
                          spm_error *err);
/* The same, with metadata in the header (image_io.h). */
int spm_output_write_film_attrs(const char *path, const spm_film *film, const spm_tonemap *tm,
                                const spm_image_attr *attrs, int nattrs, spm_error *err);
#endif
