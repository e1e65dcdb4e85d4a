/* A scene as parsed: camera, colours (concrete spectra, scales applied),
 * materials referring to colours, triangles, background. */
#ifndef SPM_SCENE_H
#define SPM_SCENE_H
#include "spectrum.h"
#include "texture.h"

#define SPM_NAME_MAX 64

/* A concrete spectrum the renderer uses. Reflectances have their scale applied
 * (and stay <= 1); emissions are normalised to luminance Y = 1 and then
 * multiplied by their scale (docs/METHODS.md), so a scale is a luminance. */
typedef struct {
    char name[SPM_NAME_MAX];
    spm_spectrum s;
} spm_colour;

/* A material: its type (host/scene/materials.h: a material and an emitter
 * descriptor) and what its clauses gave, by the descriptors' slots. */
typedef struct {
    char name[SPM_NAME_MAX];
    int refl;  /* colour index, -1 = black */
    int emit;  /* colour index, -1 = not an emitter */
    int type;  /* material tag (spm_shared.h SPM_MAT_*) */
    int etype; /* emitter tag (SPM_EMIT_*) */
    int col2;  /* a type's second colour, -1 = none */
    int col3;  /* a type's third colour, -1 = none */
    int diag;  /* a colour the type derives at the end of the scene (materials.h derive), -1 = none */
    double p[SPM_MAT_PARAMS]; /* a type's numbers */
    double ep[SPM_EMIT_PARAMS]; /* its emitter type's numbers */
    unsigned flags; /* a type's words without a value (materials.h SPM_MP_FLAG): bit `slot` */
    int tex;        /* 1 + the scene texture on its reflectance (Lambertian, coated), 0 none */
    int tpal;       /* the palette its texels pick from (scene.h palette): 0 the lifted
                       grid, k > 0 one its type derived (materials.h derive) */
    int etex;       /* 1 + the scene texture on its emission, 0 none (emit then the
                       texture's mean, for the lights' selection by power) */
    int etpal;      /* the palette of emission spectra its emission texels pick from */
    float escale;   /* the factor a textured emission's radiance takes */
    /* opacity (spm_shared.h SPM_ALPHA_*): mode 0 opaque, SPM_ALPHA_MASK or
     * SPM_ALPHA_BLEND; alpha = factor x the map's value (1 + its index in
     * the scene's alpha maps, 0: the factor alone) */
    int alpha_mode;
    float alpha_cutoff, alpha_factor;
    int alpha_map;
    /* glTF metallic-roughness (spm_shared.h SPM_MIX_*): 1 + the metal's
     * material index (0: no mix), the metallic and roughness factors, and
     * their maps (1 + an index in the scene's one-byte maps, `alphas`; 0 none) */
    int mix_metal;
    float mix_metallic, mix_rough;
    int mix_mmap, mix_rmap;
    /* a normal map (spm_shared.h SPM_NMAP_*): 1 + its index in the scene's
     * normal maps, 0 none; its scale on the tangent-space x and y */
    int nmap;
    float nmap_scale;
} spm_scene_material;

/* An opacity map: one byte a texel (alpha x 255 rounded), rows top to
 * bottom, and its wrap modes along u and v (texture.h spm_wrap). */
typedef struct {
    int w, h;
    int wrap[2];
    unsigned char *a;
    spm_uvx uvx; /* its texture coordinates' transform */
} spm_alpha_map;

/* A normal map: one word a texel (spm_shared.h SPM_NMAP_*: the tangent-space
 * normal's components in 10 bits each), rows top to bottom, its wrap modes. */
typedef struct {
    int w, h;
    int wrap[2];
    unsigned *q;
    spm_uvx uvx; /* its texture coordinates' transform */
} spm_normal_map;

typedef struct {
    float p[3][3];
    int material;
    int line;  /* source line, for messages */
    int vn;    /* 0: flat; k > 0: smooth, its vertex normals are vnormals[k - 1] */
    int uv;    /* 0: none; k > 0: its texture coordinates are uvs[k - 1] */
    int tg;    /* 0: none (made where a normal map needs them); k > 0: the file's
                  tangents, tangents[k - 1] */
} spm_scene_tri;

/* The triangles a mesh statement added, tris[first, first + n), and their
 * bounding box: what the set-up's hints (scene_hints.h) say of a mesh. */
typedef struct {
    char name[SPM_NAME_MAX];   /* the mesh file's name, without its folder */
    char where[128];           /* the statement, "file:line:col" */
    int first, n;
    float lo[3], hi[3];
} spm_scene_mesh;

/* A light of a `light` statement (host/scene/lights.h): its kind
 * (SPM_LIGHT_*), its emission's colour, its parameters (spm_shared.h
 * SPM_LIGHT_P_*) and the statement, "file:line:col". */
typedef struct {
    int kind;
    int colour;
    float p[SPM_LIGHT_PARAMS];
    char where[128];
} spm_scene_light;

/* An environment map (`background map`, host/scene/envmap.h): an
 * equirectangular image around the scene, its texels colours of a palette
 * (scene colours [first, first + ncolours), emissions of luminance 1) and a
 * luminance each. */
typedef struct {
    int w, h;            /* texels, rows top (+y) to bottom */
    float *rgb;          /* linear RGB as read, 3 a texel (freed once the palette is made) */
    double scale;        /* the factor of its radiance */
    double rotate;       /* degrees about +y */
    int first, ncolours; /* its palette */
    int *colour;         /* per texel of a sky: its palette colour (a scene colour), -1 black */
    int *node;           /* per texel of an image: its cell's base node on the grid, -1 black */
    unsigned *frac;      /* per texel of an image: its fractions a | b << 16 (1 = 65535) */
    int nnodes, stride;  /* an image's grid of nodes (envmap.h), the stride along a */
    int *node_colour;    /* per node: its scene colour, -1 unused */
    float *node_y;       /* per node: the luminance of its RGB shape */
    float *lum;          /* per texel: its luminance Y, the scale in */
    double duv_max, duv_mean; /* the palette's chromaticity error (envmap.h) */
    struct spm_sky_s *sky; /* a daylight sky's model (sky.h): its palette is of
                              daylight spectra, not of rgb; NULL: an image */
    char where[128];     /* the statement, "file:line:col" */
} spm_scene_envmap;

