/* Triangle meshes from files (the scene format's `mesh` statement): OBJ with
 * MTL, PLY, glTF 2.0 and STL, read by Assimp in a child process under
 * resource limits (mesh_import.c), then bound to scene materials, transformed,
 * filtered of degenerate triangles and added to a scene (mesh_build.c). */
#ifndef SPM_MESH_H
#define SPM_MESH_H
#include "scene_build.h"
#include "paths.h"
#include "texture.h"
#include <stddef.h>
#include <stdint.h>

/* The importer's limits. Assimp is C++ with a history of crashes and runaway
 * allocations on hostile files; a child that exceeds these is killed and the
 * load fails. 4 GiB of address space holds a 16M-triangle import; 120 s of CPU
 * is far beyond the ~1 s of a 1M-triangle binary PLY; the wall clock bound
 * catches a child that blocks without using CPU. */
#define SPM_MESH_CHILD_AS_BYTES (4ull << 30)
#define SPM_MESH_CHILD_CPU_SECONDS 120
#define SPM_MESH_CHILD_WALL_SECONDS 600
/* Test hook, active only when the environment sets it:
 * SPECMIP_TEST_MESH_CHILD=crash makes the child die of SIGSEGV before
 * importing, =hang makes it wait for ever, =as=N limits its address space
 * to N MiB instead. SPECMIP_TEST_MESH_REFS=skip leaves out the check of a
 * model's references before the import, so that a test sees the child's
 * own (every file Assimp opens, every texture it reads). */
#define SPM_MESH_MAX_MATERIALS 4096
#define SPM_MESH_MAX_DEPTH 256 /* node hierarchy depth */

/* What a file held that the renderer ignores: one warning each (vertex
 * normals only when no triangle of the statement shades smooth). */
enum {
    SPM_MESH_IGN_NORMALS = 1 << 0,
    SPM_MESH_IGN_TEXCOORDS = 1 << 1,
    SPM_MESH_IGN_COLOURS = 1 << 2,
    SPM_MESH_IGN_TEXTURES = 1 << 3,
    SPM_MESH_IGN_NORMAL_MAPS = 1 << 4,
    SPM_MESH_IGN_GLOSSY = 1 << 5,
    SPM_MESH_IGN_OPACITY = 1 << 6,
    SPM_MESH_IGN_CAMERAS = 1 << 7,
    SPM_MESH_IGN_LIGHTS = 1 << 8,
    SPM_MESH_IGN_ANIMATION = 1 << 9,
    SPM_MESH_IGN_POINTS_LINES = 1 << 10,
    SPM_MESH_IGN_EMISSIVE_STRENGTH = 1 << 11,
    SPM_MESH_IGN_LIGHT_RANGE = 1 << 12,
    SPM_MESH_IGN_EMISSIVE_TEXTURES = 1 << 13,
    SPM_MESH_IGN_OCCLUSION = 1 << 14,
    SPM_MESH_IGN_SPECULAR_MAPS = 1 << 15,
    SPM_MESH_IGN_TEX_TRANSFORM = 1 << 16,
    SPM_MESH_IGN_COUNT = 17
};
/* "vertex normals", ... for bit i */
const char *spm_mesh_ignored_name(int bit);

