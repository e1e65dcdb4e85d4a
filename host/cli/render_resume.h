/* `render --resume`: what a render is, as its film records it (the print),
 * and continuing from the film an earlier render's EXR names
 * (docs/RENDERING.md). */
#ifndef SPM_RENDER_RESUME_H
#define SPM_RENDER_RESUME_H
#include "film_file.h"
#include "render_setup.h"

/* The print of the render c/s makes: compared, the scene's prepared contents
 * (a fingerprint), mode, size, seed, spectral bins and, in a levelled mode,
 * the pretest's options; kept for the reader, the scene's path and backend. */
void spm_render_print(const spm_render_config *c, const spm_render_setup *s, spm_film_print *p);

/* The film the EXR `exr` names (its header's specmip:film, a file in the EXR's
 * directory), checked against the render's print `now` and asked to go on to
 * spp samples per pixel, into film. 0, or SPM_EXIT_INPUT with err naming the
 * file and what differs. A film that ends off the pass grid of pass_spp, or
 * was rendered on another backend, is continued with a warning: the image is
 * then not bit-identical to one render. */
int spm_resume_load(const char *exr, const spm_film_print *now, int spp, int pass_spp,
                    spm_film *film, spm_error *err);
#endif
