/* The scene format's textures (scene_texture.h): the statement, a use per
 * point (moved into the scene) or as the texture's mean colour. */
#include "scene_texture.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_TEXTURES 4096
#define MAX_CHECKS 512 /* at most 512 x 512 texels: 4 MB with the pyramid */

void spm_scene_textures_init(spm_scene_textures *t)
{
    memset(t, 0, sizeof *t);
    spm_names_init(&t->names);
    spm_names_init(&t->fits);
}

void spm_scene_textures_free(spm_scene_textures *t)
{
    for (int i = 0; i < t->n; i++)
        spm_texture_free(&t->v[i].tex);
    free(t->v);
    spm_names_free(&t->names);
    spm_names_free(&t->fits);
    memset(t, 0, sizeof *t);
}

/* The image file's pyramid. */
static int file_texture(spm_lexer *lx, const char *dir, spm_scene_tex *x, spm_error *err)
{
    char where[600], why[256];
    spm_lex_where(lx, where, sizeof where);
    if (spm_lex_path(lx, "an image file name or 'checker'", x->source, sizeof x->source, err))
        return 1;
    spm_file f;
    if (spm_path_check(dir, x->source, where, &f, err))
        return 1;
    x->file = f;
    struct stat st;
    if (stat(f.path, &st) != 0 || !S_ISREG(st.st_mode)) {
        spm_errorf(err, "%s: texture image '%s' not found (or not a regular file: %s)", where,
                   x->source, f.shown);
        return 1;
    }
    float *rgb;
    int w, h;
    if (spm_texture_read_file(&f, &rgb, &w, &h, why, sizeof why)) {
        spm_errorf(err, "%s: texture image '%s' cannot be read: %s", where, x->source, why);
        return 1;
    }
    spm_texture_from_pixels(w, h, rgb, SPM_WRAP_REPEAT, SPM_WRAP_REPEAT, &x->tex);
    free(rgb);
    spm_texture_mean(&x->tex, x->mean);
    return 0;
}

/* checker COUNT R G B R G B: count^2 squares of CHECKER_TEXELS / count texels
 * (at least 1) a side, the first colour's at the top-left; the mean exactly
 * that of the squares, ceil(count^2 / 2) of the first colour. */
#define CHECKER_TEXELS 512
static int checker_texture(spm_lexer *lx, spm_scene_tex *x, spm_error *err)
{
    long count;
    double c[2][3];
    snprintf(x->source, sizeof x->source, "checker");
    if (spm_lex_next(lx, err) ||
        spm_lex_int(lx, "a number of squares along a side", 1, MAX_CHECKS, &count, err))
        return 1;
    for (int k = 0; k < 6; k++)
        if (spm_lex_number(lx, "a linear RGB component (0 or more)", 0.0, 1e30, &c[k / 3][k % 3],
                           err))
            return 1;
    double n = (double)count * count, na = ceil(n / 2);
    float a[3], b[3];
    for (int k = 0; k < 3; k++) {
        x->mean[k] = (float)((na * c[0][k] + (n - na) * c[1][k]) / n);
        a[k] = (float)c[0][k], b[k] = (float)c[1][k];
    }
    int res = CHECKER_TEXELS / (int)count;
    spm_texture_checker((int)count, res > 1 ? res : 1, a, b, SPM_WRAP_REPEAT, &x->tex);
    return 0;
}

/* every texel times s */
static void scale_texture(spm_texture *t, double s)
{
    for (int l = 0; l < t->nlevels; l++)
        for (size_t i = 0; i < (size_t)3 * t->lv[l].w * t->lv[l].h; i++)
            t->lv[l].rgb[i] = (float)(t->lv[l].rgb[i] * s);
}