typedef struct {
    char name[SPM_NAME_MAX];   /* the file's material name (truncated) */
    float diffuse[3];          /* linear RGB: diffuse or glTF base colour */
    float emission[3];         /* linear RGB radiance (times a glTF emissive strength) */
    int32_t texture;           /* SPM_MESH_TEX_*: a base-colour texture (mesh_texture.h) */
    float texture_mean[3];     /* its mean linear colour (SPM_MESH_TEX_MEAN) */
    char texture_name[96];     /* as the file names it, or "embedded image N" */
    char texture_why[128];     /* why it was not read (SPM_MESH_TEX_UNREAD) */
    char texture_file[SPM_PATH_MAX]; /* the image file's path (checked by the path rule,
                                  again by the parent, which binds it: mesh_texture.c); ""
                                  for an embedded image */
    float factor[3];           /* the colour factor the texture's mean multiplied */
    /* the emissive texture (glTF emissiveTexture, MTL map_Ke), found as the
     * base colour's is: SPM_MESH_TEX_*, its mean (emission stays the factor
     * alone: the parent binds the image or multiplies the mean in) */
    int32_t etexture;
    float etexture_mean[3];
    char etexture_name[96];
    char etexture_why[128];
    char etexture_file[SPM_PATH_MAX];
    /* What the file says beyond the diffuse colour (mesh_pbr.c maps it):
     * SPM_MESH_HAS_* bits for the values the file gave, and the values. */
    int32_t format;            /* SPM_MESH_FMT_*: whose conventions the values follow */
    uint32_t has;
    float metallic, roughness; /* glTF metallicFactor, roughnessFactor */
    float specular[3];         /* OBJ Ks */
    float shininess;           /* OBJ Ns */
    float ior;                 /* OBJ Ni, glTF KHR_materials_ior */
    float transmission;        /* glTF KHR_materials_transmission */
    float thickness;           /* glTF KHR_materials_volume thicknessFactor */
    float atten_dist;          /* its attenuationDistance */
    float atten_colour[3];     /* its attenuationColor */
    float opacity;             /* OBJ d (1 - Tr), glTF alpha */
    float dispersion;          /* glTF KHR_materials_dispersion: 20 / V_d (read from the JSON) */
    /* Opacity (mesh_alpha.c): SPM_MESH_ALPHA_* mode, glTF's alphaCutoff, the
     * factor (glTF baseColorFactor's alpha, OBJ d) and where the map is:
     * none, the base colour image's alpha channel (texture_file), or an
     * opacity image (OBJ map_d: alpha_file, checked by the path rule). */
    int32_t alpha_mode;
    float alpha_cutoff, alpha_factor;
    int32_t alpha_map;
    char alpha_name[96];       /* the opacity image as the file names it */
    char alpha_file[SPM_PATH_MAX];
    /* glTF's metallicRoughnessTexture, or an OBJ's map_Ns (mesh_metalrough.c):
     * SPM_MESH_MRMAP_*, its name as the file gives it and its checked path
     * ("" embedded) */
    int32_t mr_map;
    char mr_name[96];
    char mr_file[SPM_PATH_MAX];
    /* A normal map (mesh_nmap.c): SPM_MESH_NMAP_*, its scale (glTF
     * normalTexture scale, OBJ -bm), the image as the file names it and its
     * path (checked by the path rule, again by the parent). */
    int32_t nmap;
    float nmap_scale;
    char nmap_name[96];
    char nmap_file[SPM_PATH_MAX];
    /* An image embedded in the file (a GLB's bufferView, a data: URI) that a
     * map names instead of a file: 1 + its index in spm_mesh_data.images,
     * 0 none (the base colour's also feeds SPM_MESH_AMAP_BASE). */
    int32_t texture_embed, etexture_embed, mr_embed, nmap_embed;
    /* its maps' texture coordinate transforms (glTF KHR_texture_transform,
     * read from the JSON by the parent: mesh_gltf_uvx.c), SPM_MESH_MAP_*;
     * the opacity map from the base colour image takes the base colour's */
    spm_uvx uvx[4];
} spm_mesh_material;
enum { SPM_MESH_MAP_BASE = 0, SPM_MESH_MAP_EMIT = 1, SPM_MESH_MAP_MR = 2, SPM_MESH_MAP_NORMAL = 3 };
enum { SPM_MESH_MRMAP_NONE = 0, SPM_MESH_MRMAP_FILE = 1, SPM_MESH_MRMAP_EMBEDDED = 2 };
/* none; glTF normalTexture or OBJ norm; OBJ bump or map_Bump (a normal map
 * when its image has colour, as Blender writes them; a grey one is a height
 * map, not rendered) */
