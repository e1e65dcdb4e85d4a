/* Scene geometry flattened for the device: triangles, BVH, emitter list, camera. */
#ifndef SPM_GEOMETRY_H
#define SPM_GEOMETRY_H
#include "scene.h"
#include "spm_shared.h"

/* What the BVH build made (render --stats / --json "bvh"). sah_cost is
 * sum over interior nodes of A(node)/A(root) plus sum over leaves of
 * A(leaf)/A(root) * triangles, on the unpadded boxes: the expected number of
 * box and triangle tests of a ray through the root box (both costed 1). */
typedef struct {
    int leaves;
    double sah_cost;
    int threads; /* threads the build ran on */
} spm_bvh_stats;

typedef struct {
    spm_tri *tris;          /* reordered by the BVH build */
    int ntris;
    spm_bvh_node *nodes;
    int nnodes;
    spm_bvh4_node *wide;    /* the kernels' tree, collapsed from nodes (bvh_wide.c) */
    int nwide;
    spm_emitter *emitters;  /* triangles with emission and area > 0, and their pick table */
    int nemitters;
    int emit_power;         /* 1: picked by power (spm_emitter); 0: uniformly (equal powers) */
    float *light_pdf;       /* per triangle: its probability of being picked by power as the
                               light (0: none); then, with --light-sampler tree, the light
                               tree's ntree words (include/spm_light_tree.h) */
    int ntree;              /* 0: no light tree */
    double *light_w;        /* each emitter's power, the selection's weight (host only) */
    float *vnormals;        /* nine floats per smooth triangle (spm_tri.vn), NULL when none */
    int nvn;                /* smooth triangles: 0 in a scene without vertex normals */
    float *disp;            /* the dispersive glasses' index tables (scene.h disp), NULL when none */
    int ndisp;              /* their count: 0 in a scene without dispersive glass */
    float *uvs;             /* textured scenes: 6 floats per triangle (spm_shared.h), else NULL */
    spm_u32 *tex;           /* the textures' words (spm_shared.h SPM_TEXD_*), NULL when none */
    size_t ntex;            /* their count: 0 in a scene without textures */
    float *env;             /* the environment map's texels and distribution (spm_shared.h
                               SPM_ENV_*), NULL when none; its light is the last emitter */
    size_t nenv;            /* its floats */
    spm_camera cam;
    spm_bvh_stats bvh;
} spm_geometry;

/* Builds triangles (MiniLight's edges/normal/tangent/area), a binned-SAH BVH
 * and the emitter list with its pick table (spm_emitter_table_build). Zero-area triangles are an input error naming the line. */
int spm_geometry_build(const spm_scene *scene, spm_geometry *g, spm_error *err);
/* The same, freeing the scene's triangles (scene->tris NULL, ntris 0) once
 * they are converted, before the BVH build: a render needs them no more, and
 * a million of them are 44 MB. `beside`, if not NULL, runs on a thread of its
 * own while they are converted and is done before they are freed: it may
 * only read the scene (the camera-inside hint, which then takes the core
 * the conversion leaves idle). */
int spm_geometry_build_consume(spm_scene *scene, void (*beside)(const spm_scene *),
                               spm_geometry *g, spm_error *err);
void spm_geometry_free(spm_geometry *g);
/* The pick table (spm_shared.h spm_emitter) of emitters em[0, n) whose tri
 * fields are set, for their powers w[0, n) (each > 0); fills cdf, pdf and
 * inv_pdf and returns 1 when picking by power, 0 when the powers are equal
 * (or too many emitters for the 24-bit table) and the pick is uniform. */
/* The textures' words and the triangles' texture coordinates, in the
 * scene's triangle order (geometry_texture.c); nothing in a scene without a
 * textured material. The BVH build puts the coordinates into its order. */
void spm_geometry_textures(const spm_scene *scene, spm_geometry *g);
void spm_geometry_uvs_permute(spm_geometry *g, const int *perm);
/* The materials' opacity in the texture words (geometry_alpha.c, spm_shared.h
 * SPM_ALPHA_*): the words it takes, and putting them from word w on (the
 * words' end); SPM_TEXD_ALPHA stays 0 when no material has one. */
