/* Environment maps: `background map FILE [scale S] [rotate DEG]`, an
 * equirectangular HDR image (EXR, Radiance HDR, anything OpenImageIO reads:
 * texture.h) around the scene, a light of its own kind (include/spm_lights.h
 * ENVMAP; kernels/light_envmap.clh says which direction a texel is).
 *
 * Its spectra (docs/METHODS.md "Environment maps"): each texel's RGB is
 * split into a luminance Y (of linear sRGB, the map's scale in) and a shape
 * rgb / max(rgb), and the shape is placed on a palette grid: the face of
 * the RGB cube the largest component names, the other two components of the
 * shape in SPM_ENVMAP_GRID steps each, nodes at the steps' ends. Each node
 * some texel may draw becomes one scene colour, its shape lifted by the sRGB
 * table (rgb2spec_table.h) times D65 as an RGB emission is
 * (spm_rgb2spec_texel, SPM_TEXEL_EMISSION) and normalised to Y = 1. A texel
 * keeps its cell's base node and its fractions in the cell (16 bits each)
 * and renders as one of the cell's four corners, drawn with the bilinear
 * weights times each node's luminance, times its own Y: the expected colour
 * is the texel's own (kernels/light_envmap.clh env_node), as a texture's
 * lookup draws a node of its grid (kernels/texture.clh tex_grid_pick). The
 * map is interpolated bilinearly by drawing one of the four texels around a
 * direction (env_tap), so a path still meets one colour. The palette's
 * colours are ordinary emissions: the pretest gives each its level, as
 * textures' rule T judges a texture's colours on a grid. */
#ifndef SPM_ENVMAP_H
#define SPM_ENVMAP_H
#include <stddef.h>
#include "scene.h"
#include "scene_lexer.h"

/* steps of the palette grid per component: at most 3 x 17^2 node colours
 * (docs/METHODS.md: the colours it takes) */
#define SPM_ENVMAP_GRID 16

/* The statement after 'background': lx on 'map'. Reads FILE (relative to
 * dir, through the path rule), the options, and sets s->env. */
int spm_envmap_statement(spm_scene *s, spm_lexer *lx, const char *dir, spm_error *err);
/* A map from a checked file (an importer's): scale, rotate in degrees. */
int spm_envmap_load(spm_scene *s, const spm_file *f, double scale, double rotate,
                    const char *where, spm_error *err);
/* A map of w x h linear RGB texels (copied; rows top to bottom). */
void spm_envmap_from_pixels(spm_scene *s, int w, int h, const float *rgb, double scale,
                            double rotate, const char *where);
/* The palette: appends its nodes' colours to s's (after the scene's own,
 * once they are pruned) and sets each texel's node, fractions and luminance. */
int spm_envmap_palette(spm_scene *s, spm_error *err);
/* the same on a grid of q steps (bench/envmap_palette.c) */
int spm_envmap_palette_grid(spm_scene *s, int q, spm_error *err);
/* The trace stage's buffer (spm_shared.h SPM_ENV_*) of a map whose palette
 * is made: *n floats (malloc'd), the distribution over the texels' means
 * of the interpolated luminance x sin(theta); *mean its mean over (u, v),
 * the distribution's integral (0: a black map). */
float *spm_envmap_tables(const spm_scene_envmap *e, size_t *n, double *mean);
void spm_envmap_free(spm_scene_envmap *e);
#endif