enum { SPM_MESH_NMAP_NONE = 0, SPM_MESH_NMAP_NORMAL = 1, SPM_MESH_NMAP_BUMP = 2 };
enum { SPM_MESH_ALPHA_OPAQUE = 0, SPM_MESH_ALPHA_MASK = 1, SPM_MESH_ALPHA_BLEND = 2 };
enum { SPM_MESH_AMAP_NONE = 0, SPM_MESH_AMAP_BASE = 1, SPM_MESH_AMAP_FILE = 2 };
enum { SPM_MESH_FMT_OTHER = 0, SPM_MESH_FMT_GLTF = 1, SPM_MESH_FMT_OBJ = 2 };
enum {
    SPM_MESH_HAS_METALLIC = 1 << 0,
    SPM_MESH_HAS_ROUGHNESS = 1 << 1,
    SPM_MESH_HAS_SPECULAR = 1 << 2,
    SPM_MESH_HAS_SHININESS = 1 << 3,
    SPM_MESH_HAS_IOR = 1 << 4,
    SPM_MESH_HAS_TRANSMISSION = 1 << 5,
    SPM_MESH_HAS_VOLUME = 1 << 6,
    SPM_MESH_HAS_OPACITY = 1 << 7,
    SPM_MESH_HAS_REFRACT = 1 << 8, /* OBJ illum 6 or 7 (refraction on), from the MTL file */
    SPM_MESH_HAS_DISPERSION = 1 << 9
};
/* spm_mesh_material.texture: none; diffuse is the factor times the
 * texture's mean; the texture could not be read, diffuse is the factor */
enum { SPM_MESH_TEX_NONE = 0, SPM_MESH_TEX_MEAN = 1, SPM_MESH_TEX_UNREAD = 2 };

/* An image embedded in a model, as its file's bytes (PNG, JPEG...) that the
 * maps naming it read as they read a file: its size, the format's extension
 * ("png", "jpg", terminated), its bytes (filled in by spm_mesh_decode: on
 * the wire the bytes follow the images' records, in order; size 0 for an
 * image no map reads). */
typedef struct {
    uint64_t size;
    char hint[8];
    const unsigned char *data;
} spm_mesh_image;
#define SPM_MESH_MAX_IMAGES 4096
#define SPM_MESH_MAX_IMAGE_BYTES (1ull << 30)

/* A triangle in file coordinates, node transforms applied, in the file's
 * winding (mirroring node transforms already compensated). */
typedef struct {
    float p[3][3];
    uint32_t mat;              /* index into the file's materials */
} spm_mesh_tri;

/* A triangle's vertex normals in file coordinates (node transforms applied
 * as normals transform, by the inverse transpose; not yet unit length), in
 * the order of its spm_mesh_tri's vertices; all zero: the triangle has none. */
typedef struct {
    float n[3][3];
} spm_mesh_normals;

/* A triangle's texture coordinates (u, v per vertex, v up as texture.h says;
 * Assimp's first set: glTF TEXCOORD_0, OBJ vt), in the order of its
 * spm_mesh_tri's vertices; all zero: the triangle has none. */
typedef struct {
    float uv[3][2];
} spm_mesh_uvs;

/* A triangle's tangents from the file (glTF TANGENT), in the order of its
 * spm_mesh_tri's vertices: per vertex a tangent (x, y, z; node transforms
 * applied as to a direction on the surface) and its handedness w = +-1, the
 * bitangent being w (N x T) (glTF's and MikkTSpace's); all zero: the
 * triangle has none (its tangents are made, geometry_nmap.c). */
typedef struct {
    float t[3][4];
} spm_mesh_tangents;

/* A glTF light (KHR_lights_punctual) a node of the default scene places,
 * in file coordinates (its node's transform applied; mesh_gltf_lights.c). */
enum { SPM_MESH_LIGHT_POINT = 0, SPM_MESH_LIGHT_SPOT = 1, SPM_MESH_LIGHT_DIRECTIONAL = 2 };
typedef struct {
    char name[64];             /* the light's name, else its node's, else "light N" */
    int32_t type;              /* SPM_MESH_LIGHT_* */
    float pos[3];              /* its node's origin */
    float dir[3];              /* its node's -z, unit length: where it shines */
    float colour[3];           /* `color`, linear RGB */
    float intensity;           /* candela (point, spot) or lux (directional) */
    float inner, outer;        /* a spot's innerConeAngle, outerConeAngle (radians) */
} spm_mesh_light;
#define SPM_MESH_MAX_LIGHTS 65536

