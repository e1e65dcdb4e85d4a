/* Mitsuba 3 XML scenes (docs/MITSUBA.md): the walk over the document's
 * top-level elements. Elements with an id are definitions that a <ref>
 * names; shapes carry their BSDF and area emitter (child or ref); the
 * other emitters go by the table below, one line each; the sensor, its
 * film and sampler, and the integrator give the camera and the options. */
#include "mitsuba.h"
#include "mesh.h"
#include "materials.h"
#include "scene_parsers.h"
#include "envmap.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    spm_scene_builder b;
    mi_spectra ms;
    mi_doc doc;
    mi_ids ids;
    spm_mesh_cache cache;
    spm_error *err;
    int bg_set;
    mi_node **made;               /* BSDFs made, one material each (refs share it) */
    spm_scene_material *protos;
    int nmade;
} mi_parser;

typedef int (*mi_emitter_fn)(mi_parser *p, mi_node *e, const char *what);

static int emitter_constant(mi_parser *p, mi_node *e, const char *what);
static int emitter_point(mi_parser *p, mi_node *e, const char *what);
static int emitter_spot(mi_parser *p, mi_node *e, const char *what);
static int emitter_directional(mi_parser *p, mi_node *e, const char *what);
static int emitter_envmap(mi_parser *p, mi_node *e, const char *what);

/* Mitsuba's emitters and what specmip does with each: a function that
 * renders it, or why it is warned about (area lights go with their shape). */
static const struct {
    const char *type;
    mi_emitter_fn fn;
    const char *why;
} emitter_types[] = {
    {"constant", emitter_constant, NULL},
    {"point", emitter_point, NULL},
    {"spot", emitter_spot, NULL},
    {"directional", emitter_directional, NULL},
    {"envmap", emitter_envmap, NULL},
    {"sunsky", NULL, "sky models are not rendered"},
    {"projector", NULL, "projectors are not rendered"},
    {"directionalarea", NULL, "directional area lights are not rendered"},
};

static void what_of(const mi_node *n, char *w, size_t size)
{
    const char *t = mi_attr(n, "type");
    snprintf(w, size, "<%s type=\"%.40s\">", n->tag, t ? t : "");
}

static int collect_ids(mi_parser *p, mi_node *n)
{
    const char *id = mi_attr(n, "id");
    if (id && strcmp(n->tag, "ref")) {
        int i = spm_names_get(&p->ids.ids, id);
        if (i >= 0) {
            spm_errorf(p->err, "%s: id \"%s\" is given twice (first at %s)", n->where, id,
                       p->ids.nodes[i]->where);
            return 1;
        }
        p->ids.nodes = spm_xrealloc(p->ids.nodes, (size_t)(p->ids.n + 1) * sizeof n);
        p->ids.nodes[p->ids.n] = n;
        spm_names_put(&p->ids.ids, id, p->ids.n++);
    }
    for (int i = 0; i < n->nkids; i++)
        if (collect_ids(p, n->kids[i]))
            return 1;
    return 0;
}

/* The child (or ref) of shape s that is a `tag` element; NULL when none. */
static mi_node *part(mi_parser *p, mi_node *s, const char *tag, int *bad)
{
    for (int i = 0; i < s->nkids; i++) {
        mi_node *k = s->kids[i], *t = k;
        if (!strcmp(k->tag, "ref")) {
            if (!(t = mi_ref(&p->ids, k, p->err))) {
                *bad = 1;
                return NULL;
            }
        }
        if (!strcmp(t->tag, tag)) {
            k->used = t->used = 1;
            return t;
        }
    }
    return NULL;
}

/* The shape's material: its BSDF, and its area emitter's radiance. */
static int shape_material(mi_parser *p, mi_node *s, const char *where)
{
    int bad = 0;
    mi_node *bsdf = part(p, s, "bsdf", &bad);
    mi_node *em = bad ? NULL : part(p, s, "emitter", &bad);
    if (bad)
        return -1;
    spm_scene_material m;
    int i = 0;
    while (i < p->nmade && p->made[i] != bsdf)
        i++;
    if (i < p->nmade) {
        m = p->protos[i];
    } else {
        if (bsdf ? mi_bsdf_make(&p->ms, &p->ids, bsdf, &m, p->err)
                 : (mi_bsdf_default(&p->ms, &m), 0))
            return -1;
        p->made = spm_xrealloc(p->made, (size_t)(p->nmade + 1) * sizeof *p->made);
        p->protos = spm_xrealloc(p->protos, (size_t)(p->nmade + 1) * sizeof *p->protos);
        p->made[p->nmade] = bsdf;
        p->protos[p->nmade++] = m;
    }
    if (em) {
        const char *t = mi_attr(em, "type");
        char w[128];
        what_of(em, w, sizeof w);
        if (!t || strcmp(t, "area")) {
            spm_errorf(p->err, "%s: %s inside a shape: a shape's emitter is \"area\"", em->where,
                       w);
            return -1;
        }
        m.emit = mi_colour(&p->ms, em, "radiance", MI_RADIANCE, -3, p->err);
        if (m.emit == -3)
            spm_errorf(p->err, "%s: %s needs a 'radiance'", em->where, w);
        if (m.emit < -1 || mi_unused(em, w, p->err))
            return -1;
        m.etype = SPM_EMIT_AREA;
        char name[SPM_NAME_MAX];
        snprintf(name, sizeof name, "%.50s (light)", m.name);
        snprintf(m.name, sizeof m.name, "%s", name);
    }
    return spm_sb_material_typed(&p->b, &m, where, p->err);
}

