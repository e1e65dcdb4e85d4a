/* The project's own scene format (docs/SCENE_FORMAT.md): one statement per
 * line, a keyword first. Spectra are named definitions turned into concrete
 * colours where a material or the background uses them, because the kind
 * (reflectance or emission) decides how partial data is extended. */
#include "scene_build.h"
#include "scene_parsers.h"
#include "scene_lexer.h"
#include "scene_camera.h"
#include "csv.h"
#include "mesh.h"
#include "interrupt.h"
#include "lights.h"
#include "materials.h"
#include "dispersion.h"
#include "fluor.h"
#include "scene_texture.h"
#include "envmap.h"
#include "sky.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_SPECTRA 4096
#define MAX_INLINE_SAMPLES 100000
#define MAX_WAVELENGTH 1e5  /* nm; anything beyond is a typo, not data */

#define SPM_INCLUDE_DEPTH 16 /* files read inside one another, the scene file included */

typedef enum { DEF_FILE, DEF_INLINE, DEF_EQUAL, DEF_BLACKBODY } def_type;

typedef struct {
    char name[SPM_NAME_MAX];
    def_type type;
    char where[600];         /* "file:line:col" of the definition */
    spm_file file;           /* DEF_FILE: resolved path */
    char column[SPM_TOK_MAX]; /* DEF_FILE: column name or "" */
    double *wl, *val;        /* DEF_INLINE */
    size_t n;
    double kelvin;           /* DEF_BLACKBODY */
    spm_spectrum *made[2];   /* per spm_kind, made on first use */
    int used;
} spec_def;

typedef struct {
    spm_lexer lx;
    spm_scene_builder b;
    spm_error *err;
    char dir[1024];          /* directory of the scene file, for relative spectrum paths */
    spec_def *defs;
    int ndefs, cap_defs;
    spm_names spectra;       /* name -> index into defs */
    spm_names materials;     /* name -> material index */
    int image_line, camera_line, spp_line, bg_line[2];
    int kw_line, kw_col;     /* the current statement's keyword: where it stands */
    spm_mesh_cache meshes;   /* lifted mesh colours, shared by the scene's meshes */
    spm_scene_textures textures;
    int texture_ok;          /* a texture may be applied per point here: 1 a reflectance,
                                2 an emission */
    double texture_scale;    /* the scale after an emission's texture */
    char texture_where[600]; /* where the material's reflectance named a texture */
    char *reading[SPM_INCLUDE_DEPTH]; /* the files being read, outermost first (canonical) */
    int nreading;
} parser;

static int statement(parser *p);

/* Statements up to the end of the file the lexer reads. */
static int read_statements(parser *p)
{
    int rc = 0;
    while (!rc && p->lx.type != SPM_TOK_EOF) {
        rc = spm_lex_skip_newlines(&p->lx, p->err);
        if (!rc && p->lx.type != SPM_TOK_EOF)
            rc = statement(p);
    }
    return rc;
}

static void where_now(const parser *p, char *buf, size_t size)
{
    spm_lex_where(&p->lx, buf, size);
}

/* "file:line:col" of the current statement's keyword. */
static void where_keyword(const parser *p, char *buf, size_t size)
{
    snprintf(buf, size, "%s:%d:%d", p->lx.path, p->kw_line, p->kw_col);
}

/* ---- numbers and vectors ------------------------------------------------- */

static int vec3(parser *p, const char *what, double lo, double hi, double v[3])
{
    for (int k = 0; k < 3; k++)
        if (spm_lex_number(&p->lx, what, lo, hi, &v[k], p->err))
            return 1;
    return 0;
}

/* An optional scale after a spectrum name: present when the next token is a number. */
static int opt_scale(parser *p, int emission, double *scale)
{
    *scale = 1.0;
    if (!spm_lex_is_number(&p->lx))
        return 0;
    if (emission && (p->lx.text[0] == '-' || strtod(p->lx.text, NULL) == 0.0))
        return spm_lex_expected(&p->lx, p->err, "an emission scale (a luminance) above 0");
    return spm_lex_number(&p->lx, emission ? "an emission scale (a luminance)" : "a scale", 0.0,
                          HUGE_VAL, scale, p->err);
}

/* ---- spectra --------------------------------------------------------------- */

/* Only regular files: a device such as /dev/zero would never end. */
static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, R_OK) == 0;
}

static int is_directory(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* A spectrum file: absolute, or relative to the scene file, or in spectra/;
 * where it may be is the path rule's (paths.h). A directory where the file is
 * looked for is named as such, not skipped. */
static int resolve_spectrum_file(parser *p, const char *name, const char *where, spm_file *out)
{
    if (spm_path_check(p->dir, name, where, out, p->err))
        return 1;
    if (file_exists(out->path))
        return 0;
    if (is_directory(out->path)) {
        spm_errorf(p->err, "%s: spectrum file '%s' is a directory (%s), not a CSV file", where,
                   name, out->shown);
        return 1;
    }
    if (name[0] == '/') {
        spm_errorf(p->err, "%s: spectrum file '%s' not found (or not a regular file)", where,
                   name);
        return 1;
    }
    char tried[SPM_PATH_MAX], rel[1100], data[SPM_PATH_MAX];
    snprintf(tried, sizeof tried, "%s", out->shown);
    snprintf(rel, sizeof rel, "spectra/%s", name);
    spm_data_path(rel, data, sizeof data);
    if (spm_path_check_joined(data, where, out, p->err) == 0 && file_exists(out->path))
        return 0;
    spm_errorf(p->err, "%s: spectrum file '%s' not found (looked for %s and %s)", where, name,
               tried, data);
    return 1;
}

static int parse_inline(parser *p, spec_def *d)
{
    size_t cap = 0;
    if (spm_lex_skip_newlines(&p->lx, p->err))
        return 1;
    while (!spm_lex_is(&p->lx, "end")) {
        if (p->lx.type == SPM_TOK_EOF || !spm_lex_is_number(&p->lx))
            return spm_lex_expected(&p->lx, p->err, "a wavelength in nm or 'end'");
        if (d->n >= MAX_INLINE_SAMPLES)
            return spm_lex_expected(&p->lx, p->err, "'end' (too many samples)");
        if (d->n == cap) {
            cap = cap ? cap * 2 : 64;
            d->wl = spm_xrealloc(d->wl, cap * sizeof *d->wl);
            d->val = spm_xrealloc(d->val, cap * sizeof *d->val);
        }
        double lo = d->n ? d->wl[d->n - 1] : 0.0;
        if (d->n && strtod(p->lx.text, NULL) <= lo) {
            char what[96];
            snprintf(what, sizeof what, "a wavelength above the previous one (%g nm)", lo);
            return spm_lex_expected(&p->lx, p->err, what);
        }
        if (spm_lex_number(&p->lx, "a wavelength in nm", 0.0, MAX_WAVELENGTH, &d->wl[d->n],
                           p->err) ||
            spm_lex_number(&p->lx, "a spectral value", 0.0, HUGE_VAL, &d->val[d->n], p->err) ||
            spm_lex_skip_newlines(&p->lx, p->err))
            return 1;
        d->n++;
    }
    if (d->n == 0)
        return spm_lex_expected(&p->lx, p->err, "a wavelength in nm");
    return spm_lex_next(&p->lx, p->err);
}

static int stmt_spectrum(parser *p)
{
    char name[SPM_NAME_MAX];
    char where[600];
    where_now(p, where, sizeof where);
    if (p->ndefs >= MAX_SPECTRA) {
        spm_errorf(p->err, "%s: more than %d spectrum definitions", where, MAX_SPECTRA);
        return 1;
    }
    if (spm_lex_name(&p->lx, "a spectrum name", name, sizeof name, p->err))
        return 1;
    int prev = spm_names_get(&p->spectra, name);
    if (prev >= 0) {
        spm_errorf(p->err, "%s: spectrum '%s' is already defined at %s", where, name,
                   p->defs[prev].where);
        return 1;
    }
    if (p->ndefs == p->cap_defs) {
        p->cap_defs = p->cap_defs ? 2 * p->cap_defs : 16;
        p->defs = spm_xrealloc(p->defs, (size_t)p->cap_defs * sizeof *p->defs);
    }
    spec_def *d = &p->defs[p->ndefs++]; /* counted now so that it is freed on error */
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "%s", name);
    snprintf(d->where, sizeof d->where, "%s", where);
    if (spm_lex_is(&p->lx, "file")) {
        char file[SPM_TOK_MAX], fwhere[600];
        d->type = DEF_FILE;
        if (spm_lex_next(&p->lx, p->err))
            return 1;
        where_now(p, fwhere, sizeof fwhere);
        if (spm_lex_path(&p->lx, "a spectrum file name", file, sizeof file, p->err) ||
            resolve_spectrum_file(p, file, fwhere, &d->file))
            return 1;
        if (spm_lex_is(&p->lx, "column") &&
            (spm_lex_next(&p->lx, p->err) ||
             spm_lex_path(&p->lx, "a column name", d->column, sizeof d->column, p->err)))
            return 1;
    } else if (spm_lex_is(&p->lx, "inline")) {
        d->type = DEF_INLINE;
        if (spm_lex_next(&p->lx, p->err) || parse_inline(p, d))
            return 1;
    } else if (spm_lex_is(&p->lx, "equal")) {
        d->type = DEF_EQUAL;
        if (spm_lex_next(&p->lx, p->err))
            return 1;
    } else if (spm_lex_is(&p->lx, "blackbody")) {
        d->type = DEF_BLACKBODY;
        if (spm_lex_next(&p->lx, p->err) ||
            spm_lex_number(&p->lx, "a temperature in kelvin", 500.0, 1e5, &d->kelvin, p->err))
            return 1;
    } else {
        return spm_lex_expected(&p->lx, p->err, "'file', 'inline', 'equal' or 'blackbody'");
    }
    spm_names_put(&p->spectra, name, p->ndefs - 1);
    return spm_lex_end_of_statement(&p->lx, p->err);
}