typedef struct {
    uint32_t ignored;          /* SPM_MESH_IGN_* bits */
    uint32_t nmats;
    uint64_t ntris;
    spm_mesh_material *mats;
    spm_mesh_tri *tris;
    spm_mesh_normals *normals; /* per triangle, or NULL: the file has no vertex normals */
    spm_mesh_uvs *uvs;         /* per triangle, or NULL: the file has no texture coordinates */
    void *buf;                 /* owns mats, tris, normals, uvs, tangents and lights */
    char extensions[512];      /* a glTF's extensionsUsed that are not rendered, ", "-separated */
    spm_mesh_light *lights;    /* a glTF's lights (NULL: none) */
    uint32_t nlights;
    uint32_t nimages;          /* the file's embedded images (NULL: none) */
    spm_mesh_image *images;
    spm_mesh_tangents *tangents; /* per triangle, or NULL: the file has no tangents (glTF TANGENT) */
} spm_mesh_data;

/* The child's answer on its pipe (mesh_wire.c): a header of this many bytes
 * (magic, status, ignored, nmats, ntris as 64 bits, flags, nlights,
 * nimages, a spare word, the images' bytes as 64 bits), the materials, the
 * triangles, with SPM_MESH_WIRE_NORMALS in flags one spm_mesh_normals per
 * triangle, then with SPM_MESH_WIRE_UVS one spm_mesh_uvs per triangle, with
 * SPM_MESH_WIRE_TANGENTS one spm_mesh_tangents per triangle, then nlights
 * spm_mesh_light, nimages spm_mesh_image and the images' bytes. */
#define SPM_MESH_WIRE_HEAD 48
#define SPM_MESH_WIRE_NORMALS 1u
#define SPM_MESH_WIRE_UVS 2u
#define SPM_MESH_WIRE_TANGENTS 4u
/* The answer's size for these counts and flags (0 for unknown flags or
 * counts over their limits). */
size_t spm_mesh_wire_size(uint32_t nmats, uint64_t ntris, uint32_t flags, uint32_t nlights,
                          uint32_t nimages, uint64_t image_bytes);

/* Imports `file` in a child process (a PLY file of triangles or strips: by
 * mesh_ply.c, in this process). The files it names are checked first
 * (spm_mesh_refs_check), and every file the importer opens is checked again
 * by the path rule in the child. Errors name the file (and what Assimp
 * said); a crash or a limit hit in the child is an error; a stop request
 * (Ctrl-C) kills the child and fails with "interrupted". */
int spm_mesh_import(const spm_file *file, spm_mesh_data *out, spm_error *err);
/* The files a model names — a glTF's buffer and image URIs, an OBJ's MTL
 * files and their maps — each checked by the path rule (paths.h); a .glb's
 * chunks against its size (mesh_refs.c). 1 with err naming the reference.
 * A glTF's extensionsUsed that specmip does not render go into
 * unrendered[size] (Assimp hides the extensions it does not parse). */
int spm_mesh_refs_check(const spm_file *model, char *unrendered, size_t size, spm_error *err);

/* A glTF's JSON (a .glb's JSON chunk), parsed; NULL with err filled when it
 * cannot be read or parsed, or with err->msg empty when the file does not
 * open (the importer says why). Free with spm_json_free. mesh_refs.c */
struct spm_json *spm_mesh_gltf_doc(const spm_file *model, spm_error *err);

/* For an OBJ (by its extension): a warning naming each `mtllib` file that is
 * not beside it, and every material that no MTL file found defines loses its
 * name, so the rule for a mesh without materials applies to those triangles;
 * a material whose `illum` is 6 or 7 gets SPM_MESH_HAS_REFRACT
 * (mesh_obj_mtl.c). `where` is the statement's file:line. */
void spm_mesh_obj_mtl_check(const spm_file *obj, const char *where, spm_mesh_data *d);
void spm_mesh_free(spm_mesh_data *d);

/* The child's answer on the pipe, decoded and checked (the parent does not
 * trust it): counts within limits, sizes that match, material indices in
 * range, names terminated. Takes ownership of buf (malloc'd) on success. */
int spm_mesh_decode(void *buf, size_t size, const char *path, spm_mesh_data *out,
                    spm_error *err);
/* The same answer made from data (used by the child, and by tests and the
 * fuzz harness): a malloc'd buffer and its size in *size. */
void *spm_mesh_encode(const spm_mesh_data *d, size_t *size);