static int do_shape(mi_parser *p, mi_node *s)
{
    char what[128];
    what_of(s, what, sizeof what);
    const char *type = mi_attr(s, "type");
    spm_mesh_data d;
    double m[4][4];
    int smooth;
    int made = mi_shape_make(&p->doc, s, type ? type : "", &d, &smooth, m, p->err);
    if (made == 2) {
        for (int k = 0; k < s->nkids; k++)
            s->kids[k]->used = 1;
        return pbrt_warn(s->where, what, "a shape type specmip does not read yet", p->err);
    }
    if (made)
        return 1;
    int mat = shape_material(p, s, s->where);
    int rc = mat < 0;
    if (!rc) {
        spm_mesh_opts o = {.material = mat,
                           .shading = smooth ? SPM_MESH_SHADE_SMOOTH : SPM_MESH_SHADE_DEFAULT};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++)
                o.m[i][j] = m[i][j];
        rc = spm_mesh_add(&p->b, &p->cache, &d, &o, what, s->where, p->err) ||
             mi_unused(s, what, p->err);
    }
    spm_mesh_free(&d);
    return rc;
}

/* constant: a uniform background, both halves. */
static int emitter_constant(mi_parser *p, mi_node *e, const char *what)
{
    int c = mi_colour(&p->ms, e, "radiance", MI_RADIANCE, -3, p->err);
    if (c == -3) { /* Mitsuba's default radiance: 1 */
        spm_spectrum one;
        spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &one);
        c = spm_sb_colour(&p->b, "constant 1", &one, e->where, p->err);
    }
    if (c < -1)
        return 1;
    if (p->bg_set++ && pbrt_warn(e->where, "a second <emitter type=\"constant\">",
                                 "the last one is the background", p->err))
        return 1;
    p->b.s->bg_up = p->b.s->bg_down = c;
    spm_envmap_free(p->b.s->env); /* a map before it */
    p->b.s->env = NULL;
    return mi_unused(e, what, p->err);
}

/* A light's colour from its spectrum `name` (default 1, Mitsuba's), lifted
 * as a radiance is (mi_colour), so its factor is 1: the colour's index, -1
 * for a zero (no light), < -1 on an error. */
static int light_colour(mi_parser *p, mi_node *e, const char *name)
{
    int c = mi_colour(&p->ms, e, name, MI_RADIANCE, -3, p->err);
    if (c == -3) {
        spm_spectrum one;
        spm_spectrum_constant(1.0, SPM_KIND_EMISSION, &one);
        c = spm_sb_colour(&p->b, "intensity 1", &one, e->where, p->err);
    }
    return c;
}

/* light l into the scene, e's other properties warned about */
static int add_light(mi_parser *p, mi_node *e, const char *what, spm_scene_light *l)
{
    l->p[SPM_LIGHT_P_SCALE] = 1.0f;
    snprintf(l->where, sizeof l->where, "%.127s", e->where);
    spm_scene *s = p->b.s;
    s->lights = spm_xrealloc(s->lights, ((size_t)s->nlights + 1) * sizeof *s->lights);
    s->lights[s->nlights++] = *l;
    return mi_unused(e, what, p->err);
}

/* to_world's origin into l's position and its +z axis (unit) into its
 * direction */
static void light_frame(double m[4][4], const double at[3], spm_scene_light *l)
{
    double pos[3], z[3] = {m[0][2], m[1][2], m[2][2]};
    pbrt_mat_apply(m, at, 1.0, pos);
    double n = sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int i = 0; i < 3; i++) {
        l->p[SPM_LIGHT_P_POS + i] = (float)pos[i];
        l->p[SPM_LIGHT_P_DIR + i] = (float)(n > 0.0 ? z[i] / n : 0.0);
    }
}