/* The named spectrum as a `kind`, made on first use. `where` is the use site. */
static const spm_spectrum *use_spectrum(parser *p, int idx, spm_kind kind, const char *where)
{
    spec_def *d = &p->defs[idx];
    d->used = 1;
    if (d->made[kind])
        return d->made[kind];
    spm_spectrum sp;
    spm_error inner;
    int rc = 0;
    switch (d->type) {
    case DEF_FILE:
        rc = spm_spectrum_load(d->file.path, d->column[0] ? d->column : NULL, kind, &sp, &inner);
        if (rc)
            spm_errorf(p->err, "%s: spectrum '%s': %s", where, d->name, inner.msg);
        break;
    case DEF_INLINE: {
        char what[700];
        snprintf(what, sizeof what, "%s: spectrum '%s'", d->where, d->name);
        rc = spm_spectrum_from_samples(d->wl, d->val, d->n, kind, what, &sp, p->err);
        break;
    }
    case DEF_EQUAL:
        spm_spectrum_constant(1.0, kind, &sp);
        break;
    case DEF_BLACKBODY:
        if (kind == SPM_KIND_REFLECTANCE) {
            spm_errorf(p->err, "%s: spectrum '%s' is a blackbody: an emission, not a reflectance",
                       where, d->name);
            rc = 1;
        } else {
            spm_spectrum_blackbody(d->kelvin, &sp);
        }
        break;
    }
    if (rc)
        return NULL;
    d->made[kind] = spm_xmalloc(sizeof sp);
    *d->made[kind] = sp;
    return d->made[kind];
}

/* "NAME SCALE?" -> a colour of the scene (scaled, checked). Returns its index
 * or -1. A spectrum name, with an optional scale; shape_only: without one, the
 * spectrum's peak scaled to 1 (a shape, as a reflectance-kind colour; an
 * emission's shape, so zero outside its samples as every emission is);
 * optical: an optical constant (a conductor's eta or k), extended as a
 * reflectance (by its end values) but not bounded by 1. */
static int colour_ref_as(parser *p, spm_kind kind, int shape_only, int optical)
{
    char where[600], name[SPM_NAME_MAX], cname[SPM_NAME_MAX];
    where_now(p, where, sizeof where);
    if (spm_lex_is(&p->lx, "texture")) {
        if (shape_only || optical) {
            spm_errorf(p->err, "%s: a texture gives a reflectance or an emission, not %s", where,
                       optical ? "an optical constant" : "a spectral shape");
            return -1;
        }
        if (spm_lex_next(&p->lx, p->err))
            return -1;
        p->textures.last = 0;
        int c = spm_scene_texture_colour(&p->textures, &p->lx, &p->b, kind, &p->texture_scale,
                                         p->err);
        if (c >= 0 && !p->texture_ok)
            spm_scene_texture_as_mean(&p->textures, p->textures.last - 1, kind, where,
                                      "textures are applied per point to a reflectance or an emission");
        if (c >= 0 && p->texture_ok == 1)
            snprintf(p->texture_where, sizeof p->texture_where, "%s", where);
        return c;
    }
    if (spm_lex_name(&p->lx, "a spectrum name", name, sizeof name, p->err))
        return -1;
    int idx = spm_names_get(&p->spectra, name);
    if (idx < 0) {
        spm_errorf(p->err, "%s: unknown spectrum '%s' (define it with 'spectrum %s ...' first)",
                   where, name, name);
        return -1;
    }
    double scale;
    const spm_spectrum *shape =
        use_spectrum(p, idx, shape_only ? SPM_KIND_EMISSION : kind, where);
    scale = 1.0;
    if (!shape || (!shape_only && opt_scale(p, kind == SPM_KIND_EMISSION, &scale)))
        return -1;
    if (shape_only == 1) {
        double peak = spm_spectrum_max(shape);
        if (!(peak > 0.0)) {
            spm_errorf(p->err, "%s: spectrum '%s' is zero inside %d-%d nm: it has no shape", where,
                       name, SPM_LAMBDA_MIN, SPM_LAMBDA_MAX);
            return -1;
        }
        scale = 1.0 / peak;
    }
    spm_spectrum sp;
    int rc = kind == SPM_KIND_EMISSION ? spm_sb_emission(shape, scale, where, &sp, p->err)
             : optical                 ? spm_sb_optical(shape, scale, &sp)
                                       : spm_sb_reflectance(shape, scale, where, &sp, p->err);
    if (rc)
        return -1;
    if (scale == 1.0 && kind == SPM_KIND_REFLECTANCE)
        snprintf(cname, sizeof cname, "%s", name);
    else
        snprintf(cname, sizeof cname, "%.40s*%.6g", name, scale);
    return spm_sb_colour(&p->b, cname, &sp, where, p->err);
}

static int colour_ref(parser *p, spm_kind kind)
{
    return colour_ref_as(p, kind, 0, 0);
}

/* ---- lights (host/scene/lights.h) ------------------------------------------ */

/* an angle in degrees in [lo, hi], in radians */
static int light_angle(parser *p, const char *what, double lo, double hi, double *rad)
{
    double x;
    if (spm_lex_number(&p->lx, what, lo, hi, &x, p->err))
        return 1;
    *rad = x * M_PI / 180.0;
    return 0;
}

/* a light's direction from v (not zero) into q[DIR]; target: v came from
 * a target */
static int light_dir(parser *p, const double v[3], float *q, int target)
{
    double x = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(x > 0.0) || !isfinite(x))
        return spm_lex_expected(&p->lx, p->err, target ? "a target away from the light"
                                                       : "a direction that is not zero");
    for (int i = 0; i < 3; i++)
        q[SPM_LIGHT_P_DIR + i] = (float)(v[i] / x);
    return 0;
}