/* The scene material a lifted file material maps to (mesh_pbr.c, the table
 * in docs/SCENE_FORMAT.md): for glTF a conductor (metallic >= 0.5), a
 * dielectric (transmission >= 0.5) or a coated base colour; for OBJ a
 * dielectric (illum 6 or 7), a conductor (black Kd, coloured Ks), a coated
 * Kd (coloured Ks) or the diffuse colour; what has no target gets a warning
 * naming the material (`where`). r and e are the lifted reflectance and
 * emission colours; scale is the statement's length scale, cbrt |det M|
 * (a glTF attenuation distance becomes scene units by it). Returns the
 * material index or -1 with err filled. */
int spm_mesh_map_material(spm_scene_builder *b, const spm_mesh_material *m, int r, int e,
                          double scale, const char *where, spm_error *err);
/* A conductor whose normal-incidence reflectance is the reflectance spectrum
 * f0 (Gulbrandsen 2014 per wavelength, edge tint g = f0): its eta and k. */
void spm_mesh_gulbrandsen(const spm_spectrum *f0, spm_spectrum *eta, spm_spectrum *k);

/* A material's opacity (mesh_alpha.c). In the importer's child: glTF's
 * alphaMode (MASK, BLEND; OPAQUE ignores the alpha, as the specification
 * says) with its alphaCutoff and baseColorFactor's alpha over the base
 * colour image's alpha channel; any other format's opacity (OBJ d) and
 * opacity map (OBJ map_d, found beside the model) as stochastic opacity.
 * 0, or 2 with *refused filled when the map is outside where the scene may
 * read (paths.h). In the parent: the material with it (its map read, the
 * path checked again), or `material` when it is opaque; a map on a mesh
 * without texture coordinates, or that cannot be read, is warned about and
 * the factor alone is used. -1 with err. */
struct aiScene;
struct aiMaterial;
int spm_mesh_alpha_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                        spm_error *refused);
int spm_mesh_alpha_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                        int material, const char *mwhere, spm_error *err);
/* An image a material names (Assimp's path, Windows separators taken as
 * '/'), relative to the model's folder, checked by the path rule: 0, or 1
 * with *refused filled (mesh_alpha.c; the opacity, metallic-roughness and normal maps). */
int spm_mesh_image_check(const char *ref, const char *model, spm_file *file, spm_error *refused);

/* The image a map names, for the parent's binding: the embedded image
 * embed - 1 of d (embed > 0), else the file `file` (checked again by
 * the path rule; f holds it). 0 with *src, or 1 with why filled
 * (mesh_texture.c). */
int spm_mesh_map_image(const spm_mesh_data *d, int32_t embed, const char *file,
                       const char *mwhere, spm_file *f, spm_image_src *src, char *why,
                       size_t whylen);

/* glTF's metallic-roughness map and MTL's map_Ns (mesh_metalrough.c). In
 * the importer's child: the metallicRoughnessTexture's (an OBJ's map_Ns's)
 * name and path (beside the model, checked by the path rule; 2 with *refused
 * filled when outside). In the parent: the material with its metallic (blue)
 * and roughness (green) channels bound to its mix record (SPM_MIX_*), or
 * `material` unchanged when it has no mix; for an OBJ the material with the
 * exponent map as a roughness map (a mix of metallic 1 naming the material
 * itself); a map that cannot be read or applied, or on a mesh without
 * texture coordinates, is warned about and the factors alone are used. */
int spm_mesh_mix_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                      spm_error *refused);
int spm_mesh_mix_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                      int material, const char *mwhere, spm_error *err);

/* A material's normal map (mesh_nmap.c), as spm_mesh_alpha_read and
 * spm_mesh_alpha_bind do opacity: read in the child (2 with *refused when the
 * image is outside where the scene may read), bound in the parent (the
 * material with it, or `material` when it has none or it cannot be applied:
 * warned about by name). */
int spm_mesh_nmap_read(const struct aiMaterial *m, const char *model, spm_mesh_material *out,
                       spm_error *refused);
int spm_mesh_nmap_bind(spm_scene_builder *b, const spm_mesh_data *d, const spm_mesh_material *m,
                       int material, const char *mwhere, spm_error *err);

/* A file material bound to a scene material. */
typedef struct {
    char file_mat[SPM_NAME_MAX];
    int material;
} spm_mesh_bind;