/* point: specmip's point light (scene.h spm_scene_light), at `position`
 * or to_world's origin, its `intensity` (W/sr) the light's colour. */
static int emitter_point(mi_parser *p, mi_node *e, const char *what)
{
    int bad = 0;
    double m[4][4], at[3] = {0, 0, 0};
    mi_node *k = mi_prop(e, "position", "point", &bad, p->err);
    const char *xyz[3] = {"x", "y", "z"};
    if (bad || (k && mi_vec3(k, xyz, "value", at, p->err)) || mi_to_world(e, m, p->err))
        return 1;
    int c = light_colour(p, e, "intensity");
    if (c < -1)
        return 1;
    if (c == -1) /* a zero intensity: no light */
        return mi_unused(e, what, p->err);
    spm_scene_light l = {.kind = SPM_LIGHT_POINT, .colour = c};
    light_frame(m, at, &l);
    return add_light(p, e, what, &l);
}

/* spot: specmip's spot light, at to_world's origin along its +z, the same
 * falloff (linear in angle from beam_width to cutoff_angle, degrees,
 * defaults 3/4 of the cutoff and 20), its `intensity` the colour. */
static int emitter_spot(mi_parser *p, mi_node *e, const char *what)
{
    int bad = 0;
    double m[4][4], at[3] = {0, 0, 0};
    double cut = mi_float(e, "cutoff_angle", 20.0, &bad, p->err);
    double beam = bad ? 0.0 : mi_float(e, "beam_width", 0.75 * cut, &bad, p->err);
    if (bad || mi_to_world(e, m, p->err))
        return 1;
    if (!(cut > 0.0 && cut <= 90.0) || !(beam >= 0.0 && beam <= cut)) {
        spm_errorf(p->err, "%s: %s: cutoff_angle %g must be above 0 and at most 90 degrees, "
                   "beam_width %g from 0 to it", e->where, what, cut, beam);
        return 1;
    }
    int c = light_colour(p, e, "intensity");
    if (c < -1)
        return 1;
    if (c == -1)
        return mi_unused(e, what, p->err);
    spm_scene_light l = {.kind = SPM_LIGHT_SPOT, .colour = c};
    light_frame(m, at, &l);
    l.p[SPM_LIGHT_P_A] = (float)(cut * M_PI / 180.0);
    l.p[SPM_LIGHT_P_B] = (float)(beam * M_PI / 180.0);
    l.p[SPM_LIGHT_P_C] = (float)cos(cut * M_PI / 180.0);
    return add_light(p, e, what, &l);
}

/* directional: specmip's distant light, travelling along `direction` or
 * to_world's +z, its `irradiance` the colour. */
static int emitter_directional(mi_parser *p, mi_node *e, const char *what)
{
    int bad = 0;
    double m[4][4], dir[3];
    mi_node *k = mi_prop(e, "direction", "vector", &bad, p->err);
    const char *xyz[3] = {"x", "y", "z"};
    if (bad || (k && mi_vec3(k, xyz, "value", dir, p->err)) || mi_to_world(e, m, p->err))
        return 1;
    int c = light_colour(p, e, "irradiance");
    if (c < -1)
        return 1;
    if (c == -1)
        return mi_unused(e, what, p->err);
    spm_scene_light l = {.kind = SPM_LIGHT_DISTANT, .colour = c};
    double d[3] = {m[0][2], m[1][2], m[2][2]};
    for (int i = 0; k && i < 3; i++)
        d[i] = dir[i];
    double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(n > 0.0) || !isfinite(n)) {
        spm_errorf(p->err, "%s: %s: its direction is zero", e->where, what);
        return 1;
    }
    for (int i = 0; i < 3; i++)
        l.p[SPM_LIGHT_P_DIR + i] = (float)(d[i] / n);
    return add_light(p, e, what, &l);
}

/* envmap: specmip's environment map (envmap.h), whose convention is
 * Mitsuba's; `filename` through the path rule, `scale` (default 1), and
 * to_world's turn about +y: any other part of it (a tilt, a mirror, a
 * scale) is warned about by name and left out. */