/* `cone DEG [falloff DEG] [shape linear|smoothstep|squared]` (lights.h 'C') */
static int light_cone(parser *p, float *q)
{
    double c, f;
    if (!spm_lex_is(&p->lx, "cone"))
        return spm_lex_expected(&p->lx, p->err, "'cone' and the cone's half-angle in degrees");
    if (spm_lex_next(&p->lx, p->err) ||
        light_angle(p, "the cone's half-angle in degrees", 1e-3, 90.0, &c))
        return 1;
    f = c / 4.0; /* Mitsuba 3's default beam_width: 3/4 of the cutoff angle */
    if (spm_lex_is(&p->lx, "falloff") &&
        (spm_lex_next(&p->lx, p->err) ||
         light_angle(p, "the falloff's width in degrees (at most the cone's half-angle)", 0.0,
                     c * 180.0 / M_PI, &f)))
        return 1;
    q[SPM_LIGHT_P_A] = (float)c;
    q[SPM_LIGHT_P_B] = (float)(c - f);
    q[SPM_LIGHT_P_C] = (float)cos(c);
    q[SPM_LIGHT_P_D] = SPM_SPOT_LINEAR;
    if (!spm_lex_is(&p->lx, "shape"))
        return 0;
    static const char *shapes[] = {[SPM_SPOT_LINEAR] = "linear",
                                   [SPM_SPOT_SMOOTHSTEP] = "smoothstep",
                                   [SPM_SPOT_SQUARED] = "squared"};
    if (spm_lex_next(&p->lx, p->err))
        return 1;
    for (int i = 0; i < 3; i++)
        if (spm_lex_is(&p->lx, shapes[i])) {
            q[SPM_LIGHT_P_D] = (float)i;
            return spm_lex_next(&p->lx, p->err);
        }
    return spm_lex_expected(&p->lx, p->err, "a falloff shape (linear, smoothstep, squared)");
}

/* One argument of a light's statement, its letter c (spm_light_desc.args),
 * into l; *power the power a 'W' gave (0: an intensity). */
static int light_arg(parser *p, char c, spm_scene_light *l, double *power)
{
    double v[3], x;
    float *q = l->p;
    switch (c) {
    case 'P':
    case 'T':
        if (vec3(p, c == 'P' ? "a coordinate" : "a target coordinate", -SPM_SCENE_MAX_COORD,
                 SPM_SCENE_MAX_COORD, v))
            return 1;
        for (int i = 0; c == 'T' && i < 3; i++)
            v[i] -= q[SPM_LIGHT_P_POS + i];
        for (int i = 0; c == 'P' && i < 3; i++)
            q[SPM_LIGHT_P_POS + i] = (float)v[i];
        return c == 'T' ? light_dir(p, v, q, 1) : 0;
    case 'D':
        return vec3(p, "a direction component", -HUGE_VAL, HUGE_VAL, v) || light_dir(p, v, q, 0);
    case 'S':
        return (l->colour = colour_ref_as(p, SPM_KIND_EMISSION, 2, 0)) < 0;
    case 'C':
        return light_cone(p, q);
    default: /* W, E: the factor of the spectrum */
        if (c == 'W' && spm_lex_is(&p->lx, "intensity")) {
            if (spm_lex_next(&p->lx, p->err))
                return 1;
            c = 'I';
        }
        if (spm_lex_number(&p->lx, c == 'W' ? "a power (or 'intensity' and an intensity)"
                                   : c == 'I' ? "an intensity"
                                              : "an irradiance",
                           1e-30, HUGE_VAL, &x, p->err))
            return 1;
        *power = c == 'W' ? x : 0.0;
        q[SPM_LIGHT_P_SCALE] = c == 'W' ? 1.0f : (float)x;
        return 0;
    }
}

/* light KIND ARGUMENTS...: a light of a kind the list names (lights.h), its
 * arguments as its descriptor says */
static int stmt_light(parser *p)
{
    char what[256] = "a light kind (";
    const char *sep = "";
    for (int i = 0, n = (int)strlen(what); i < spm_nlight_kinds; i++)
        if (spm_light_kinds[i].keyword) {
            n += snprintf(what + n, sizeof what - (size_t)n, "%s%s", sep,
                          spm_light_kinds[i].keyword);
            sep = ", ";
        }
    strncat(what, ")", sizeof what - strlen(what) - 1);
    const spm_light_desc *k = p->lx.type == SPM_TOK_WORD ? spm_light_kind_find(p->lx.text) : NULL;
    if (!k)
        return spm_lex_expected(&p->lx, p->err, what);
    spm_scene_light l = {.kind = (int)k->tag, .colour = -1};
    where_keyword(p, l.where, sizeof l.where);
    double power = 0.0;
    if (spm_lex_next(&p->lx, p->err))
        return 1;
    for (const char *c = k->args; *c; c++)
        if (light_arg(p, *c, &l, &power))
            return 1;
    spm_scene *s = p->b.s;
    if (power > 0.0) /* the intensity that emits it (p[SCALE] = 1 so far) */
        l.p[SPM_LIGHT_P_SCALE] = (float)(power / k->power(s, l.p));
    s->lights = spm_xrealloc(s->lights, ((size_t)s->nlights + 1) * sizeof *s->lights);
    s->lights[s->nlights++] = l;
    return spm_lex_end_of_statement(&p->lx, p->err);
}

/* ---- statements ------------------------------------------------------------ */

static int once(parser *p, int *line, const char *what)
{
    if (*line) {
        char where[600];
        where_keyword(p, where, sizeof where);
        spm_errorf(p->err, "%s: %s given twice (first at line %d)", where, what, *line);
        return 1;
    }
    *line = p->kw_line;
    return 0;
}

static int stmt_image(parser *p)
{
    long w, h;
    if (once(p, &p->image_line, "the image size") ||
        spm_lex_int(&p->lx, "the image width", 1, SPM_SCENE_MAX_SIDE, &w, p->err) ||
        spm_lex_int(&p->lx, "the image height", 1, SPM_SCENE_MAX_SIDE, &h, p->err))
        return 1;
    p->b.s->width = (int)w;
    p->b.s->height = (int)h;
    return spm_lex_end_of_statement(&p->lx, p->err);
}

static int stmt_spp(parser *p)
{
    long n;
    if (once(p, &p->spp_line, "the sample count") ||
        spm_lex_int(&p->lx, "samples per pixel", 1, SPM_SCENE_MAX_SPP, &n, p->err))
        return 1;
    p->b.s->spp = (int)n;
    return spm_lex_end_of_statement(&p->lx, p->err);
}

static int stmt_camera(parser *p)
{
    char where[600];
    where_keyword(p, where, sizeof where);
    if (once(p, &p->camera_line, "the camera") || spm_parse_camera(&p->lx, &p->b, where, p->err))
        return 1;
    return spm_lex_end_of_statement(&p->lx, p->err);
}

/* An index of refraction (materials.h SPM_MP_INDEX), by its clause: 'ior'
 * a number or a spectrum name of n per wavelength, 'sellmeier B1 B2 B3 C1
 * C2 C3', 'cauchy A B', 'glass NAME' (dispersion.h). n_d goes into p[slot];
 * an index that varies gets a row of the scene's index table (n at each 1 nm
 * bin's centre; a spectrum's bin means), p[SPM_DIEL_P_DISP] = 1 + the row.
 * An 'ior SPECTRUM' whose values are all equal is that one number, as
 * 'ior N' (the same image, bit for bit). */
