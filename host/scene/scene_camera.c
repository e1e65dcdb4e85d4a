/* The camera statement of specmip's scene format (docs/SCENE_FORMAT.md):
 *   camera position X Y Z (direction X Y Z | lookat X Y Z) [up X Y Z]
 *          (fov DEGREES | orthographic SIZE) [horizontal | vertical]
 *          [aperture DIAMETER] [focus DISTANCE]
 * and the command line's overrides of a loaded scene's camera. The field of
 * view is horizontal unless `vertical` follows it (MiniLight's, kept for
 * scenes written before); 1..179 degrees, unclamped (MiniLight's own files
 * keep its 10..160 clamp, scene_minilight.c). */
#include "scene_camera.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "scene_build.h"

enum { K_POSITION, K_DIRECTION, K_LOOKAT, K_UP, K_FOV, K_ORTHO, K_APERTURE, K_FOCUS, K_N };
static const char *const keys[K_N] = {"position", "direction", "lookat",   "up",
                                      "fov",      "orthographic", "aperture", "focus"};

typedef struct {
    int have[K_N];
    double v[K_N][3];
    int axis;
} camera_words;

static int numbers(spm_lexer *lx, int n, const char *what, double lo, double hi, double *v,
                   spm_error *err)
{
    for (int k = 0; k < n; k++)
        if (spm_lex_number(lx, what, lo, hi, &v[k], err))
            return 1;
    return 0;
}

/* One clause: its keyword (each once; direction and lookat exclusive, fov
 * and orthographic too) and its numbers, an axis word after fov/orthographic. */
static int clause(spm_lexer *lx, camera_words *c, spm_error *err)
{
    int k = 0;
    while (k < K_N && !spm_lex_is(lx, keys[k]))
        k++;
    if (k == K_N || c->have[k] || (k == K_DIRECTION && c->have[K_LOOKAT]) ||
        (k == K_LOOKAT && c->have[K_DIRECTION]) || (k == K_FOV && c->have[K_ORTHO]) ||
        (k == K_ORTHO && c->have[K_FOV]))
        return spm_lex_expected(lx, err, "'position', 'direction' or 'lookat', 'up', 'fov' or "
                                         "'orthographic', 'aperture', 'focus' (each once)");
    c->have[k] = 1;
    if (spm_lex_next(lx, err))
        return 1;
    int rc;
    if (k <= K_UP)
        rc = numbers(lx, 3, k == K_POSITION || k == K_LOOKAT ? "a coordinate" : "a vector component",
                     -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, c->v[k], err);
    else if (k == K_FOV)
        rc = numbers(lx, 1, "a field of view in degrees (1..179)", 1.0, 179.0, c->v[k], err);
    else if (k == K_APERTURE)
        rc = numbers(lx, 1, "an aperture diameter (0 or more)", 0.0, SPM_SCENE_MAX_COORD,
                     c->v[k], err);
    else
        rc = numbers(lx, 1, k == K_FOCUS ? "a focus distance above 0" : "a view width above 0",
                     1e-30, SPM_SCENE_MAX_COORD, c->v[k], err);
    if (rc || (k != K_FOV && k != K_ORTHO))
        return rc;
    if (spm_lex_is(lx, "horizontal") || spm_lex_is(lx, "vertical")) {
        c->axis = spm_lex_is(lx, "vertical") ? SPM_FOV_VERTICAL : SPM_FOV_HORIZONTAL;
        return spm_lex_next(lx, err);
    }
    return 0;
}