static int options(spm_lexer *lx, spm_scene_tex *x, spm_error *err)
{
    int have_wrap = 0, have_scale = 0;
    while (lx->type != SPM_TOK_NEWLINE && lx->type != SPM_TOK_EOF) {
        if (!have_wrap && spm_lex_is(lx, "wrap")) {
            static const char *modes[] = {"repeat", "clamp", "mirror"};
            have_wrap = 1;
            if (spm_lex_next(lx, err))
                return 1;
            int m = 0;
            while (m < 3 && !spm_lex_is(lx, modes[m]))
                m++;
            if (m == 3)
                return spm_lex_expected(lx, err, "'repeat', 'clamp' or 'mirror'");
            x->wrap = x->tex.wrap[0] = x->tex.wrap[1] = (spm_wrap)m;
            if (spm_lex_next(lx, err))
                return 1;
        } else if (!have_scale && spm_lex_is(lx, "scale")) {
            double s;
            have_scale = 1;
            if (spm_lex_next(lx, err) || spm_lex_number(lx, "a scale (0 or more)", 0.0, 1e30, &s, err))
                return 1;
            for (int k = 0; k < 3; k++)
                x->mean[k] = (float)(x->mean[k] * s);
            x->scale = s;
            scale_texture(&x->tex, s);
        } else {
            return spm_lex_expected(lx, err, "'wrap' or 'scale' (each once) or the end of the line");
        }
    }
    return spm_lex_end_of_statement(lx, err);
}

int spm_scene_texture_statement(spm_scene_textures *t, spm_lexer *lx, const char *dir,
                                spm_error *err)
{
    spm_scene_tex x;
    memset(&x, 0, sizeof x);
    spm_lex_where(lx, x.where, sizeof x.where);
    x.scale = 1.0;
    if (spm_lex_name(lx, "a texture name", x.name, sizeof x.name, err))
        return 1;
    if (spm_names_get(&t->names, x.name) >= 0) {
        spm_errorf(err, "%s: texture '%s' is already defined", x.where, x.name);
        return 1;
    }
    if (t->n >= MAX_TEXTURES) {
        spm_errorf(err, "%s: more than %d textures", x.where, MAX_TEXTURES);
        return 1;
    }
    int rc = spm_lex_is(lx, "checker") ? checker_texture(lx, &x, err)
                                       : file_texture(lx, dir, &x, err);
    if (rc || options(lx, &x, err)) {
        spm_texture_free(&x.tex);
        return 1;
    }
    if (t->n == t->cap) {
        t->cap = t->cap ? 2 * t->cap : 8;
        t->v = spm_xrealloc(t->v, (size_t)t->cap * sizeof *t->v);
    }
    t->v[t->n] = x;
    spm_names_put(&t->names, x.name, t->n++);
    return 0;
}

/* The texture named at the lexer, marked used; NULL with err. */
static spm_scene_tex *named(spm_scene_textures *t, spm_lexer *lx, spm_error *err)
{
    char where[600], name[SPM_NAME_MAX];
    spm_lex_where(lx, where, sizeof where);
    if (spm_lex_name(lx, "a texture name", name, sizeof name, err))
        return NULL;
    int i = spm_names_get(&t->names, name);
    if (i < 0) {
        spm_errorf(err, "%s: unknown texture '%s' (define it with 'texture %s ...' first)", where,
                   name, name);
        return NULL;
    }
    t->v[i].used = 1;
    t->last = i + 1;
    return &t->v[i];
}