static int index_param(parser *p, const spm_mparam *pa, spm_scene_material *m)
{
    char where[600];
    where_now(p, where, sizeof where);
    double n[SPM_TRUTH_BINS], nd = 0.0;
    const char *cl = pa->clause;
    if (!strcmp(cl, "ior") && spm_lex_is_number(&p->lx)) {
        double v;
        if (spm_lex_number(&p->lx, pa->what, pa->lo, pa->hi, &v, p->err))
            return 1;
        m->p[pa->slot] = v;
        return 0;
    }
    if (!strcmp(cl, "ior")) {
        char name[SPM_NAME_MAX];
        if (spm_lex_name(&p->lx, "a number or a spectrum name", name, sizeof name, p->err))
            return 1;
        int id = spm_names_get(&p->spectra, name);
        if (id < 0) {
            spm_errorf(p->err, "%s: unknown spectrum '%s' (define it with 'spectrum %s ...' first)",
                       where, name, name);
            return 1;
        }
        /* extended by its end values, as an optical constant */
        const spm_spectrum *sp = use_spectrum(p, id, SPM_KIND_REFLECTANCE, where);
        if (!sp)
            return 1;
        const spec_def *d = &p->defs[id];
        int constant = 1;
        if (d->type == DEF_INLINE) /* its own numbers, not their bin means */
            for (size_t i = 1; i < d->n; i++)
                constant = constant && d->val[i] == d->val[0];
        else
            for (int b = 1; b < SPM_TRUTH_BINS; b++)
                constant = constant && sp->nm1[b] == sp->nm1[0];
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            n[b] = sp->nm1[b];
        if (constant)
            n[0] = d->type == DEF_INLINE ? d->val[0] : sp->nm1[0];
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            if (!(n[b] >= pa->lo && n[b] <= pa->hi)) {
                spm_errorf(p->err, "%s: spectrum '%s' as %s: %g at %g nm is outside %g..%g", where,
                           name, pa->what, n[b], spm_disp_bin_nm(b), pa->lo, pa->hi);
                return 1;
            }
        if (constant) {
            m->p[pa->slot] = n[0];
            return 0;
        }
        nd = n[(int)SPM_DISP_REF_NM - SPM_LAMBDA_MIN]; /* the bin holding the d-line */
    } else if (!strcmp(cl, "glass")) {
        char name[SPM_NAME_MAX], list[256];
        if (spm_lex_name(&p->lx, "a glass name", name, sizeof name, p->err))
            return 1;
        const spm_glass *g = spm_glass_find(name);
        if (!g) {
            spm_errorf(p->err, "%s: unknown glass '%s' (the catalogue has %s)", where, name,
                       spm_glass_list(list, sizeof list));
            return 1;
        }
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            n[b] = spm_disp_sellmeier(g->b, g->c, spm_disp_bin_nm(b));
        nd = spm_disp_sellmeier(g->b, g->c, SPM_DISP_REF_NM);
    } else {
        int sell = !strcmp(cl, "sellmeier"), k = sell ? 6 : 2;
        double c[6];
        static const char *what[2][6] = {
            {"Cauchy's A", "Cauchy's B (um^2)"},
            {"Sellmeier's B1", "Sellmeier's B2", "Sellmeier's B3", "Sellmeier's C1 (um^2)",
             "Sellmeier's C2 (um^2)", "Sellmeier's C3 (um^2)"}};
        for (int i = 0; i < k; i++)
            if (spm_lex_number(&p->lx, what[sell][i], sell ? 0.0 : i ? -1.0 : 1.0,
                               sell ? 1e4 : i ? 1.0 : 4.0, &c[i], p->err))
                return 1;
        for (int b = 0; b < SPM_TRUTH_BINS; b++)
            n[b] = sell ? spm_disp_sellmeier(c, c + 3, spm_disp_bin_nm(b))
                        : spm_disp_cauchy(c[0], c[1], spm_disp_bin_nm(b));
        nd = sell ? spm_disp_sellmeier(c, c + 3, SPM_DISP_REF_NM) : spm_disp_cauchy(c[0], c[1], SPM_DISP_REF_NM);
    }
    for (int b = 0; b < SPM_TRUTH_BINS; b++)
        if (isnan(n[b])) {
            spm_errorf(p->err, "%s: '%s' gives no real index at %g nm (n^2 <= 0, or a pole inside "
                               "%d-%d nm)", where, cl, spm_disp_bin_nm(b), SPM_LAMBDA_MIN,
                       SPM_LAMBDA_MAX);
            return 1;
        } else if (!(n[b] >= pa->lo && n[b] <= pa->hi)) {
            spm_errorf(p->err, "%s: '%s' gives an index of %g at %g nm, outside %g..%g", where, cl,
                       n[b], spm_disp_bin_nm(b), pa->lo, pa->hi);
            return 1;
        }
    spm_sb_index_table(&p->b, n, m);
    m->p[pa->slot] = nd;
    return 0;
}

/* One parameter of a material or emitter type, as its descriptor says. */
/* A re-radiation matrix file (materials.h SPM_MP_FILE): found as a spectrum
 * file is, its diagonal a colour into refl, its fluorescent part appended to
 * the scene's matrices. */
static int matrix_param(parser *p, const spm_mparam *pa, spm_scene_material *m)
{
    char where[600], file[512];
    spm_file path;
    where_now(p, where, sizeof where);
    if (spm_lex_path(&p->lx, "a matrix file name", file, sizeof file, p->err) ||
        resolve_spectrum_file(p, file, where, &path))
        return 1;
    spm_scene *s = p->b.s;
    const size_t nn = (size_t)SPM_TRUTH_BINS * SPM_TRUTH_BINS;
    double *F = spm_xcalloc(nn, sizeof *F);
    spm_spectrum diag;
    spm_error inner;
    if (spm_fluor_load_donaldson(path.path, &diag, F, &inner)) {
        spm_errorf(p->err, "%s: %s", where, inner.msg);
        free(F);
        return 1;
    }
    char cname[SPM_NAME_MAX];
    snprintf(cname, sizeof cname, "%.50s:matrix", m->name);
    m->refl = spm_sb_colour(&p->b, cname, &diag, where, p->err);
    if (m->refl < 0) {
        free(F);
        return 1;
    }
    s->rerad = spm_xrealloc(s->rerad, (size_t)(s->nrerad + 1) * nn * sizeof *s->rerad);
    memcpy(s->rerad + (size_t)s->nrerad * nn, F, nn * sizeof *F);
    free(F);
    m->p[pa->slot] = s->nrerad++;
    return 0;
}

static int material_param(parser *p, const spm_mparam *pa, spm_scene_material *m)
{
    if (pa->kind == SPM_MP_FILE)
        return matrix_param(p, pa, m);
    if (pa->kind == SPM_MP_INDEX)
        return index_param(p, pa, m);
    if (pa->kind == SPM_MP_FLAG) {
        m->flags |= 1u << pa->slot;
        return 0;
    }
    if (pa->kind == SPM_MP_NUMBER || pa->kind == SPM_MP_EMIT_NUMBER) {
        double v;
        if (spm_lex_number(&p->lx, pa->what, pa->lo, pa->hi, &v, p->err))
            return 1;
        *(pa->kind == SPM_MP_NUMBER ? &m->p[pa->slot] : &m->ep[pa->slot]) = v; /* an emitter's: ep */
        return 0;
    }
    p->texture_ok = pa->slot == SPM_MSLOT_REFL && pa->kind == SPM_MP_REFLECTANCE ? 1
                    : pa->slot == SPM_MSLOT_EMIT && pa->kind == SPM_MP_EMISSION ? 2
                                                                                 : 0;
    p->textures.last = 0;
    int c = colour_ref_as(p, pa->kind == SPM_MP_EMISSION ? SPM_KIND_EMISSION : SPM_KIND_REFLECTANCE,
                          pa->kind == SPM_MP_SHAPE, pa->kind == SPM_MP_OPTICAL);
    if (p->texture_ok == 1)
        m->tex = p->textures.last; /* 1 + the parser's texture: the material decides */
    if (p->texture_ok == 2 && p->textures.last) /* every emitter type is textured per point */
        m->etex = p->textures.last, m->escale = (float)p->texture_scale;
    p->texture_ok = 0;
    if (c < 0)
        return 1;
    *(pa->slot == SPM_MSLOT_REFL   ? &m->refl
      : pa->slot == SPM_MSLOT_EMIT ? &m->emit
      : pa->slot == SPM_MSLOT_COL3 ? &m->col3
                                   : &m->col2) = c;
    return 0;
}

