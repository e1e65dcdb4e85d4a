/* The pbrt-v4 parser's state, shared by its directive files: the include
 * stack, the graphics state (pbrt_state.c: transforms, attributes), the
 * materials, lights, shapes and instances (pbrt_world.c), the camera and
 * the rendering options (pbrt_options.c). */
#ifndef SPM_PBRT_PARSER_H
#define SPM_PBRT_PARSER_H
#include "pbrt.h"

typedef struct {
    double ctm[4][4];
    int reverse;           /* ReverseOrientation */
    int mat;               /* index into protos */
    int area_colour;       /* AreaLightSource's emission colour, -1 none */
    int area_twosided;
} pbrt_gstate;

typedef struct {            /* a shape inside ObjectBegin/End */
    spm_mesh_data d;
    int material, smooth;
    double m[4][4];
    char where[600];
} pbrt_obj_shape;

typedef struct {
    char name[SPM_NAME_MAX];
    pbrt_obj_shape *shapes;
    int n;
} pbrt_object;

typedef struct {
    spm_scene_builder b;
    pbrt_spectra sp;
    spm_error *err;
    pbrt_lexer *files[PBRT_MAX_INCLUDE_DEPTH];
    char canon[PBRT_MAX_INCLUDE_DEPTH][SPM_PATH_MAX]; /* for include cycles */
    int depth;
    pbrt_gstate gs, *stack;
    int nstack;
    spm_scene_material *protos;  /* material prototypes; 0 is pbrt's default */
    int nprotos;
    spm_names named_mats;        /* MakeNamedMaterial name -> proto */
    spm_names coordsys;          /* CoordinateSystem name -> cs index */
    double (*cs)[4][4];
    int ncs;
    pbrt_object *objs;
    int nobjs, cur_obj;          /* cur_obj: inside ObjectBegin, else -1 */
    spm_names obj_names;
    spm_mesh_cache cache;
    int world;                   /* after WorldBegin */
    int have_camera;
    double cam_ctm[4][4];        /* camera-from-world at the Camera directive */
    double fov;
    double lens_radius, focal_distance; /* Camera's thin lens (pbrt-v4's defaults 0, 1e6) */
    int ortho;                         /* Camera "orthographic" */
    char cam_where[600];
    int width, height, spp;
} pbrt_parser;

static inline pbrt_lexer *pbrt_lx(pbrt_parser *p) { return p->files[p->depth - 1]; }

/* A directive's handler: the lexer is past its name; `where` names it. */
typedef int (*pbrt_handler)(pbrt_parser *p, const char *where);
typedef struct {
    const char *name;
    pbrt_handler fn;
} pbrt_directive;

extern const pbrt_directive pbrt_state_directives[];  /* pbrt_state.c */
extern const pbrt_directive pbrt_world_directives[];  /* pbrt_world.c */
extern const pbrt_directive pbrt_option_directives[]; /* pbrt_options.c */

/* Arguments (pbrt_args.c): a quoted string; n numbers, bare or in one bracketed list. */
int pbrt_arg_string(pbrt_parser *p, const char *what, char *out, size_t size);
int pbrt_arg_numbers(pbrt_parser *p, int n, const char *what, double *out);
/* The directive's parameter list (pbrt_params_read on the current file). */
int pbrt_arg_params(pbrt_parser *p, pbrt_params *ps);

/* Names the coordinate system m (CoordinateSystem; pbrt's "camera" and
 * "world"), replacing one of that name. */
void pbrt_coordsys_set(pbrt_parser *p, const char *name, const double m[4][4]);
/* The camera and film, once the options are complete (WorldBegin, or the
 * end of a file without it). */
int pbrt_options_finish(pbrt_parser *p, const char *where);
void pbrt_objects_free(pbrt_parser *p);
/* LightSource `type` with its parameters (pbrt_lights.c): a light, the
 * background, or a warning naming what is not rendered. */
int pbrt_light_make(pbrt_parser *p, const char *type, pbrt_params *ps, const char *where);
/* A light's spectrum parameter `name` (default the colour space's white,
 * D65) at luminance `scale` (pbrt-v4's normalisation): a colour, -1 for
 * black, < -1 on an error. */
int pbrt_light_colour(pbrt_parser *p, pbrt_params *ps, const char *name, double scale,
                      const char *where);
#endif
