/* pbrt-v4 scene files (docs/PBRT.md): what the importer's parts share. The
 * lexer (pbrt_lexer.c) reads a file into tokens, the parameter lists
 * (pbrt_params.c) hold a directive's typed values, the spectra
 * (pbrt_spectra.c) lift rgb, blackbody, named and file spectra as pbrt-v4
 * does, the materials (pbrt_materials.c) and shapes (pbrt_shapes.c) map onto
 * specmip's, and the parser (pbrt_parse.c) keeps the graphics state and
 * builds the scene through scene_build.h. */
#ifndef SPM_PBRT_H
#define SPM_PBRT_H
#include "scene_build.h"
#include "mesh.h"
#include "paths.h"

#define PBRT_MAX_INCLUDE_DEPTH 32
#define PBRT_MAX_FILE_BYTES (1ull << 31) /* a text scene file held whole */

/* ---- tokens ----------------------------------------------------------------- */

typedef enum { PT_EOF, PT_WORD, PT_STRING, PT_NUMBER, PT_LBRACK, PT_RBRACK } pbrt_tok_type;

typedef struct {
    char path[SPM_PATH_MAX];  /* as messages name it */
    char dir[SPM_PATH_MAX];   /* its folder: references are relative to it */
    char *buf;
    size_t n, pos;
    int line, col;            /* of buf[pos] */
    pbrt_tok_type type;       /* the current token */
    char *text;               /* its text (a string's contents, unescaped) */
    size_t cap;
    double num;               /* PT_NUMBER's value */
    int tline, tcol;
} pbrt_lexer;

/* Reads the checked file p whole and its first token; messages name it by p->shown. */
int pbrt_lex_open(pbrt_lexer *lx, const spm_file *p, spm_error *err);
void pbrt_lex_close(pbrt_lexer *lx);
int pbrt_lex_next(pbrt_lexer *lx, spm_error *err);
/* "file:line:col" of the current token. */
void pbrt_lex_where(const pbrt_lexer *lx, char *buf, size_t size);
/* "file:line:col: expected WHAT, found ...". Returns 1. */
int pbrt_lex_expected(const pbrt_lexer *lx, spm_error *err, const char *what);

/* ---- parameters -------------------------------------------------------------- */

typedef enum {
    PP_INTEGER, PP_FLOAT, PP_POINT2, PP_VECTOR2, PP_POINT3, PP_VECTOR3, PP_NORMAL, PP_BOOL,
    PP_STRING, PP_TEXTURE, PP_RGB, PP_BLACKBODY, PP_SPECTRUM, PP_TYPES
} pbrt_ptype;

typedef struct {
    pbrt_ptype type;
    char type_name[16];   /* as written ("point" for point3, "color" for rgb) */
    char name[SPM_NAME_MAX];
    double *num;
    size_t nnum;
    char **str;
    size_t nstr;
    char where[600];      /* "file:line:col" of its declaration */
    int used;
} pbrt_param;

typedef struct {
    pbrt_param *p;
    int n;
} pbrt_params;

/* The "type name" value... pairs after a directive's arguments, until the
 * next directive. Errors: an unknown type, values of the wrong kind or count. */
int pbrt_params_read(pbrt_lexer *lx, pbrt_params *ps, spm_error *err);
void pbrt_params_free(pbrt_params *ps);
/* The parameter `name`, marked used, or NULL. A parameter of that name but
 * of a type not among `types` (a bit mask of 1 << PP_*) is an error (-> *bad). */
pbrt_param *pbrt_param_find(pbrt_params *ps, const char *name, unsigned types, int *bad,
                            spm_error *err);
/* One number: the parameter's single value, else def. *bad on a type or
 * count error. */
double pbrt_param_float(pbrt_params *ps, const char *name, double def, int *bad,
                        spm_error *err);
int pbrt_param_int(pbrt_params *ps, const char *name, int def, int *bad, spm_error *err);
int pbrt_param_bool(pbrt_params *ps, const char *name, int def, int *bad, spm_error *err);
/* A string parameter's value, or def. */
const char *pbrt_param_string(pbrt_params *ps, const char *name, const char *def, int *bad,
                              spm_error *err);
/* One warning for each parameter not used: "WHERE: WHAT: parameter 'TYPE NAME' ignored". */
int pbrt_params_unused(const pbrt_params *ps, const char *what, spm_error *err);

/* ---- warnings ------------------------------------------------------------------ */