/* opacity (texture NAME | A) [cutoff C | blend], the lexer on 'opacity':
 * the material's opacity, a texture's values or the number A (0 to 1), as a
 * cut-out at alpha >= C (default 0.5, glTF's) or, with 'blend', stochastic
 * (spm_shared.h SPM_ALPHA_*; any material type). */
static int opacity_clause(parser *p, spm_scene_material *m)
{
    double v = 1.0, cut = 0.5;
    if (spm_lex_next(&p->lx, p->err))
        return 1;
    if (spm_lex_is(&p->lx, "texture")) {
        if (spm_lex_next(&p->lx, p->err) ||
            (m->alpha_map = spm_scene_texture_alpha(&p->textures, &p->lx, &p->b, p->err)) < 0)
            return 1;
    } else if (spm_lex_number(&p->lx, "an opacity (0 to 1) or 'texture NAME'", 0.0, 1.0, &v,
                              p->err)) {
        return 1;
    }
    m->alpha_mode = (int)SPM_ALPHA_MASK;
    if (spm_lex_is(&p->lx, "blend")) {
        m->alpha_mode = (int)SPM_ALPHA_BLEND, cut = 0.0;
        if (spm_lex_next(&p->lx, p->err))
            return 1;
    } else if (spm_lex_is(&p->lx, "cutoff") &&
               (spm_lex_next(&p->lx, p->err) ||
                spm_lex_number(&p->lx, "an opacity cutoff (0 to 1)", 0.0, 1.0, &cut, p->err))) {
        return 1;
    }
    m->alpha_factor = (float)v, m->alpha_cutoff = (float)cut;
    return 0;
}

/* normal texture NAME [scale S], the lexer on 'normal': the material's
 * normal map, the texture's values as a tangent-space normal; S (default 1,
 * glTF's normalTexture scale) scales its x and y (spm_shared.h SPM_NMAP_*;
 * any material type). */
static int normal_clause(parser *p, spm_scene_material *m)
{
    double scale = 1.0;
    if (spm_lex_next(&p->lx, p->err))
        return 1;
    if (!spm_lex_is(&p->lx, "texture"))
        return spm_lex_expected(&p->lx, p->err, "'texture NAME' after 'normal'");
    if (spm_lex_next(&p->lx, p->err) ||
        (m->nmap = spm_scene_texture_nmap(&p->textures, &p->lx, &p->b, p->err)) < 0)
        return 1;
    if (spm_lex_is(&p->lx, "scale") &&
        (spm_lex_next(&p->lx, p->err) ||
         spm_lex_number(&p->lx, "a normal map scale", -100.0, 100.0, &scale, p->err)))
        return 1;
    m->nmap_scale = (float)scale;
    return 0;
}

/* A clause of any type at the lexer, each once: opacity, normal. 1 read, 0
 * none there, -1 with the error. */
static int any_type_clause(parser *p, spm_scene_material *m)
{
    if (!m->alpha_mode && spm_lex_is(&p->lx, "opacity"))
        return opacity_clause(p, m) ? -1 : 1;
    if (!m->nmap && spm_lex_is(&p->lx, "normal"))
        return normal_clause(p, m) ? -1 : 1;
    return 0;
}

/* The clauses of material type mt, then every emitter type's, into cl (ctag:
 * SPM_EMIT_TYPES for the material's own, else the emitter's tag). */
static int clause_list(const spm_mtype_desc *mt, const spm_mparam **cl, unsigned *ctag)
{
    int ncl = 0;
    for (int d = -1; d < spm_nemitter_types; d++) {
        const spm_mtype_desc *t = d < 0 ? mt : &spm_emitter_types[d];
        for (int i = 0; i < t->nparams; i++)
            if (t->params[i].clause) {
                ctag[ncl] = d < 0 ? SPM_EMIT_TYPES : t->tag;
                cl[ncl++] = &t->params[i];
            }
    }
    return ncl;
}

/* A type keyword after the default type's clauses ('material N reflect S
 * fluoresce ...'): the type named, if it takes every clause given so far;
 * else NULL. */
static const spm_mtype_desc *late_type(parser *p, const spm_mtype_desc *mt,
                                       const spm_mparam *const *cl, const int *have, int ncl)
{
    if (mt != spm_material_type_default())
        return NULL;
    const spm_mtype_desc *t = NULL;
    for (int i = 0; i < spm_nmaterial_types && !t; i++)
        if (spm_material_types[i].keyword && spm_lex_is(&p->lx, spm_material_types[i].keyword))
            t = &spm_material_types[i];
    for (int k = 0; t && k < ncl; k++) {
        int found = !have[k];
        for (int i = 0; i < t->nparams && !found; i++)
            found = t->params[i].clause && !strcmp(t->params[i].clause, cl[k]->clause);
        if (!found)
            t = NULL;
    }
    return t;
}

/* material NAME [TYPE] POSITIONAL... [CLAUSE ...]...: the type's keyword
 * (none: Lambertian), its positional parameters in order, then its clauses and
 * those of the emitter types, each once, in any order. Everything comes from
 * the descriptors (materials.h): a new type adds no code here. */