size_t spm_geometry_alpha_words(const spm_scene *s);
size_t spm_geometry_alpha_put(const spm_scene *s, spm_u32 *x, size_t w);
/* The texture coordinates at point p of triangle tr (uv: u, v at its three
 * vertices) from p's barycentrics (the projections onto its edges), and a
 * coordinate wrapped into one period of a wrap mode (texture.h spm_wrap;
 * clamp: within [-1, 2]; NaN 0): the texture lookups' and the opacity
 * test's, as kernels/texture.clh and alpha.clh compute them. */
void spm_tri_uv(const spm_tri *tr, const float uv[6], const float p[3], float *u, float *v);
float spm_tex_wrap_coord(float u, spm_u32 mode);
/* A map's texture coordinate transform in the texture words (spm_shared.h
 * SPM_TEX_UVX; geometry_texture.c): the words it takes (0 for none), put
 * from word w on with its offset from the head's word `head` in
 * x[head + slot] (the word after), and (u, v) through the transform of the
 * head h at h + off (0: unchanged), as kernels/texture.clh
 * tex_uvx computes it; the footprint's factor sqrt |m0 m4 - m1 m3| (1 for
 * none). */
size_t spm_geometry_uvx_words(const spm_uvx *t);
size_t spm_geometry_uvx_put(const spm_uvx *t, spm_u32 *x, size_t head, size_t slot, size_t w);
void spm_tex_uvx(const spm_u32 *h, spm_u32 off, float *u, float *v);
float spm_tex_uvx_scale(const spm_u32 *h, spm_u32 off);
/* A normal map's tangent t and bitangent b turned to the transformed
 * coordinates (along +u' and +v', each t's length), as kernels/uvx.clh
 * tex_uvx_frame computes them; unchanged for no transform. */
void spm_tex_uvx_frame(const spm_u32 *h, spm_u32 off, float t[3], float b[3]);
/* Normal maps in the texture words (geometry_nmap.c, spm_shared.h
 * SPM_NMAP_*): whether a material of s has one (its kernels: SPM_WITH_NMAP),
 * the words they take with every triangle's tangents, putting them from word
 * w on (the words' end), and the tangents put into the BVH's triangle order. */
int spm_geometry_has_nmap(const spm_scene *s);
size_t spm_geometry_nmap_words(const spm_scene *s);
size_t spm_geometry_nmap_put(const spm_scene *s, spm_u32 *x, size_t w);
void spm_geometry_tangents_permute(spm_geometry *g, const int *perm);
/* A triangle's corners for the tangents: position, normal (any length: the
 * face's on a flat triangle) and (u, v). */
typedef struct {
    float p[3][3], n[3][3], uv[3][2];
} spm_tangent_in;
/* Per vertex of each of the n triangles a unit tangent and its handedness
 * (x, y, z, +-1), made as MikkTSpace makes them: each face's dP/du (from its
 * (u, v) derivatives) made perpendicular to a corner's normal, weighed by the
 * corner's angle and summed over the corners that share position, normal,
 * (u, v) and handedness (the sign of (N x T) . dP/dv), then made
 * perpendicular to the normal again (Gram-Schmidt); where nothing is left (no
 * (u, v) variation), any tangent perpendicular to the normal. */
void spm_tangents_make(const spm_tangent_in *in, int n, float (*out)[12]);
/* 1 when a material of g has an opacity record (its kernels: SPM_WITH_ALPHA). */
int spm_geometry_has_alpha(const spm_geometry *g);
/* Whether a hit at distance t on triangle tri along the ray (o, d) counts:
 * 1 where the surface is there (always for a material without opacity). */
int spm_alpha_there(const spm_geometry *g, spm_u32 tri, const float o[3], const float d[3],
                    float t);
/* A one-byte map's bilinear value at (u, v) in [0, 1] (spm_shared.h
 * SPM_ALPHA_MAP_HEAD: the opacity's and the metallic-roughness maps). */