int spm_scene_texture_alpha(spm_scene_textures *t, spm_lexer *lx, spm_scene_builder *b,
                            spm_error *err)
{
    char where[600], why[256];
    spm_lex_where(lx, where, sizeof where);
    spm_scene_tex *x = named(t, lx, err);
    if (!x || x->alpha_index)
        return x ? x->alpha_index : -1;
    const spm_texmap *l0 = &x->tex.lv[0];
    float *a;
    int w = l0->w, h = l0->h;
    if (x->file.path[0]) {
        if (spm_texture_read_alpha_file(&x->file, 0, &a, &w, &h, why, sizeof why)) {
            spm_errorf(err, "%s: texture image '%s' cannot be read as opacity: %s", where,
                       x->source, why);
            return -1;
        }
        for (size_t i = 0; i < (size_t)w * h; i++)
            a[i] = (float)(a[i] * x->scale);
    } else { /* a checkerboard: its first component, scaled already */
        a = spm_xmalloc((size_t)w * h * sizeof *a);
        for (size_t i = 0; i < (size_t)w * h; i++)
            a[i] = l0->rgb[3 * i];
    }
    x->alpha_index = 1 + spm_sb_alpha_pixels(b, a, w, h, (int)x->tex.wrap[0], (int)x->tex.wrap[1]);
    free(a);
    return x->alpha_index;
}

int spm_scene_texture_nmap(spm_scene_textures *t, spm_lexer *lx, spm_scene_builder *b,
                           spm_error *err)
{
    char where[600], why[256];
    spm_lex_where(lx, where, sizeof where);
    spm_scene_tex *x = named(t, lx, err);
    if (!x || x->nmap_index)
        return x ? x->nmap_index : -1;
    const spm_texmap *l0 = &x->tex.lv[0];
    float *rgb = l0->rgb;
    int w = l0->w, h = l0->h;
    if (x->file.path[0] && spm_texture_read_data_file(&x->file, &rgb, &w, &h, why, sizeof why)) {
        spm_errorf(err, "%s: texture image '%s' cannot be read as a normal map: %s", where,
                   x->source, why);
        return -1;
    }
    x->nmap_index = 1 + spm_sb_nmap_pixels(b, rgb, w, h, (int)x->tex.wrap[0], (int)x->tex.wrap[1]);
    if (rgb != l0->rgb)
        free(rgb);
    return x->nmap_index;
}

int spm_scene_texture_colour(spm_scene_textures *t, spm_lexer *lx, spm_scene_builder *b,
                             spm_kind kind, double *scale, spm_error *err)
{
    char where[600];
    spm_lex_where(lx, where, sizeof where);
    spm_scene_tex *x = named(t, lx, err);
    if (!x)
        return -1;
    *scale = 1.0;
    if (kind == SPM_KIND_EMISSION && spm_lex_is_number(lx) &&
        spm_lex_number(lx, "an emission scale (a luminance) above 0", 1e-30, HUGE_VAL, scale, err))
        return -1;
    double rgb[3] = {x->mean[0] * *scale, x->mean[1] * *scale, x->mean[2] * *scale};
    int c = spm_sb_rgb_colour(b, &t->fits, rgb, kind, where, err);
    if (c == -1) { /* black */
        spm_spectrum zero;
        spm_spectrum_constant(0.0, kind, &zero);
        c = spm_sb_colour(b, "black", &zero, where, err);
    }
    return c < 0 ? -1 : c;
}

void spm_scene_texture_as_mean(spm_scene_textures *t, int i, spm_kind kind, const char *where,
                               const char *why)
{
    spm_scene_tex *x = &t->v[i];
    if (x->warned[kind])
        return;
    x->warned[kind] = 1;
    spm_warnf("%s: texture '%s' (%s) is applied as its mean colour (%.3g %.3g %.3g, linear): %s",
              where, x->name, x->source, x->mean[0], x->mean[1], x->mean[2], why);
}

int spm_scene_texture_adopt(spm_scene_textures *t, int i, spm_scene_builder *b)
{
    spm_scene_tex *x = &t->v[i];
    if (!x->scene_index)
        x->scene_index = 1 + spm_sb_texture(b, &x->tex);
    return x->scene_index;
}

void spm_scene_textures_unused(const spm_scene_textures *t)
{
    for (int i = 0; i < t->n; i++)
        if (!t->v[i].used)
            spm_warnf("%s: texture '%s' is never used", t->v[i].where, t->v[i].name);
}