static int stmt_material(parser *p)
{
    char where[600], name[SPM_NAME_MAX];
    where_now(p, where, sizeof where);
    if (spm_lex_name(&p->lx, "a material name", name, sizeof name, p->err))
        return 1;
    if (spm_names_get(&p->materials, name) >= 0) {
        spm_errorf(p->err, "%s: material '%s' is already defined", where, name);
        return 1;
    }
    spm_scene_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.refl = m.emit = m.col2 = m.col3 = m.diag = -1;
    const spm_mtype_desc *mt = NULL;
    for (int i = 0; i < spm_nmaterial_types && !mt; i++)
        if (spm_material_types[i].keyword && spm_lex_is(&p->lx, spm_material_types[i].keyword))
            mt = &spm_material_types[i];
    if (mt) {
        if (spm_lex_next(&p->lx, p->err))
            return 1;
    } else {
        mt = spm_material_type_default();
    }
    m.type = (int)mt->tag;
    m.etype = SPM_EMIT_AREA;
    for (int i = 0; i < mt->nparams; i++)
        if (!mt->params[i].clause && material_param(p, &mt->params[i], &m))
            return 1;
    /* the clauses: the material type's, then every emitter type's */
    const spm_mparam *cl[SPM_MTYPE_MAX_PARAMS * (1 + SPM_EMIT_TYPES)];
    unsigned ctag[SPM_MTYPE_MAX_PARAMS * (1 + SPM_EMIT_TYPES)];
    int have[SPM_MTYPE_MAX_PARAMS * (1 + SPM_EMIT_TYPES)] = {0}, emitter = 0;
    int ncl = clause_list(mt, cl, ctag);
    char expected[256];
    int ne = 0;
    for (int k = 0; k < ncl; k++) /* "'a', 'b' or 'c' (each once)" */
        ne += snprintf(expected + ne, sizeof expected - (size_t)ne, "%s'%s'",
                       k == 0 ? "" : k == ncl - 1 ? " or " : ", ", cl[k]->clause);
    snprintf(expected + ne, sizeof expected - (size_t)ne, " (each once)");
    while (p->lx.type != SPM_TOK_NEWLINE && p->lx.type != SPM_TOK_EOF) {
        int any = any_type_clause(p, &m);
        if (any < 0)
            return 1;
        if (any)
            continue;
        int k = 0;
        while (k < ncl && !spm_lex_is(&p->lx, cl[k]->clause))
            k++;
        const spm_mtype_desc *lt = k == ncl ? late_type(p, mt, cl, have, ncl) : NULL;
        if (lt) { /* the clauses given keep their marks under the new type's list */
            const spm_mparam *ocl[SPM_MTYPE_MAX_PARAMS * (1 + SPM_EMIT_TYPES)];
            int ohave[SPM_MTYPE_MAX_PARAMS * (1 + SPM_EMIT_TYPES)], on = ncl;
            memcpy(ocl, cl, sizeof ocl);
            memcpy(ohave, have, sizeof ohave);
            mt = lt;
            m.type = (int)mt->tag;
            ncl = clause_list(mt, cl, ctag);
            for (int a = 0; a < ncl; a++) {
                have[a] = 0;
                for (int b = 0; b < on; b++)
                    have[a] |= ohave[b] && !strcmp(ocl[b]->clause, cl[a]->clause);
            }
            if (spm_lex_next(&p->lx, p->err))
                return 1;
            for (int i = 0; i < mt->nparams; i++)
                if (!mt->params[i].clause && material_param(p, &mt->params[i], &m))
                    return 1;
            continue;
        }
        if (k == ncl || have[k] || (ctag[k] != SPM_EMIT_TYPES && emitter && (int)ctag[k] != m.etype))
            return spm_lex_expected(&p->lx, p->err, expected);
        for (int a = 0; a < ncl; a++)
            if (cl[k]->group && have[a] && cl[a]->group == cl[k]->group) {
                char at[600];
                where_now(p, at, sizeof at);
                spm_errorf(p->err, "%s: material '%s': '%s' and '%s' both give %s (one of them)",
                           at, name, cl[a]->clause, cl[k]->clause, cl[k]->what);
                return 1;
            }
        have[k] = 1;
        if (ctag[k] != SPM_EMIT_TYPES) {
            m.etype = (int)ctag[k];
            emitter = 1;
        }
        if (spm_lex_next(&p->lx, p->err) || material_param(p, cl[k], &m))
            return 1;
    }
    for (int k = 0; k < ncl; k++) {
        int given = have[k];
        char alts[256] = "";
        for (int a = 0, n = 0; cl[k]->group && a < ncl; a++)
            if (cl[a]->group == cl[k]->group) {
                given |= have[a];
                n += snprintf(alts + n, sizeof alts - (size_t)n, "%s'%s'", n ? " or " : "",
                              cl[a]->clause);
            }
        if (cl[k]->required && !given) { /* a clause the type cannot do without */
            if (!alts[0])
                snprintf(alts, sizeof alts, "'%s'", cl[k]->clause);
            spm_errorf(p->err, "%s: material '%s': %s needs %s (%s)", where, name,
                       mt->keyword ? mt->keyword : "it", alts, cl[k]->what);
            return 1;
        }
    }
    if (m.tex && !spm_material_textured(m.type)) {
        spm_scene_texture_as_mean(&p->textures, m.tex - 1, SPM_KIND_REFLECTANCE, p->texture_where,
                                  SPM_TEXTURED_TYPES_WHY);
        m.tex = 0;
    } else if (m.tex) {
        m.tex = spm_scene_texture_adopt(&p->textures, m.tex - 1, &p->b);
    }
    if (m.etex)
        m.etex = spm_scene_texture_adopt(&p->textures, m.etex - 1, &p->b);
    int idx = spm_sb_material_typed(&p->b, &m, where, p->err);
    if (idx < 0)
        return 1;
    spm_names_put(&p->materials, name, idx);
    return spm_lex_end_of_statement(&p->lx, p->err);
}

/* tri (3 vertices) or quad (4 vertices, two triangles a b c and a c d). */
static int stmt_polygon(parser *p, int nverts)
{
    /* Positions are kept as numbers and formatted only for an error: a scene
     * of a million triangles is a million of these statements. */
    char where[600], name[SPM_NAME_MAX];
    int line = p->kw_line, col = p->kw_col;
    int mline = p->lx.tline, mcol = p->lx.tcol;
    if (spm_lex_name(&p->lx, "a material name", name, sizeof name, p->err))
        return 1;
    int m = spm_names_get(&p->materials, name);
    if (m < 0) {
        spm_errorf(p->err,
                   "%s:%d:%d: unknown material '%s' (define it with 'material %s ...' first)",
                   p->lx.path, mline, mcol, name, name);
        return 1;
    }
    double v[4][3];
    for (int i = 0; i < nverts; i++)
        if (vec3(p, "a vertex coordinate", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, v[i]))
            return 1;
    /* texture coordinates: 'uv U V' per vertex, else the unit square's corners
     * in order (a triangle: pbrt's (0 0) (1 0) (1 1)) */
    float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    if (spm_lex_is(&p->lx, "uv")) {
        if (spm_lex_next(&p->lx, p->err))
            return 1;
        for (int i = 0; i < 2 * nverts; i++) {
            double x;
            if (spm_lex_number(&p->lx, "a texture coordinate", -1e6, 1e6, &x, p->err))
                return 1;
            uv[i / 2][i % 2] = (float)x;
        }
    }
    if (spm_lex_end_of_statement(&p->lx, p->err))
        return 1;
    double t[3][3];
    for (int tri = 0; tri < nverts - 2; tri++) {
        memcpy(t[0], v[0], sizeof t[0]);
        memcpy(t[1], v[tri + 1], sizeof t[1]);
        memcpy(t[2], v[tri + 2], sizeof t[2]);
        /* an empty position, then the message gets the statement's in front */
        if (spm_sb_tri(&p->b, t, m, line, "", p->err)) {
            spm_error inner = *p->err;
            snprintf(where, sizeof where, "%s:%d:%d", p->lx.path, line, col);
            spm_errorf(p->err, "%s%s", where, inner.msg);
            return 1;
        }
        const spm_scene_material *sm = &p->b.s->materials[m];
        if (sm->tex || sm->etex || sm->alpha_map || sm->nmap) {
            float tuv[6] = {uv[0][0], uv[0][1], uv[tri + 1][0], uv[tri + 1][1], uv[tri + 2][0],
                            uv[tri + 2][1]};
            spm_sb_tri_uv(&p->b, tuv);
        }
    }
    return 0;
}

/* bind FILE_MATERIAL NAME: appended to *binds (the lexer on 'bind'). */
static int mesh_bind(parser *p, spm_mesh_bind **binds, int *nbinds)
{
    char where[600], name[SPM_NAME_MAX];
    *binds = spm_xrealloc(*binds, (size_t)(*nbinds + 1) * sizeof **binds);
    spm_mesh_bind *bd = &(*binds)[*nbinds];
    where_now(p, where, sizeof where);
    if (spm_lex_next(&p->lx, p->err) ||
        spm_lex_path(&p->lx, "a material name of the mesh file", bd->file_mat,
                     sizeof bd->file_mat, p->err))
        return 1;
    for (int j = 0; j < *nbinds; j++)
        if (!strcmp((*binds)[j].file_mat, bd->file_mat)) {
            spm_errorf(p->err, "%s: file material '%s' is bound twice", where, bd->file_mat);
            return 1;
        }
    where_now(p, where, sizeof where);
    if (spm_lex_name(&p->lx, "a material name", name, sizeof name, p->err))
        return 1;
    bd->material = spm_names_get(&p->materials, name);
    if (bd->material < 0) {
        spm_errorf(p->err, "%s: unknown material '%s' (define it with 'material %s ...' first)",
                   where, name, name);
        return 1;
    }
    (*nbinds)++;
    return 0;
}

