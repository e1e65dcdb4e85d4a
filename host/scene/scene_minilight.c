/* Import of MiniLight's .ml.txt scenes (Harrison Ainsworth's format):
 *   #MiniLight
 *   iterations
 *   width height
 *   (eye) (direction) fov-degrees
 *   (sky emission) (ground reflection)
 *   (v0) (v1) (v2) (reflectivity) (emitivity)     one triangle each, until the end
 * Line breaks do not matter (MiniLight reads with scanf). RGB is linear sRGB:
 * reflectivities become fitted spectra (rgb2spec.c), emissions a reflectance
 * shape times D65 at the RGB's luminance, so a white light stays D65-white.
 * Where MiniLight silently clamps bad values, this importer reports them: an
 * imported scene should be the one its author meant. */
#include "scene_build.h"
#include "scene_parsers.h"
#include "scene_lexer.h"
#include "rgb2spec.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct {
    spm_lexer lx;
    spm_scene_builder b;
    spm_names rgb_colours;  /* exact RGB text key -> colour index (one fit per colour) */
    spm_error *err;
} ml_parser;

static int skip(ml_parser *p) { return spm_lex_skip_newlines(&p->lx, p->err); }

/* "( x y z )" with each component within [lo, hi]. */
static int vec(ml_parser *p, const char *what, double lo, double hi, double v[3])
{
    if (skip(p) || spm_lex_punct(&p->lx, SPM_TOK_LPAREN, p->err))
        return 1;
    for (int k = 0; k < 3; k++)
        if (skip(p) || spm_lex_number(&p->lx, what, lo, hi, &v[k], p->err))
            return 1;
    return skip(p) || spm_lex_punct(&p->lx, SPM_TOK_RPAREN, p->err);
}

static int is_black(const double rgb[3]) { return rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0; }

/* The colour of an RGB reflectivity or emission (spm_sb_rgb_colour).
 * Returns its index, -1 for black, -2 on error. */
static int rgb_colour(ml_parser *p, const double rgb[3], spm_kind kind, const char *where)
{
    return spm_sb_rgb_colour(&p->b, &p->rgb_colours, rgb, kind, where, p->err);
}

static int header(ml_parser *p)
{
    spm_scene *s = p->b.s;
    long iterations, w, h;
    double eye[3], dir[3], fov;
    char where[600];
    if (skip(p) || spm_lex_int(&p->lx, "the iteration count", 0, SPM_SCENE_MAX_SPP, &iterations,
                               p->err) ||
        skip(p) || spm_lex_int(&p->lx, "the image width", 1, SPM_SCENE_MAX_SIDE, &w, p->err) ||
        skip(p) || spm_lex_int(&p->lx, "the image height", 1, SPM_SCENE_MAX_SIDE, &h, p->err) ||
        skip(p))
        return 1;
    s->spp = (int)iterations; /* one MiniLight iteration = one sample per pixel */
    s->width = (int)w;
    s->height = (int)h;
    spm_lex_where(&p->lx, where, sizeof where);
    return vec(p, "a coordinate", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, eye) ||
           vec(p, "a direction component", -HUGE_VAL, HUGE_VAL, dir) || skip(p) ||
           spm_lex_number(&p->lx, "a field of view in degrees", -HUGE_VAL, HUGE_VAL, &fov,
                          p->err) ||
           spm_sb_camera(&p->b, eye, dir, fov, where, p->err);
}

/* Sky emission (seen by rays escaping upward) and ground reflection (downward
 * rays see sky x ground): bg_up = sky, bg_down = the product spectrum. */
static int background(ml_parser *p)
{
    spm_scene *s = p->b.s;
    double sky[3], ground[3];
    char where[600];
    if (skip(p))
        return 1;
    spm_lex_where(&p->lx, where, sizeof where);
    if (vec(p, "a sky emission component", 0.0, HUGE_VAL, sky) ||
        vec(p, "a ground reflection component", 0.0, 1.0, ground))
        return 1;
    if (is_black(sky))
        return 0;
    s->bg_up = rgb_colour(p, sky, SPM_KIND_EMISSION, where);
    if (s->bg_up < 0)
        return 1;
    if (is_black(ground))
        return 0;
    spm_spectrum refl, down;
    spm_error inner;
    if (spm_rgb_to_reflectance(ground, &refl, NULL, &inner)) {
        spm_errorf(p->err, "%s: %s", where, inner.msg);
        return 1;
    }
    down = s->colours[s->bg_up].s;
    spm_spectrum_multiply(&down, &refl);
    char name[SPM_NAME_MAX];
    snprintf(name, sizeof name, "ground(%.6g,%.6g,%.6g)", ground[0], ground[1], ground[2]);
    s->bg_down = spm_sb_colour(&p->b, name, &down, where, p->err);
    return s->bg_down < 0;
}

static int triangle(ml_parser *p)
{
    double v[3][3], refl[3], emit[3];
    char where[600];
    int line = p->lx.tline;
    spm_lex_where(&p->lx, where, sizeof where);
    for (int i = 0; i < 3; i++)
        if (vec(p, "a vertex coordinate", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, v[i]))
            return 1;
    if (vec(p, "a reflectivity component", 0.0, 1.0, refl) ||
        vec(p, "an emitivity component", 0.0, HUGE_VAL, emit))
        return 1;
    int r = rgb_colour(p, refl, SPM_KIND_REFLECTANCE, where);
    int e = r < -1 ? -2 : rgb_colour(p, emit, SPM_KIND_EMISSION, where);
    if (e < -1)
        return 1;
    char name[SPM_NAME_MAX];
    snprintf(name, sizeof name, "%s%.50s", e >= 0 ? "light " : "",
             r >= 0 ? p->b.s->colours[r].name : "black");
    int m = spm_sb_material(&p->b, name, r, e, where, p->err);
    return m < 0 || spm_sb_tri(&p->b, v, m, line, where, p->err);
}

int spm_scene_parse_minilight(const spm_file *file, spm_scene *out, spm_error *err)
{
    const char *path = file->shown;
    ml_parser p;
    memset(&p, 0, sizeof p);
    p.err = err;
    spm_names_init(&p.rgb_colours);
    spm_sb_init(&p.b, out, path);
    /* The "#MiniLight" line is a comment to the lexer; spm_scene_load checked it. */
    int rc = spm_lex_open(&p.lx, file, err) || header(&p) || background(&p) || skip(&p);
    while (!rc && p.lx.type != SPM_TOK_EOF)
        rc = triangle(&p) || skip(&p);
    if (!rc) {
        char where[600];
        spm_lex_where(&p.lx, where, sizeof where);
        rc = spm_sb_finish(&p.b, where, err);
    }
    spm_lex_close(&p.lx);
    spm_names_free(&p.rgb_colours);
    spm_sb_done(&p.b, !rc);
    return rc;
}