/* What the importer does not render: one warning per kind of thing ignored
 * (`what`, e.g. "LightSource \"point\""), naming where it was first met;
 * repeats are counted and summed up at the end (pbrt_warn_summary). Under
 * --strict (spm_scene_strict) the first is an error: 1 with err. */
int pbrt_warn(const char *where, const char *what, const char *why, spm_error *err);
void pbrt_warn_summary(void);
void pbrt_warn_reset(void);

/* ---- spectra -------------------------------------------------------------------- */

/* How a value is lifted to a spectrum (pbrt-v4's SpectrumType): a bounded
 * reflectance, an unbounded value (eta, k), or an illuminant. */
typedef enum { PBRT_ALBEDO, PBRT_UNBOUNDED, PBRT_ILLUMINANT } pbrt_lift;

typedef struct {
    spm_scene_builder *b;
    spm_names rgb_fits;      /* rgb text key -> colour (one fit per value and lift) */
    const char *dir;         /* folder spectrum files are relative to */
    spm_error *err;
} pbrt_spectra;

/* The spectrum parameter pa (rgb, blackbody or spectrum) lifted as `lift`:
 * illuminants normalised to luminance 1 as pbrt-v4 does, times scale
 * (rgb: the rgb's own luminance times scale). A colour index, -1 for black
 * (an rgb of zeros), -2 with err. */
int pbrt_spectrum_colour(pbrt_spectra *sp, const pbrt_param *pa, pbrt_lift lift, double scale);
/* The spectrum of pa as 1 nm bins (no colour made): eta per wavelength. */
int pbrt_spectrum_values(pbrt_spectra *sp, const pbrt_param *pa, pbrt_lift lift,
                         spm_spectrum *out);
/* pbrt-v4's named spectra this importer knows ("metal-Ag-eta", "glass-BK7",
 * "stdillum-D65", ...): 0 and the spectrum, or 1 (unknown: *known lists them). */
int pbrt_named_spectrum(const char *name, spm_kind kind, spm_spectrum *out, const char **known,
                        spm_error *err);
/* A named glass's catalogue entry (dispersion.h), or NULL. */
const char *pbrt_glass_catalogue_name(const char *pbrt_name);

/* ---- materials ------------------------------------------------------------------- */

/* pa: the directive's parameters; type the material's type ("diffuse", ...);
 * out the prototype (spm_scene_material; colours made, no emission). 0, or 1 with err. */
int pbrt_material_make(pbrt_spectra *sp, const char *type, pbrt_params *ps, const char *where,
                       spm_scene_material *out, spm_error *err);
/* The scene material pbrt's default is (diffuse, reflectance 0.5). */
void pbrt_material_default(pbrt_spectra *sp, spm_scene_material *out);

/* ---- shapes ------------------------------------------------------------------------ */

typedef struct {
    int reverse;       /* ReverseOrientation */
    const char *dir;   /* folder of the file naming it */
    int has_normals;   /* out: the shape gave vertex normals (shades smooth) */
} pbrt_shape_ctx;

/* The shape's triangles in object space (one material, index 0), each wound
 * so that its front face is the side pbrt-v4's geometric normal takes (its
 * normals' side when it has normals; ReverseOrientation turns it). 0 and
 * *out; 1 with err; 2: a type not supported (warned by the caller). */
int pbrt_shape_make(const char *type, pbrt_params *ps, pbrt_shape_ctx *c, const char *where,
                    spm_mesh_data *out, spm_error *err);

/* ---- transforms ---------------------------------------------------------------------- */

void pbrt_mat_identity(double m[4][4]);
void pbrt_mat_mul(const double a[4][4], const double b[4][4], double out[4][4]);
/* 1 when m is singular. */
int pbrt_mat_inverse(const double m[4][4], double out[4][4]);
void pbrt_mat_translate(const double t[3], double out[4][4]);
void pbrt_mat_scale(const double s[3], double out[4][4]);
/* `deg` degrees about axis (pbrt's Rotate). 1 when the axis is zero. */
int pbrt_mat_rotate(double deg, const double axis[3], double out[4][4]);
/* pbrt's LookAt: the camera-from-world matrix. 1 when degenerate. */
int pbrt_mat_lookat(const double eye[3], const double look[3], const double up[3],
                    double out[4][4]);
/* m applied to the point (w 1) or vector (w 0) v. */
void pbrt_mat_apply(const double m[4][4], const double v[3], double w, double out[3]);
#endif