/* material NAME (the lexer after 'material'). */
static int mesh_material(parser *p, int *material)
{
    char where[600], name[SPM_NAME_MAX];
    where_now(p, where, sizeof where);
    if (spm_lex_name(&p->lx, "a material name", name, sizeof name, p->err))
        return 1;
    if ((*material = spm_names_get(&p->materials, name)) < 0) {
        spm_errorf(p->err, "%s: unknown material '%s' (define it with 'material %s ...' first)",
                   where, name, name);
        return 1;
    }
    return 0;
}

/* scale S | scale SX SY SZ (the lexer after 'scale'), applied after m. */
static int mesh_scale(parser *p, double m[3][4])
{
    char where[600];
    double s[3];
    where_now(p, where, sizeof where);
    if (spm_lex_number(&p->lx, "a scale", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, &s[0],
                       p->err))
        return 1;
    s[1] = s[2] = s[0];
    if (spm_lex_is_number(&p->lx) &&
        (spm_lex_number(&p->lx, "a scale", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, &s[1],
                        p->err) ||
         spm_lex_number(&p->lx, "a scale", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, &s[2],
                        p->err)))
        return 1;
    if (s[0] == 0 || s[1] == 0 || s[2] == 0) {
        spm_errorf(p->err, "%s: a scale must not be zero (it flattens the mesh)", where);
        return 1;
    }
    spm_mesh_scale(m, s);
    return 0;
}

/* rotate AX AY AZ DEGREES (the lexer after 'rotate'), applied after m. */
static int mesh_rotate(parser *p, double m[3][4])
{
    char where[600];
    double axis[3], deg;
    where_now(p, where, sizeof where);
    if (vec3(p, "a rotation axis component", -HUGE_VAL, HUGE_VAL, axis) ||
        spm_lex_number(&p->lx, "an angle in degrees", -1e6, 1e6, &deg, p->err))
        return 1;
    double len = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if (!(len > 0 && isfinite(len))) {
        spm_errorf(p->err, "%s: the rotation axis must be a non-zero vector", where);
        return 1;
    }
    spm_mesh_rotate(m, axis, deg);
    return 0;
}

/* translate X Y Z (the lexer after 'translate'), applied after m. */
static int mesh_translate(parser *p, double m[3][4])
{
    double t[3];
    if (vec3(p, "a translation component", -SPM_SCENE_MAX_COORD, SPM_SCENE_MAX_COORD, t))
        return 1;
    spm_mesh_translate(m, t);
    return 0;
}

/* The mesh file's path (relative to the scene's folder, where the path rule
 * allows), existing and of a format the importer reads. */
static int mesh_path(parser *p, const char *file, const char *fwhere, spm_file *path)
{
    if (spm_path_check(p->dir, file, fwhere, path, p->err))
        return 1;
    if (!file_exists(path->path)) {
        spm_errorf(p->err, "%s: mesh file '%s' not found (or not a regular file; looked for %s)",
                   fwhere, file, path->shown);
        return 1;
    }
    const char *dot = strrchr(file, '.');
    static const char *exts[] = {".obj", ".ply", ".gltf", ".glb", ".stl", ".dae", ".fbx"};
    for (size_t i = 0; dot && i < sizeof exts / sizeof exts[0]; i++)
        if (strcasecmp(dot, exts[i]) == 0)
            return 0;
    spm_errorf(p->err, "%s: mesh file '%s': unknown format (the name must end in .obj, .ply, "
                       ".gltf, .glb, .stl, .dae or .fbx)", fwhere, file);
    return 1;
}

/* The smooth clause's crease: SPM_MESH_DEFAULT_CREASE unless `crease DEG`
 * (given at crease_line) says otherwise; a crease without `smooth` is an error. */
static int mesh_crease(parser *p, spm_mesh_opts *o, int crease_line, const char *where)
{
    if (crease_line && o->shading != SPM_MESH_SHADE_SMOOTH) {
        spm_errorf(p->err, "%s: 'crease' (line %d) applies to the normals 'smooth' computes: "
                           "add 'smooth'", where, crease_line);
        return 1;
    }
    if (!crease_line)
        o->crease = SPM_MESH_DEFAULT_CREASE;
    return 0;
}

/* mesh FILE [material NAME] [bind FILE_MATERIAL NAME]... [smooth | flat] [crease DEG]
 * [scale S | scale SX SY SZ]... [rotate AX AY AZ DEGREES]... [translate X Y Z]...:
 * clauses in any order, the transforms applied in the order written. */
static int stmt_mesh(parser *p)
{
    char where[600], fwhere[600], file[SPM_TOK_MAX];
    spm_file path;
    int line = p->kw_line;
    where_keyword(p, where, sizeof where);
    where_now(p, fwhere, sizeof fwhere);
    if (spm_lex_path(&p->lx, "a mesh file name", file, sizeof file, p->err))
        return 1;
    int rc = 0, nbinds = 0, have_material = 0, crease_line = 0;
    spm_mesh_bind *binds = NULL;
    spm_mesh_opts o = {.material = -1, .line = line};
    spm_mesh_identity(o.m);
    while (!rc && p->lx.type != SPM_TOK_NEWLINE && p->lx.type != SPM_TOK_EOF) {
        if (spm_lex_is(&p->lx, "bind")) {
            rc = mesh_bind(p, &binds, &nbinds);
            continue;
        }
        if (spm_lex_is(&p->lx, "crease") && !crease_line) {
            crease_line = p->lx.tline;
            rc = spm_lex_next(&p->lx, p->err) ||
                 spm_lex_number(&p->lx, "a crease angle in degrees", 1, 180, &o.crease, p->err);
            continue;
        }
        int sh = spm_lex_is(&p->lx, "smooth") ? SPM_MESH_SHADE_SMOOTH
                 : spm_lex_is(&p->lx, "flat") ? SPM_MESH_SHADE_FLAT : 0;
        if (sh && !o.shading) {
            o.shading = sh;
            rc = spm_lex_next(&p->lx, p->err);
            continue;
        }
        int k = spm_lex_is(&p->lx, "scale") ? 1 : spm_lex_is(&p->lx, "rotate") ? 2
                : spm_lex_is(&p->lx, "translate") ? 3
                : spm_lex_is(&p->lx, "material") && !have_material ? 0 : -1;
        if (k < 0) {
            rc = spm_lex_expected(&p->lx, p->err, "'material' (once), 'bind', 'smooth' or "
                                                  "'flat' (once), 'crease' (once), 'scale', "
                                                  "'rotate' or 'translate'");
            break;
        }
        have_material |= k == 0;
        rc = spm_lex_next(&p->lx, p->err) ||
             (k == 0   ? mesh_material(p, &o.material)
              : k == 1 ? mesh_scale(p, o.m)
              : k == 2 ? mesh_rotate(p, o.m)
                       : mesh_translate(p, o.m));
    }
    rc = rc || mesh_crease(p, &o, crease_line, where) || mesh_path(p, file, fwhere, &path) ||
         spm_lex_end_of_statement(&p->lx, p->err);
    if (!rc) {
        spm_mesh_data d;
        o.binds = binds;
        o.nbinds = nbinds;
        rc = spm_mesh_import(&path, &d, p->err);
        if (rc && !spm_stop_requested()) { /* say which statement */
            spm_error inner = *p->err;
            spm_errorf(p->err, "%s: mesh %.900s", where, inner.msg);
        }
        if (!rc) {
            spm_mesh_obj_mtl_check(&path, where, &d);
            rc = spm_mesh_add(&p->b, &p->meshes, &d, &o, path.shown, where, p->err);
        }
        spm_mesh_free(&d);
    }
    free(binds);
    return rc;
}

/* background up|down|both SPECTRUM, background map FILE ... (envmap.h) or
 * background sky ... (sky.h), which are both */
