/* Mitsuba 3 XML scene files (docs/MITSUBA.md): what the importer's parts
 * share. The reader (mitsuba_xml.c) turns the files into one tree of
 * elements, with `include` spliced in place, `default` and `$name`
 * substituted and each element's file:line:col kept; the properties
 * (mitsuba_props.c) read a plugin's typed children; the spectra
 * (mitsuba_spectra.c), BSDFs (mitsuba_bsdfs.c), shapes (mitsuba_shapes.c)
 * and the scene's walk (mitsuba_parse.c) build through scene_build.h. The
 * warning rule is pbrt-v4's (pbrt_warn), the transform arithmetic too. */
#ifndef SPM_MITSUBA_H
#define SPM_MITSUBA_H
#include "pbrt.h"

#define MI_MAX_INCLUDE_DEPTH 32
#define MI_MAX_FILE_BYTES (1ull << 30)
#define MI_MAX_DEFINES 64

typedef struct mi_node {
    char *tag;
    char **attr;              /* name, value, name, value, ... ($name substituted) */
    int nattr;
    struct mi_node **kids;
    int nkids;
    char where[600];          /* "file:line:col" of its start tag */
    const char *dir;          /* its file's folder: relative file names start there */
    int used;                 /* read by some code: what is not is warned about */
} mi_node;

/* The files' tree: root is the top file's <scene>. */
typedef struct {
    mi_node *root;
    char **dirs;              /* folders, owned here (nodes point into them) */
    int ndirs;
    char **search;            /* <path value=...> folders, resolved, in order */
    int nsearch;
} mi_doc;

/* -D name=value from the command line (spm_scene_define, scene.h) win over
 * the files' `default`s. */

/* Reads the checked file and everything it includes. 0, or 1 with err
 * naming file:line:col (malformed XML, a bad $name, an include cycle, a
 * file outside the folder). */
int mi_doc_read(const spm_file *top, mi_doc *doc, spm_error *err);
void mi_doc_free(mi_doc *doc);
/* An attribute's value, or NULL. */
const char *mi_attr(const mi_node *n, const char *name);
/* A file a node names (`filename`), relative to its file's folder, then to
 * the <path> folders: checked by the path rule. 0 and *out; 1 with err. */
int mi_file(const mi_doc *doc, const mi_node *n, const char *ref, spm_file *out,
            spm_error *err);

/* ---- properties ---------------------------------------------------------- */

/* The child of plugin `pl` that is a property of this name and one of the
 * tags (e.g. "float|integer"), marked used; NULL when absent; *bad with err
 * when it has another tag. */
mi_node *mi_prop(mi_node *pl, const char *name, const char *tags, int *bad, spm_error *err);
double mi_float(mi_node *pl, const char *name, double def, int *bad, spm_error *err);
int mi_int(mi_node *pl, const char *name, int def, int *bad, spm_error *err);
int mi_bool(mi_node *pl, const char *name, int def, int *bad, spm_error *err);
const char *mi_string(mi_node *pl, const char *name, const char *def, int *bad,
                      spm_error *err);
/* A <point>/<vector>: x y z attributes or value="x, y, z". */
int mi_vec3(const mi_node *n, const char *attrs[3], const char *value_attr, double out[3],
            spm_error *err);
/* A <transform> (translate, rotate, scale, matrix, lookat, in order, each
 * applied after the ones before): the 4x4 matrix. */
int mi_transform(mi_node *t, double m[4][4], spm_error *err);
/* `to_world` of a plugin, the identity when absent. */
int mi_to_world(mi_node *pl, double m[4][4], spm_error *err);
/* Parses a number list "a, b c" into out[max]: the count, -1 on a bad token. */
int mi_numbers(const char *s, double *out, int max);
/* "WHAT 'TYPE': parameter 'NAME'" warned for each child no code read. */
int mi_unused(mi_node *pl, const char *what, spm_error *err);
/* The elements with an id, and what a <ref id> names (NULL with err: none). */
typedef struct {
    spm_names ids;            /* id -> index into nodes */
    mi_node **nodes;
    int n;
} mi_ids;
mi_node *mi_ref(mi_ids *ids, mi_node *ref, spm_error *err);

/* ---- spectra --------------------------------------------------------------- */

typedef enum { MI_REFLECTANCE, MI_UNBOUNDED, MI_RADIANCE } mi_lift;

typedef struct {
    pbrt_spectra sp;          /* the rgb fits and the builder, shared with pbrt's lifts */
    const mi_doc *doc;
} mi_spectra;

/* The property `name` of pl (spectrum, rgb, blackbody, float): its colour,
 * def when absent, -1 black, -2 with err. A spectrum's values are Mitsuba's
 * (radiance in its units, W m^-2 sr^-1 nm^-1 ~ specmip's luminance per
 * equal-energy 1), zero outside its samples as Mitsuba's are. */
int mi_colour(mi_spectra *ms, mi_node *pl, const char *name, mi_lift lift, int def,
              spm_error *err);
/* The same as 1 nm values (no colour made), 1 when absent, 2 on error. */
int mi_values(mi_spectra *ms, mi_node *pl, const char *name, mi_lift lift, spm_spectrum *out,
              spm_error *err);
/* An index of refraction: a number or one of Mitsuba's named media. */
int mi_ior(mi_node *pl, const char *name, double def, double *out, spm_error *err);

/* ---- BSDFs and shapes ---------------------------------------------------- */

/* The material a <bsdf> maps to (its colours made); out->name set. 0, 1 err. */
int mi_bsdf_make(mi_spectra *ms, mi_ids *ids, mi_node *b, spm_scene_material *out,
                 spm_error *err);
/* Mitsuba's default: diffuse, reflectance 0.5. */
void mi_bsdf_default(mi_spectra *ms, spm_scene_material *out);

/* A shape's triangles in object space, its front faces Mitsuba's normal's
 * side. 0; 1 err; 2 a type not tessellated (the caller warns). *smooth:
 * it has vertex normals to shade with. */
int mi_shape_make(const mi_doc *doc, mi_node *s, const char *type, spm_mesh_data *out,
                  int *smooth, double obj[4][4], spm_error *err);

/* ---- sensor and integrator (mitsuba_sensor.c) ------------------------------ */

/* The camera, image size and samples of a <sensor> (NULL: Mitsuba's default). */
int mi_sensor(mi_node *s, spm_scene_builder *b, spm_error *err);
/* An <integrator>: what it asks that specmip does not do, warned. */
int mi_integrator(mi_node *n, spm_error *err);
#endif
