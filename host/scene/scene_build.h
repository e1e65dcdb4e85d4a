/* Building an spm_scene: what both parsers (the project's format and the
 * MiniLight importer) share, so the checks and the limits are written once.
 * `where` arguments are "file:line:col" prefixes for error messages. */
#ifndef SPM_SCENE_BUILD_H
#define SPM_SCENE_BUILD_H
#include "scene.h"
#include "scene_names.h"

/* image width and height, and samples per pixel: in a scene and on the command line */
#define SPM_SCENE_MAX_SIDE 16384
#define SPM_SCENE_MAX_SPP (1 << 20)
#define SPM_SCENE_MAX_TRIS (1 << 24)    /* MiniLight's limit */
#define SPM_SCENE_MAX_COLOURS 4096      /* ids are 16-bit on the device; pretests cost per colour */
#define SPM_SCENE_MAX_MATERIALS 4096
/* |coordinate| of vertices and the eye: the one absolute bound on geometry,
 * float's range. The watertight test (host/geometry/bvh.c, kernels/traverse.clh)
 * runs in float. With every coordinate within C, vertices relative to a ray's
 * origin are within 2C, sheared (|sx|, |sy| <= 1) within 4C, so each edge
 * function is within 32 C^2; for a hit they share a sign and det = U + V + W
 * is twice the sheared triangle's area, within 64 C^2 (its vertices lie in a
 * square of side 8C); z scaled by |sz| <= sqrt(3) is within 3.5 C, so t's
 * numerator is within 222 C^3: the one product cubic in C. It overflows float
 * (FLT_MAX = 3.4e38) beyond C = 1.15e12; squared distances (12 C^2) and areas
 * (6 C^2) only beyond 5e18. 1e12 keeps that numerator below 0.65 FLT_MAX and
 * takes MiniLight's suns, 1.5e11 away. Nothing else depends on the unit: the
 * smallest triangles (spm_sb_degenerate, area 1e-24) are float's other end. */
#define SPM_SCENE_MAX_COORD 1e12
#define SPM_FOV_MIN 10.0                /* MiniLight's clamp of the view angle */
#define SPM_FOV_MAX 160.0

typedef struct {
    spm_scene *s;
    int cap_colours, cap_materials, cap_tris, cap_vnormals, cap_uvs, cap_textures, cap_alphas;
    int cap_nmaps, cap_tangents;
    int pruned;                /* spm_sb_prune has run */
    spm_names colour_index;    /* colour content key -> index (sharing) */
    spm_names material_index;  /* "refl emit" -> index (sharing) */
} spm_scene_builder;

/* Starts an empty scene (no camera, no background) for file `path`. */
void spm_sb_init(spm_scene_builder *b, spm_scene *s, const char *path);
/* Frees the builder's tables; on failure (ok == 0) the scene too. */
void spm_sb_done(spm_scene_builder *b, int ok);

/* A colour with this spectrum, shared with an identical earlier one (the first
 * one's name is kept). Returns its index or -1 with err filled. */
int spm_sb_colour(spm_scene_builder *b, const char *name, const spm_spectrum *sp,
                  const char *where, spm_error *err);
/* The colour of an RGB reflectance or emission (linear sRGB), lifted to a
 * spectrum by the Jakob–Hanika fit once per distinct value: fits[] maps the
 * exact value to the colour it gave. Index, -1 for black, -2 with err filled. */
int spm_sb_rgb_colour(spm_scene_builder *b, spm_names *fits, const double rgb[3], spm_kind kind,
                      const char *where, spm_error *err);
/* A material, shared with one of the same colours. Index or -1. */
int spm_sb_material(spm_scene_builder *b, const char *name, int refl, int emit,
                    const char *where, spm_error *err);
/* A material of any type (materials.h), shared with an identical one. */
int spm_sb_material_typed(spm_scene_builder *b, const spm_scene_material *proto,
                          const char *where, spm_error *err);
/* The last triangle's texture coordinates (u, v at its three vertices): 0,
 * or 1 when it has them already or there is none. */
int spm_sb_tri_uv(spm_scene_builder *b, const float uv[6]);
/* A texture into the scene (moved: *t is left empty); its index. */
struct spm_texture_s;
int spm_sb_texture(spm_scene_builder *b, struct spm_texture_s *t);
/* An opacity map of w x h values (rows top to bottom; clamped to [0, 1],
 * stored as bytes, scene.h spm_alpha_map) into the scene: its index. */