static int stmt_background(parser *p)
{
    int dir = spm_lex_is(&p->lx, "up") ? 0 : spm_lex_is(&p->lx, "down") ? 1
              : spm_lex_is(&p->lx, "both") || spm_lex_is(&p->lx, "map") ||
                        spm_lex_is(&p->lx, "sky") ? 2 : -1;
    if (dir < 0)
        return spm_lex_expected(&p->lx, p->err, "'up', 'down', 'both', 'map' or 'sky'");
    for (int k = 0; k < 2; k++)
        if ((dir == k || dir == 2) && p->bg_line[k]) {
            char where[600];
            where_now(p, where, sizeof where);
            spm_errorf(p->err, "%s: background %s given twice (first at line %d)", where,
                       k ? "down" : "up", p->bg_line[k]);
            return 1;
        }
    int line = p->lx.tline;
    if (spm_lex_is(&p->lx, "map")) {
        p->bg_line[0] = p->bg_line[1] = line;
        return spm_envmap_statement(p->b.s, &p->lx, p->dir, p->err);
    }
    if (spm_lex_is(&p->lx, "sky")) {
        p->bg_line[0] = p->bg_line[1] = line;
        return spm_sky_statement(p->b.s, &p->lx, p->err);
    }
    if (spm_lex_next(&p->lx, p->err))
        return 1;
    int c = colour_ref(p, SPM_KIND_EMISSION);
    if (c < 0)
        return 1;
    if (dir != 1) {
        p->b.s->bg_up = c;
        p->bg_line[0] = line;
    }
    if (dir != 0) {
        p->b.s->bg_down = c;
        p->bg_line[1] = line;
    }
    return spm_lex_end_of_statement(&p->lx, p->err);
}

static int stmt_tri(parser *p)
{
    return stmt_polygon(p, 3);
}

static int stmt_quad(parser *p)
{
    return stmt_polygon(p, 4);
}

/* include FILE: FILE's statements, as if written here. FILE is relative to
 * this file's folder, where the path rule allows (paths.h); an included file
 * may include others, but not one that is being read (a cycle). */
static int stmt_include(parser *p)
{
    char where[600], file[SPM_TOK_MAX], dir[sizeof p->dir];
    where_keyword(p, where, sizeof where);
    spm_file inc;
    if (spm_lex_path(&p->lx, "an included file's name", file, sizeof file, p->err) ||
        spm_lex_end_of_statement(&p->lx, p->err) ||
        spm_path_check(p->dir, file, where, &inc, p->err))
        return 1;
    if (!file_exists(inc.path)) {
        spm_errorf(p->err, "%s: included file '%s' not found (or not a regular file; looked for "
                           "%s)", where, file, inc.shown);
        return 1;
    }
    for (int i = 0; i < p->nreading; i++)
        if (!strcmp(p->reading[i], inc.path)) {
            spm_errorf(p->err, "%s: include '%s': a cycle (that file is being read already)",
                       where, file);
            return 1;
        }
    if (p->nreading == SPM_INCLUDE_DEPTH) {
        spm_errorf(p->err, "%s: include '%s': more than %d files deep", where, file,
                   SPM_INCLUDE_DEPTH);
        return 1;
    }
    spm_lexer outer = p->lx;
    memcpy(dir, p->dir, sizeof dir);
    spm_path_dir(inc.shown, p->dir, sizeof p->dir);
    p->reading[p->nreading++] = spm_xstrdup(inc.path);
    int rc = spm_lex_open(&p->lx, &inc, p->err) || read_statements(p);
    if (rc && !spm_stop_requested()) { /* say where it was included */
        spm_error inner = *p->err;
        spm_errorf(p->err, "%.800s (included at %s)", inner.msg, where);
    }
    spm_lex_close(&p->lx);
    p->lx = outer;
    memcpy(p->dir, dir, sizeof dir);
    free(p->reading[--p->nreading]);
    return rc;
}

/* The statements: a keyword and its parser, which starts on the token after
 * the keyword (the keyword's position is p->kw_line, p->kw_col). The order is
 * the one the error for an unknown statement lists them in. */
/* texture NAME FILE|checker ... (scene_texture.h) */
static int stmt_texture(parser *p)
{
    return spm_scene_texture_statement(&p->textures, &p->lx, p->dir, p->err);
}

static const struct {
    const char *keyword;
    int (*parse)(parser *p);
} statements[] = {
    {"image", stmt_image},   {"spp", stmt_spp},   {"camera", stmt_camera},
    {"spectrum", stmt_spectrum}, {"material", stmt_material}, {"tri", stmt_tri},
    {"quad", stmt_quad},     {"mesh", stmt_mesh}, {"background", stmt_background},
    {"include", stmt_include}, {"texture", stmt_texture}, {"light", stmt_light},
};
#define NSTATEMENTS ((int)(sizeof statements / sizeof statements[0]))

static int statement(parser *p)
{
    spm_lexer *lx = &p->lx;
    for (int i = 0; i < NSTATEMENTS; i++)
        if (spm_lex_is(lx, statements[i].keyword)) {
            p->kw_line = lx->tline;
            p->kw_col = lx->tcol;
            return spm_lex_next(lx, p->err) || statements[i].parse(p);
        }
    char what[256] = "a statement (";
    for (int i = 0, n = (int)strlen(what); i < NSTATEMENTS; i++)
        n += snprintf(what + n, sizeof what - (size_t)n, "%s%s", statements[i].keyword,
                      i + 1 < NSTATEMENTS ? ", " : ")");
    return spm_lex_expected(lx, p->err, what);
}

static void parser_free(parser *p)
{
    for (int i = 0; i < p->ndefs; i++) {
        free(p->defs[i].wl);
        free(p->defs[i].val);
        free(p->defs[i].made[0]);
        free(p->defs[i].made[1]);
    }
    free(p->defs);
    spm_names_free(&p->spectra);
    spm_names_free(&p->materials);
    spm_mesh_cache_free(&p->meshes);
    spm_scene_textures_free(&p->textures);
    spm_lex_close(&p->lx);
    for (int i = 0; i < p->nreading; i++)
        free(p->reading[i]);
}

static int finish(parser *p)
{
    char where[600];
    where_now(p, where, sizeof where);
    if (!p->image_line)
        return spm_lex_expected(&p->lx, p->err, "an 'image WIDTH HEIGHT' statement");
    if (!p->camera_line)
        return spm_lex_expected(&p->lx, p->err,
                                "a 'camera position X Y Z direction X Y Z fov DEGREES' statement");
    for (int i = 0; i < p->ndefs; i++)
        if (!p->defs[i].used)
            spm_warnf("%s: spectrum '%s' is never used", p->defs[i].where, p->defs[i].name);
    spm_scene_textures_unused(&p->textures);
    if (p->b.s->ntextures && /* the textures' colours: of what is left, before derived ones */
        (spm_sb_prune(&p->b, where, p->err) || spm_sb_texture_palette(&p->b, where, p->err)))
        return 1;
    return spm_sb_finish(&p->b, where, p->err);
}

int spm_scene_parse_text(const spm_file *file, spm_scene *out, spm_error *err)
{
    const char *path = file->shown;
    parser p;
    memset(&p, 0, sizeof p);
    p.err = err;
    spm_names_init(&p.spectra);
    spm_names_init(&p.materials);
    spm_mesh_cache_init(&p.meshes);
    spm_scene_textures_init(&p.textures);
    spm_sb_init(&p.b, out, path);
    const char *slash = strrchr(path, '/');
    if (slash)
        snprintf(p.dir, sizeof p.dir, "%.*s", (int)(slash - path), path);
    else
        snprintf(p.dir, sizeof p.dir, ".");
    if (slash == path)
        snprintf(p.dir, sizeof p.dir, "/");
    p.reading[p.nreading++] = spm_xstrdup(file->path);
    int rc = spm_lex_open(&p.lx, file, err) || read_statements(&p);
    if (!rc)
        rc = finish(&p);
    parser_free(&p);
    spm_sb_done(&p.b, !rc);
    return rc;
}