typedef struct {
    char path[512];      /* file it came from ("<default>" for the built-in scene) */
    float eye[3], dir[3];
    float fov_deg;       /* full field of view, across the axis fov_axis names */
    int fov_axis;        /* SPM_FOV_HORIZONTAL (MiniLight, specmip's default),
                            SPM_FOV_VERTICAL (glTF's yfov) or SPM_FOV_SHORTER (pbrt-v4) */
    int projection;      /* SPM_PROJ_PERSPECTIVE or SPM_PROJ_ORTHOGRAPHIC */
    float ortho_size;    /* orthographic: the view's extent across fov_axis, scene units */
    float aperture;      /* thin lens: the aperture's diameter, scene units (0: a pinhole) */
    float focus;         /* thin lens: the distance along dir of the plane in focus */
    float up[3];         /* the camera's up (unit, normal to dir); zero: MiniLight's rule
                            (Y, or Z for a vertical view: host/geometry spm_camera_make) */
    int mirror;          /* 1: the image's x runs along dir x up, not up x dir (a
                            camera-from-world transform that mirrors, as pbrt's scenes
                            written from right-handed tools have) */
    int width, height;
    int spp;             /* samples per pixel the file asks for (0: not given) */
    spm_colour *colours;
    int ncolours;
    spm_scene_material *materials;
    int nmaterials;
    spm_scene_tri *tris;
    int ntris;
    /* per smooth triangle (spm_scene_tri.vn), its unit vertex normals n0, n1,
     * n2 (in its vertices' order, oriented to its front face's side) */
    float (*vnormals)[9];
    int nvnormals;
    /* per triangle with texture coordinates (spm_scene_tri.uv): u, v at its
     * three vertices, in their order (v = 0 at an image's bottom row) */
    float (*uvs)[6];
    int nuvs;
    /* the textures materials use (spm_scene_material.tex; host/scene/texture.h)
     * and the colour grid their texels are lifted on: npalettes palettes of
     * SPM_TEX_GRID^3 colour indices each, -1 where no texel needs the node
     * (texture_palette.c); the first the lifted colours, the others a type's
     * colours derived from them (the coated type's effective reflectance) */
    struct spm_texture_s *textures;
    int ntextures;
    int *palette;
    int npalettes;
    spm_alpha_map *alphas; /* the opacity maps materials use (spm_scene_material.alpha_map) */
    int nalphas;
    spm_normal_map *nmaps; /* the normal maps materials use (spm_scene_material.nmap) */
    int nnmaps;
    /* per triangle with the file's tangents (spm_scene_tri.tg): at each vertex
     * a tangent (x, y, z) and its handedness w = +-1 (glTF TANGENT's) */
    float (*tangents)[12];
    int ntangents;
    int bg_up;           /* colour for a ray escaping upward (+y), -1 none */
    int bg_down;         /* for one escaping downward, -1 none */
    spm_scene_envmap *env; /* the environment map (NULL: none; then bg_up and bg_down) */
    spm_scene_light *lights; /* the `light` statements' lights, in the file's order */
    /* the triangles' bounding sphere (centre, radius), kept when the geometry
     * consumes the triangles (lights.h spm_light_bounding_sphere) */
    double sphere[4];
    int have_sphere;
    int nlights;
    spm_scene_mesh *meshes; /* one per mesh statement, in the file's order */
    int nmeshes;
    /* Measured re-radiation matrices ('donaldson'): nrerad fluorescent parts
     * at 1 nm, SPM_TRUTH_BINS^2 doubles each as M[o][i] (host/scene/fluor.h). */
    double *rerad;
    int nrerad;
    /* Dispersive glasses (dispersion.h): ndisp index tables of SPM_TRUTH_BINS
     * doubles, n at the centre of each 1 nm bin; material p[SPM_DIEL_P_DISP]
     * is 1 + its row. */
    double *disp;
    int ndisp;
} spm_scene;

enum { SPM_FOV_HORIZONTAL = 0, SPM_FOV_SHORTER = 1, SPM_FOV_VERTICAL = 2 };
enum { SPM_PROJ_PERSPECTIVE = 0, SPM_PROJ_ORTHOGRAPHIC = 1 };

/* render --strict: what an importer would warn about as not rendered is an
 * error instead (exit 2). */
extern int spm_scene_strict;
/* render -D NAME=VALUE: a Mitsuba scene's parameter, over its <default>
 * (host/scene/mitsuba_xml.c). 1 with err when it is not NAME=VALUE or too many. */
int spm_scene_define(const char *name_value, spm_error *err);

/* render --camera NAME|INDEX: which of a model file's own cameras renders
 * (host/scene/scene_model.c; checked when the model loads). 0. */
int spm_scene_model_camera(const char *name_or_index);

/* Load a scene file: MiniLight .ml.txt (first line "#MiniLight") or the
 * project's own format. Errors: "file:line:col: what was expected". */
int spm_scene_load(const char *path, spm_scene *out, spm_error *err);
/* The built-in default: a Cornell box with ColorChecker walls, equal-energy light. */
int spm_scene_default(spm_scene *out, spm_error *err);
void spm_scene_free(spm_scene *s);
#endif