float spm_byte_map_bilinear(const spm_u32 *m, float u, float v);
/* The metallic-roughness mix at point p of triangle tri (spm_shared.h
 * SPM_MIX_*): the metal's material index, the metallic value and the width
 * alpha there; -1 when tri's material has no mix. */
int spm_mix_values(const spm_geometry *g, spm_u32 tri, const float p[3], float *metallic,
                   float *alpha);
int spm_emitter_table_build(spm_emitter *em, const double *w, int n);
spm_camera spm_camera_make(const float eye[3], const float dir[3], float fov_deg, int w, int h);
/* The camera of scene s: spm_camera_make, or the frame its up vector, mirror
 * flag and field-of-view axis give (scene.h). */
spm_camera spm_camera_of_scene(const spm_scene *s);

/* Closest hit along origin + t dir, t > 0, ignoring triangle `skip` (or
 * SPM_NONE-like 0xFFFFFFFF). Returns the triangle index or -1; *t_out set.
 * A ray with a `skip` leaves that triangle: it starts at spm_ray_spawn's
 * point, and t is measured from there. */
int spm_bvh_intersect(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                      float *t_out);
/* The same by testing every triangle (for tests). */
int spm_brute_intersect(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                        float *t_out);
/* The start of a ray leaving triangle `from` at o along d (bvh.c): o rebuilt
 * on the triangle a margin inside its edges and moved off its plane on d's
 * side, by SPM_SPAWN_ULPS of the triangle's coordinates; o itself when
 * `from` is no triangle. */
void spm_ray_spawn(const spm_geometry *g, spm_u32 from, const float o[3], const float d[3],
                   float out[3]);

/* Both intersectors use the watertight test (spm_tri_intersect) and break an
 * exact tie in t by the lower triangle index, so the answer does not depend on
 * the traversal order. nnodes == 0 when there are no triangles. The BVH is at
 * most SPM_BVH_STACK levels deep (spm_shared.h); node boxes are padded so a
 * float slab test is conservative. */
/* Builds g->nodes from g->tris (binned SAH, leaves of at most 2 triangles:
 * bvh_build.c LEAF_MAX) and reorders g->tris into leaf order; each box is
 * padded relative to its own magnitude and g->cam.eye's (bvh_build.c). Called
 * by spm_geometry_build. */
int spm_bvh_build(spm_geometry *g, spm_error *err);
/* The same on nthreads threads (1: the calling thread alone; small scenes
 * always build on one). The tree does not depend on nthreads or on the
 * threads' timing. spm_bvh_build uses spm_bvh_default_threads(): the online
 * cores, at most 16. */
int spm_bvh_build_threads(spm_geometry *g, int nthreads, spm_error *err);
int spm_bvh_default_threads(void);
/* Builds g->wide from g->nodes (4-wide, the same leaves and boxes; called by
 * spm_bvh_build_threads). nwide == 0 when nnodes == 0. */
int spm_bvh_wide_build(spm_geometry *g, spm_error *err);
/* The SAH cost (spm_bvh_stats) of nodes[0, nnodes) and their leaf count. */
double spm_bvh_sah_cost(const spm_bvh_node *nodes, int nnodes, int *leaves);
/* Nodes whose box spm_bvh_intersect tested, counted per thread: a cost
 * measure for tests and benchmarks that the traversal only adds to. */
extern _Thread_local unsigned long long spm_bvh_nodes_tested;
/* The watertight ray-triangle test (bvh.c) on a ray's frame, made once per
 * ray: the axis of d's largest component and the shear that takes d onto it. */
typedef struct {
    float o[3], d[3]; /* the ray as given (the opacity test's hash and hit point) */
    int kx, ky, kz;
    float sx, sy, sz;
} spm_ray_frame;
void spm_ray_frame_make(const float o[3], const float d[3], spm_ray_frame *f);
/* Hit distance t > 0 along d, or -1 for a miss; either face. */
float spm_tri_intersect_frame(const spm_tri *t, const spm_ray_frame *f);
float spm_tri_intersect(const spm_tri *t, const float o[3], const float d[3]);
#endif