/* `smooth`'s crease angle without a `crease` clause, in degrees: above the
 * 30 degrees between the faces of an 8 x 12 UV sphere (and the 45 of an
 * 8-sided cylinder), so coarse tessellations of curved surfaces turn round,
 * and below the 90 of a box's edges, which stay sharp (Houdini's normal
 * node's default cusp angle). */
#define SPM_MESH_DEFAULT_CREASE 60.0

/* spm_mesh_opts.shading: the `smooth` and `flat` clauses. By default a
 * triangle with vertex normals shades smooth when its material's type says so
 * (materials.h spm_mtype_desc.smooth: not the diffuse types). */
enum { SPM_MESH_SHADE_DEFAULT = 0, SPM_MESH_SHADE_SMOOTH = 1, SPM_MESH_SHADE_FLAT = 2 };

typedef struct {
    int material;              /* scene material for unbound file materials, -1: lift RGB */
    int fallback;              /* 1 + the scene material of triangles the file gives no
                                  material (a glTF file's take glTF's default material);
                                  0: none, they are an error */
    int shading;               /* SPM_MESH_SHADE_* */
    double crease;             /* with SPM_MESH_SHADE_SMOOTH and above 0: triangles without
                                  vertex normals get computed ones (spm_mesh_smooth_normals),
                                  faces meeting at more than this many degrees keep their edge */
    const spm_mesh_bind *binds;
    int nbinds;
    double m[3][4];            /* scene-from-file transform (x' = M x + t) */
    int line;                  /* the statement's line */
} spm_mesh_opts;

/* Transforms composed in the order applied: each call applies its transform
 * after what m already does (m <- T m). A rotation is `degrees` about `axis`
 * (non-zero; right-handed); a scale is per axis (non-zero). */
void spm_mesh_identity(double m[3][4]);
void spm_mesh_scale(double m[3][4], const double scale[3]);
void spm_mesh_rotate(double m[3][4], const double axis[3], double degrees);
void spm_mesh_translate(double m[3][4], const double translate[3]);
/* scale, then rotate, then translate */
void spm_mesh_transform(const double scale[3], const double axis[3], double degrees,
                        const double translate[3], double m[3][4]);

/* Vertex normals for the triangles that have none (d->normals NULL or a
 * triangle's all zero; the others are copied): each corner's normal the sum of
 * angle x unit face normal over the faces around its vertex (corners at equal
 * positions are one vertex), taken across edges shared by exactly two faces
 * whose normals differ by at most crease_deg, measured after the transform m.
 * Returned as the file's own would be, for spm_mesh_add's normal map (M^T of
 * the scene normal); *made counts the triangles given normals. NULL (and
 * *made 0) when every triangle has its own. mesh_smooth.c */
spm_mesh_normals *spm_mesh_smooth_normals(const spm_mesh_data *d, const double m[3][4],
                                          double crease_deg, uint64_t *made);

/* Lifted RGB colours shared across a scene's meshes (one fit per colour). */
typedef struct {
    spm_names rgb;
} spm_mesh_cache;
void spm_mesh_cache_init(spm_mesh_cache *c);
void spm_mesh_cache_free(spm_mesh_cache *c);

/* Adds the mesh's triangles to the scene: binding, transform (a mirroring one
 * keeps each face's front side by reversing the winding), degenerate triangles
 * skipped and counted. `file` names the mesh in messages, `where` the
 * statement. Prints the triangle count and bounding box unless warnings are
 * quiet. */
int spm_mesh_add(spm_scene_builder *b, spm_mesh_cache *cache, const spm_mesh_data *d,
                 const spm_mesh_opts *o, const char *file, const char *where, spm_error *err);
/* The file's lights (d->lights) added to the scene as its light kinds
 * (point, spot of the squared shape, distant), placed by the statement's
 * transform o->m; a point or spot light's candela times the square of its
 * length scale, so that the image does not depend on the scene's unit.
 * mesh_lights.c */
int spm_mesh_add_lights(spm_scene_builder *b, spm_mesh_cache *cache, const spm_mesh_data *d,
                        const spm_mesh_opts *o, const char *file, const char *where,
                        spm_error *err);
#endif