int spm_parse_camera(spm_lexer *lx, spm_scene_builder *b, const char *where, spm_error *err)
{
    camera_words c;
    memset(&c, 0, sizeof c);
    while (lx->type != SPM_TOK_NEWLINE && lx->type != SPM_TOK_EOF)
        if (clause(lx, &c, err))
            return 1;
    const char *need = !c.have[K_POSITION]                      ? "'position'"
                       : !c.have[K_DIRECTION] && !c.have[K_LOOKAT] ? "'direction' or 'lookat'"
                       : !c.have[K_FOV] && !c.have[K_ORTHO]        ? "'fov' or 'orthographic'"
                                                                  : NULL;
    if (need)
        return spm_lex_expected(lx, err, need);
    double *eye = c.v[K_POSITION], dir[3], dist = 0.0;
    for (int k = 0; k < 3; k++) {
        dir[k] = c.have[K_LOOKAT] ? c.v[K_LOOKAT][k] - eye[k] : c.v[K_DIRECTION][k];
        dist += dir[k] * dir[k];
    }
    dist = sqrt(dist);
    if (c.have[K_LOOKAT] && !(dist > 0.0)) {
        spm_errorf(err, "%s: the camera looks at its own position", where);
        return 1;
    }
    double aperture = c.have[K_APERTURE] ? c.v[K_APERTURE][0] : 0.0;
    if (aperture > 0.0 && !c.have[K_FOCUS] && !c.have[K_LOOKAT]) {
        spm_errorf(err, "%s: an aperture needs 'focus DISTANCE' (or 'lookat', whose distance it "
                        "then focuses at)", where);
        return 1;
    }
    if (spm_sb_camera_view(b, eye, dir, c.have[K_UP] ? c.v[K_UP] : NULL, 0,
                           c.have[K_FOV] ? c.v[K_FOV][0] : 90.0, c.axis, where, err))
        return 1;
    spm_scene *s = b->s;
    s->projection = c.have[K_ORTHO] ? SPM_PROJ_ORTHOGRAPHIC : SPM_PROJ_PERSPECTIVE;
    s->ortho_size = c.have[K_ORTHO] ? (float)c.v[K_ORTHO][0] : 0.0f;
    s->aperture = (float)aperture;
    s->focus = (float)(c.have[K_FOCUS] ? c.v[K_FOCUS][0] : dist);
    if (s->projection == SPM_PROJ_ORTHOGRAPHIC && aperture > 0.0)
        spm_warnf("%s: an orthographic camera has no lens: its aperture ignored", where);
    return 0;
}

int spm_scene_camera_override(spm_scene *s, const spm_camera_override *o, spm_error *err)
{
    const double *from = o->has_from ? o->from : NULL, *at = o->has_at ? o->at : NULL;
    double eye[3], dir[3], len = 0.0, fov = o->fov;
    for (int k = 0; k < 3; k++) {
        eye[k] = from ? from[k] : s->eye[k];
        dir[k] = at ? at[k] - eye[k] : s->dir[k];
        len += dir[k] * dir[k];
    }
    if (!(len > 0.0)) {
        spm_errorf(err, "--look-at: the point looked at is the camera's position");
        return 1;
    }
    if (fov > 0.0 && !(fov >= 1.0 && fov <= 179.0)) {
        spm_errorf(err, "--fov: %g degrees (it must be inside 1..179)", fov);
        return 1;
    }
    double up[3] = {s->up[0], s->up[1], s->up[2]};
    int has_up = up[0] != 0.0 || up[1] != 0.0 || up[2] != 0.0;
    double c[3] = {up[1] * dir[2] - up[2] * dir[1], up[2] * dir[0] - up[0] * dir[2],
                   up[0] * dir[1] - up[1] * dir[0]};
    if (has_up && !(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1e-18 * len)) {
        spm_errorf(err, "--look-at: the new direction is parallel to the camera's up vector");
        return 1;
    }
    len = sqrt(len);
    for (int k = 0; k < 3; k++) {
        s->eye[k] = (float)eye[k];
        s->dir[k] = (float)(dir[k] / len);
    }
    if (has_up) { /* up made normal to the new direction again: (dir x up) x dir */
        double u[3] = {s->dir[1] * up[2] - s->dir[2] * up[1], s->dir[2] * up[0] - s->dir[0] * up[2],
                       s->dir[0] * up[1] - s->dir[1] * up[0]};
        double v[3] = {u[1] * s->dir[2] - u[2] * s->dir[1], u[2] * s->dir[0] - u[0] * s->dir[2],
                       u[0] * s->dir[1] - u[1] * s->dir[0]};
        double lv = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int k = 0; k < 3; k++)
            s->up[k] = (float)(v[k] / lv);
    }
    if (fov > 0.0) {
        s->fov_deg = (float)fov;
        s->projection = SPM_PROJ_PERSPECTIVE;
    }
    return 0;
}
