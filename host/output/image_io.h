/* Image files through OpenImageIO: read any image OIIO reads as linear float RGB,
 * write float or 8-bit RGB (host/output/image_io.cpp; the project's other C++ files
 * read textures: host/scene/texture_io.cpp and mesh_texture_io.cpp). */
#ifndef SPM_IMAGE_IO_H
#define SPM_IMAGE_IO_H
#ifdef __cplusplus
extern "C" {
#endif
#include "util.h" /* a C header: its declarations need C linkage here too */

/* width x height pixels, 3 floats (R, G, B) each, rows top to bottom. */
typedef struct {
    int width, height;
    float *rgb;
    int encoded;                /* read from display-encoded integer codes (decoded to linear) */
} spm_image;

typedef enum { SPM_PIXEL_FLOAT = 0, SPM_PIXEL_UINT8 = 1 } spm_pixel_type;

/* Reads the first three channels (one or two channels: the first is repeated as grey).
 * Float and half files are taken as linear light (linear sRGB primaries); integer
 * files (8/16-bit PNG, JPEG, TIFF...) as sRGB-encoded and decoded to linear.
 * Returns 0, or fills err naming the file. Free with spm_image_free. */
int spm_image_read(const char *path, spm_image *img, spm_error *err);
void spm_image_free(spm_image *img);

/* Writes 3-channel pixels: SPM_PIXEL_FLOAT takes float[3*w*h] stored as float32
 * (EXR/TIFF/PFM keep negative and > 1 values), SPM_PIXEL_UINT8 takes unsigned
 * char[3*w*h] of already display-encoded values. The format follows the extension.
 * The data go to a new temporary file in the same directory, which is renamed over
 * `path` only once complete: a failed write leaves an existing file untouched and
 * no temporary behind, and so does a second interruption (interrupt.h). A path
 * that is a symbolic link is written through: the link stays, and its target
 * (spm_image_target) is replaced the same way, the temporary file being made
 * in the target's directory. Returns 0, or fills err naming the file. */
int spm_image_write(const char *path, int width, int height, const void *pixels,
                    spm_pixel_type type, spm_error *err);

/* A piece of metadata for the image header. EXR keeps its type; formats that
 * carry only text (PNG's text chunks) get the value as text, and TIFF keeps
 * the standard names only ("Software", "ImageDescription", "DateTime"). */
typedef enum { SPM_ATTR_INT, SPM_ATTR_FLOAT, SPM_ATTR_STRING } spm_attr_type;
typedef struct {
    const char *name;
    spm_attr_type type;
    int i;       /* SPM_ATTR_INT */
    float f;     /* SPM_ATTR_FLOAT */
    const char *s;
} spm_image_attr;

/* spm_image_write, with nattrs attributes in the header. */
int spm_image_write_attrs(const char *path, int width, int height, const void *pixels,
                          spm_pixel_type type, const spm_image_attr *attrs, int nattrs,
                          spm_error *err);

/* Writes nch float32 channels named names[0..nch) (pixels: nch floats a
 * pixel, rows top to bottom) with nattrs attributes, replacing the file as
 * spm_image_write does. For formats that take any channel names (EXR). */
int spm_image_write_channels(const char *path, int width, int height, int nch,
                             const char *const *names, const float *pixels,
                             const spm_image_attr *attrs, int nattrs, spm_error *err);

/* The file writing `path` replaces: path itself, or the file its symbolic
 * link(s) lead to (for a dangling link, the file it names), as an absolute
 * path whose directory part is free of links and "."/"..", so that two
 * spellings of one file give the same string. Its directory must exist.
 * Malloc'd; NULL with err filled. */
char *spm_image_target(const char *path, spm_error *err);

/* A fresh, exclusively created empty file next to `target` (an absolute
 * path, spm_image_target), named dir/.base.spmtmp-PID-N with the extension
 * ext, registered as a temporary file (interrupt.h) in *slot from before it
 * exists. Malloc'd; NULL with *errnum set. */
char *spm_temp_create(const char *target, const char *ext, int *slot, int *errnum);

/* The string attribute `name` of an image's header into buf: 1, 0 when the
 * header has none, -1 with err filled when the file cannot be read. */
int spm_image_read_string_attr(const char *path, const char *name, char *buf, size_t size,
                               spm_error *err);

/* 1 if OIIO has a writer for this file name's extension. */
int spm_image_can_write(const char *path);

#ifdef __cplusplus
}
#endif
#endif
