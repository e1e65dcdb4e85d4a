/* Hints on a render that may show nothing: warnings naming the likely cause,
 * never errors (the exit status is unchanged). The camera inside a closed
 * mesh is the scene's own hint (scene_hints.h). */
#ifndef SPM_RENDER_HINTS_H
#define SPM_RENDER_HINTS_H
#include "film.h"
#include "geometry.h"

/* Warns once per one-sided emitting material none of whose triangles can
 * matter: for each, the ray from its centroid along its normal hits no
 * triangle and the camera is not in front of its plane. Returns how many
 * materials it warned of. */
int spm_render_hint_emitters(const spm_scene *sc, const spm_geometry *g);
/* Warns when every pixel of the film is zero: no light reached the camera.
 * Returns 1 when it warned. */
int spm_render_hint_black(const spm_film *f);
#endif
