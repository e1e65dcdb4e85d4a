/* What a rendered image says about how it was made: the header metadata of
 * `specmip render`'s outputs (names as pbrt-v4 where it has one). */
#ifndef SPM_RENDER_META_H
#define SPM_RENDER_META_H
#include "image_io.h"
#include "render_setup.h"

#define SPM_META_MAX 20

typedef struct {
    spm_image_attr a[SPM_META_MAX];
    int n;
    /* the strings the attributes point to */
    char software[64], description[1024], datetime[32], seed[16], devices[2048];
} spm_render_meta;

/* The metadata of a render of c/s that ended with r after render_s seconds
 * (samples per pixel done and asked for tell an interrupted image). */
void spm_render_meta_make(const spm_render_config *c, const spm_render_setup *s,
                          const spm_run_result *r, double render_s, spm_render_meta *m);
#endif