int spm_sb_alpha_pixels(spm_scene_builder *b, const float *a, int w, int h, int wrap_u,
                        int wrap_v);
/* A normal map of w x h linear RGB texels c (rows top to bottom) into the
 * scene, as m = 2 c - 1 (scene.h spm_normal_map): its index. */
int spm_sb_nmap_pixels(spm_scene_builder *b, const float *rgb, int w, int h, int wrap_u,
                       int wrap_v);
/* The last triangle's tangents from its file (scene.h tangents): 0, or 1 when
 * it has them already or there is none. */
int spm_sb_tri_tangents(spm_scene_builder *b, const float t[12]);
/* Drops what no triangle uses (spm_sb_finish does it first unless it ran):
 * a parser that adds colours for what is left calls it, adds them, then
 * spm_sb_finish. 0, or 1 with err (no triangles). */
int spm_sb_prune(spm_scene_builder *b, const char *where, spm_error *err);
/* The colour grid of the scene's textures (scene.h palette; texture_palette.c),
 * called by a parser between spm_sb_prune and spm_sb_finish:
 * each grid node some texel's lift can pick, a colour; a textured material's
 * reflectance colour the palette's of the largest mean (Russian roulette's
 * survival: any bound works, the weight is its inverse). 0, or 1 with err. */
int spm_sb_texture_palette(spm_scene_builder *b, const char *where, spm_error *err);
/* Appends a triangle; zero-area or degenerate (collinear) triangles, huge
 * coordinates and too many triangles are errors. */
int spm_sb_tri(spm_scene_builder *b, const double p[3][3], int material, int line,
               const char *where, spm_error *err);
/* Makes the last triangle appended smooth: its unit vertex normals n0, n1,
 * n2 (nine floats, its vertices' order, oriented to its front face's side;
 * the mesh statement checks them). Returns 1 when there is no triangle or it
 * has normals already. */
int spm_sb_tri_normals(spm_scene_builder *b, const float n[9]);
/* Whether a triangle (float vertices, as the renderer sees them) is
 * degenerate: zero area, or so thin that it has no usable normal. */
int spm_sb_degenerate(const float p[3][3]);
/* Camera: direction must not be zero (stored normalised); the field of view
 * is clamped to MiniLight's 10..160 degrees with a warning. */
int spm_sb_camera(spm_scene_builder *b, const double eye[3], const double dir[3], double fov,
                  const char *where, spm_error *err);
/* A dispersive index (dispersion.h): n at each 1 nm bin's centre appended
 * to the scene's index table, m's p[SPM_DIEL_P_DISP] = 1 + its row. */
void spm_sb_index_table(spm_scene_builder *b, const double n[SPM_TRUTH_BINS],
                        spm_scene_material *m);
/* A camera without MiniLight's clamp: fov (0..180 degrees) across the axis
 * `axis` names (scene.h SPM_FOV_*); an up vector (NULL: MiniLight's rule)
 * made normal to dir, the mirror flag (scene.h) kept. */
int spm_sb_camera_view(spm_scene_builder *b, const double eye[3], const double dir[3],
                       const double up[3], int mirror, double fov, int axis, const char *where,
                       spm_error *err);

/* An optical constant (a conductor's eta or k): shape times scale, any
 * non-negative value (the loader refuses negative ones), extended as a
 * reflectance by its end values. 0. */
int spm_sb_optical(const spm_spectrum *shape, double scale, spm_spectrum *out);
/* Reflectance `shape` times `scale`; more than 1 anywhere is an error. */
int spm_sb_reflectance(const spm_spectrum *shape, double scale, const char *where,
                       spm_spectrum *out, spm_error *err);
/* Emission `shape` normalised to luminance 1, times `luminance` (docs/METHODS.md). */
int spm_sb_emission(const spm_spectrum *shape, double luminance, const char *where,
                    spm_spectrum *out, spm_error *err);

/* Final checks at the end of the file (`where`): triangles exist, something
 * emits (a triangle's material or the background); unused materials and
 * colours are dropped. */
int spm_sb_finish(spm_scene_builder *b, const char *where, spm_error *err);
#endif