static int emitter_envmap(mi_parser *p, mi_node *e, const char *what)
{
    int bad = 0;
    double m[4][4];
    const char *fn = mi_string(e, "filename", NULL, &bad, p->err);
    double scale = mi_float(e, "scale", 1.0, &bad, p->err);
    if (bad || mi_to_world(e, m, p->err))
        return 1;
    if (!fn) {
        spm_errorf(p->err, "%s: %s needs a 'filename'", e->where, what);
        return 1;
    }
    double rot = atan2(m[0][2], m[0][0]), c = cos(rot), sn = sin(rot), off = 0.0;
    double want[3][3] = {{c, 0, sn}, {0, 1, 0}, {-sn, 0, c}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            off = fmax(off, fabs(m[i][j] - want[i][j]));
    if (off > 1e-6 && pbrt_warn(e->where, "to_world of an <emitter type=\"envmap\"> other than "
                                "a turn about +y", "its turn about +y alone is rendered", p->err))
        return 1;
    if (p->bg_set++ && pbrt_warn(e->where, "a second background emitter",
                                 "the last one is the background", p->err))
        return 1;
    spm_file f;
    if (mi_file(&p->doc, mi_prop(e, "filename", "string", &bad, p->err), fn, &f, p->err) ||
        spm_envmap_load(p->b.s, &f, scale, rot * 180.0 / M_PI, e->where, p->err))
        return 1;
    p->b.s->bg_up = p->b.s->bg_down = -1;
    return mi_unused(e, what, p->err);
}

static int do_emitter(mi_parser *p, mi_node *e)
{
    char what[128];
    what_of(e, what, sizeof what);
    const char *t = mi_attr(e, "type");
    if (t && !strcmp(t, "area"))
        return 0; /* a definition for shapes' refs */
    for (size_t i = 0; t && i < sizeof emitter_types / sizeof emitter_types[0]; i++)
        if (!strcmp(emitter_types[i].type, t)) {
            if (emitter_types[i].fn)
                return emitter_types[i].fn(p, e, what);
            for (int k = 0; k < e->nkids; k++)
                e->kids[k]->used = 1;
            return pbrt_warn(e->where, what, emitter_types[i].why, p->err);
        }
    spm_errorf(p->err, "%s: unknown emitter type \"%s\"", e->where, t ? t : "");
    return 1;
}

static int walk(mi_parser *p, int *have_sensor)
{
    mi_node *root = p->doc.root;
    root->used = 1;
    for (int i = 0; i < root->nkids; i++) {
        mi_node *n = root->kids[i];
        int rc = 0;
        if (n->used)
            continue;
        n->used = 1;
        if (!strcmp(n->tag, "shape"))
            rc = do_shape(p, n);
        else if (!strcmp(n->tag, "emitter"))
            rc = do_emitter(p, n);
        else if (!strcmp(n->tag, "sensor"))
            rc = (*have_sensor)++ ? pbrt_warn(n->where, "a second <sensor>", "the first one "
                                                                             "renders", p->err)
                                  : mi_sensor(n, &p->b, p->err);
        else if (!strcmp(n->tag, "integrator"))
            rc = mi_integrator(n, p->err);
        else if (!strcmp(n->tag, "bsdf") && mi_attr(n, "id"))
            n->used = 0; /* a definition: read where a ref names it */
        else {
            char what[128];
            what_of(n, what, sizeof what);
            rc = pbrt_warn(n->where, what, "not rendered", p->err);
        }
        if (rc)
            return 1;
    }
    return 0;
}

int spm_scene_parse_mitsuba(const spm_file *file, spm_scene *out, spm_error *err)
{
    mi_parser p = {.err = err};
    spm_sb_init(&p.b, out, file->shown);
    p.ms.sp.b = &p.b;
    p.ms.sp.err = err;
    p.ms.doc = &p.doc;
    spm_names_init(&p.ms.sp.rgb_fits);
    spm_names_init(&p.ids.ids);
    spm_mesh_cache_init(&p.cache);
    int have_sensor = 0;
    int rc = mi_doc_read(file, &p.doc, err);
    if (!rc) {
        const char *v = mi_attr(p.doc.root, "version");
        if (v && atoi(v) < 2 &&
            pbrt_warn(p.doc.root->where, "<scene version=\"0.x\">",
                      "Mitsuba 0.6's parameter names are read as Mitsuba 3's", err))
            rc = 1;
    }
    rc = rc || collect_ids(&p, p.doc.root) || walk(&p, &have_sensor);
    if (!rc && !have_sensor) /* Mitsuba's default sensor */
        rc = mi_sensor(NULL, &p.b, err);
    if (!rc)
        pbrt_warn_summary();
    char where[SPM_PATH_MAX + 8];
    snprintf(where, sizeof where, "%s", file->shown);
    rc = rc || spm_sb_finish(&p.b, where, err);
    mi_doc_free(&p.doc);
    spm_names_free(&p.ms.sp.rgb_fits);
    spm_names_free(&p.ids.ids);
    free(p.ids.nodes);
    free(p.made);
    free(p.protos);
    spm_mesh_cache_free(&p.cache);
    pbrt_warn_reset();
    spm_sb_done(&p.b, !rc);
    return rc;
}
