/* The camera statement and the command line's camera overrides (scene_camera.c). */
#ifndef SPM_SCENE_CAMERA_H
#define SPM_SCENE_CAMERA_H
#include "scene.h"
#include "scene_build.h"
#include "scene_lexer.h"

/* The clauses after the 'camera' keyword, up to the end of the statement
 * (not consumed); `where` names the statement in messages. */
int spm_parse_camera(spm_lexer *lx, spm_scene_builder *b, const char *where, spm_error *err);
/* The command line's camera: --look-from, --look-at, --fov (0: not given). */
typedef struct {
    int has_from, has_at;
    double from[3], at[3];
    double fov;
} spm_camera_override;
/* o over scene s's camera: --look-from alone keeps the direction; the up
 * vector, when the scene gave one, is made normal to the new direction;
 * --fov (across the scene's fov axis) makes an orthographic camera a
 * perspective one. */
int spm_scene_camera_override(spm_scene *s, const spm_camera_override *o, spm_error *err);
#endif
