/* The scene format's textures: 'texture NAME FILE [wrap MODE] [scale S]' and
 * 'texture NAME checker COUNT R G B R G B [wrap MODE] [scale S]' define a
 * texture (an image file, by the path rule, or a procedural checkerboard of
 * linear RGB squares); 'texture NAME' in place of a spectrum name uses it
 * (docs/SCENE_FORMAT.md). A reflectance of a type whose descriptor says
 * `textured` (Lambertian, coated) is textured per point (the texture moves
 * into the scene: scene.h textures); any other use is the
 * texture's mean colour, lifted as any RGB colour is, with a warning that
 * says so. */
#ifndef SPM_SCENE_TEXTURE_H
#define SPM_SCENE_TEXTURE_H
#include "scene.h"
#include "scene_build.h"
#include "scene_lexer.h"
#include "scene_names.h"
#include "texture.h"

typedef struct {
    char name[SPM_NAME_MAX];
    char where[600];  /* the definition */
    char source[300]; /* the file as written, or "checker" */
    spm_wrap wrap;
    float mean[3];    /* linear RGB, times the scale */
    int used, warned[2];
    spm_texture tex;  /* the pyramid, until a use moves it into the scene */
    int scene_index;  /* 1 + its index in the scene once moved, 0 before */
    spm_file file;    /* the image file, checked ("" for a checkerboard) */
    double scale;     /* its 'scale' (1 without) */
    int alpha_index;  /* 1 + its opacity map in the scene once made, 0 before */
    int nmap_index;   /* 1 + its normal map in the scene once made, 0 before */
} spm_scene_tex;

typedef struct {
    spm_scene_tex *v;
    int n, cap;
    spm_names names; /* texture name -> index */
    spm_names fits;  /* mean colours lifted, by value */
    int last;        /* 1 + the texture the last use named (0: none) */
} spm_scene_textures;

void spm_scene_textures_init(spm_scene_textures *t);
void spm_scene_textures_free(spm_scene_textures *t);
/* The statement after its keyword, up to its end; dir is the scene file's
 * folder. 0, or 1 with err naming where. */
int spm_scene_texture_statement(spm_scene_textures *t, spm_lexer *lx, const char *dir,
                                spm_error *err);
/* After the word 'texture' in a colour's place: the name (an emission: and
 * an optional SCALE, into *scale, else 1), and the colour of `kind` its mean
 * (times the scale) gives (an index of the builder), with t->last set to 1 +
 * the texture. -1 with err on error. */
int spm_scene_texture_colour(spm_scene_textures *t, spm_lexer *lx, spm_scene_builder *b,
                             spm_kind kind, double *scale, spm_error *err);
/* Texture i applied as its mean colour (a use that is not textured per
 * point): warned once per kind, naming where. */
void spm_scene_texture_as_mean(spm_scene_textures *t, int i, spm_kind kind, const char *where,
                               const char *why);
/* Texture i on a reflectance per point: 1 + its index in the scene (moved
 * there at the first use). */
int spm_scene_texture_adopt(spm_scene_textures *t, int i, spm_scene_builder *b);
/* After the word 'texture' in a normal clause: the name, and 1 + the
 * scene's normal map made from it (once per texture): an image file's RGB as
 * stored, not decoded (a normal map is data), or a checkerboard's colours.
 * -1 with err. */
int spm_scene_texture_nmap(spm_scene_textures *t, spm_lexer *lx, spm_scene_builder *b,
                           spm_error *err);
/* After the word 'texture' in an opacity clause: the name, and 1 + the
 * scene's opacity map made from it (once per texture): an image file's
 * alpha channel (its first channel without one) as stored, not decoded;
 * a checkerboard's first component; times the texture's scale. -1 with err. */
int spm_scene_texture_alpha(spm_scene_textures *t, spm_lexer *lx, spm_scene_builder *b,
                            spm_error *err);
/* Warns about each texture never used. */
void spm_scene_textures_unused(const spm_scene_textures *t);
#endif
