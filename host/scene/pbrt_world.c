/* The world: materials (named and current), area lights, shapes and object
 * instances, added to the scene through the mesh builder (mesh_build.c) with
 * the current transform (LightSource: pbrt_lights.c); textures are warned
 * about. */
#include "pbrt_parser.h"
#include "materials.h"
#include <stdlib.h>
#include <string.h>

static int add_proto(pbrt_parser *p, const spm_scene_material *m)
{
    p->protos = spm_xrealloc(p->protos, (size_t)(p->nprotos + 1) * sizeof *p->protos);
    p->protos[p->nprotos] = *m;
    return p->nprotos++;
}

static int dir_material(pbrt_parser *p, const char *where)
{
    char type[64];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a material type", type, sizeof type) || pbrt_arg_params(p, &ps))
        return 1;
    spm_scene_material m;
    int rc = pbrt_material_make(&p->sp, type, &ps, where, &m, p->err);
    pbrt_params_free(&ps);
    if (rc)
        return 1;
    snprintf(m.name, sizeof m.name, "%.40s@%d", type, pbrt_lx(p)->tline);
    p->gs.mat = add_proto(p, &m);
    return 0;
}

static int dir_make_named(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a material name", name, sizeof name) || pbrt_arg_params(p, &ps))
        return 1;
    int bad = 0, rc = 1;
    const char *type = pbrt_param_string(&ps, "type", NULL, &bad, p->err);
    spm_scene_material m;
    if (!bad && !type)
        spm_errorf(p->err, "%s: MakeNamedMaterial \"%s\" needs a 'string type'", where, name);
    else if (!bad && spm_names_get(&p->named_mats, name) >= 0)
        spm_errorf(p->err, "%s: named material \"%s\" is defined twice", where, name);
    else if (!bad)
        rc = pbrt_material_make(&p->sp, type, &ps, where, &m, p->err);
    pbrt_params_free(&ps);
    if (rc)
        return 1;
    snprintf(m.name, sizeof m.name, "%s", name);
    spm_names_put(&p->named_mats, name, add_proto(p, &m));
    return 0;
}

static int dir_named_material(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    if (pbrt_arg_string(p, "a material name", name, sizeof name))
        return 1;
    int i = spm_names_get(&p->named_mats, name);
    if (i < 0) {
        spm_errorf(p->err, "%s: NamedMaterial \"%s\": no MakeNamedMaterial defines it (before "
                           "this line)", where, name);
        return 1;
    }
    p->gs.mat = i;
    return 0;
}

static int dir_texture(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX], cls[32], type[64], what[128];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a texture name", name, sizeof name) ||
        pbrt_arg_string(p, "a texture class (\"spectrum\" or \"float\")", cls, sizeof cls) ||
        pbrt_arg_string(p, "a texture type", type, sizeof type) || pbrt_arg_params(p, &ps))
        return 1;
    snprintf(what, sizeof what, "Texture \"%.40s\"", type);
    int rc = pbrt_warn(where, what, "textures are not rendered yet (materials that use one take "
                                    "their default)", p->err);
    pbrt_params_free(&ps);
    return rc;
}

static int dir_light(pbrt_parser *p, const char *where)
{
    char type[64];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a light type", type, sizeof type) || pbrt_arg_params(p, &ps))
        return 1;
    int rc = pbrt_light_make(p, type, &ps, where);
    pbrt_params_free(&ps);
    return rc;
}

/* AreaLightSource "diffuse": L (default the colour space's white), scale,
 * twosided; pbrt-v4 normalises a spectrum L to luminance 1 before scale. */
static int dir_area_light(pbrt_parser *p, const char *where)
{
    char type[64];
    pbrt_params ps;
    if (pbrt_arg_string(p, "an area light type", type, sizeof type) || pbrt_arg_params(p, &ps))
        return 1;
    int bad = 0, rc = 0;
    if (strcmp(type, "diffuse")) {
        spm_errorf(p->err, "%s: unknown area light type \"%s\" (pbrt-v4 has \"diffuse\")", where,
                   type);
        pbrt_params_free(&ps);
        return 1;
    }
    double scale = pbrt_param_float(&ps, "scale", 1.0, &bad, p->err);
    int two = pbrt_param_bool(&ps, "twosided", 0, &bad, p->err);
    if (bad || !(scale >= 0)) {
        if (!bad)
            spm_errorf(p->err, "%s: a negative scale %g", where, scale);
        rc = 1;
    }
    if (!rc) {
        p->gs.area_colour = pbrt_light_colour(p, &ps, "L", scale, where);
        p->gs.area_twosided = two;
        rc = p->gs.area_colour < -1;
    }
    rc = rc || pbrt_params_unused(&ps, "AreaLightSource \"diffuse\"", p->err);
    pbrt_params_free(&ps);
    return rc;
}

/* The current material, with the area light's emission when there is one. */
static int shape_material(pbrt_parser *p, int emit, const char *where)
{
    spm_scene_material m = p->protos[p->gs.mat];
    if (emit && p->gs.area_colour >= 0) {
        m.emit = p->gs.area_colour;
        m.etype = SPM_EMIT_AREA;
        if (p->gs.area_twosided)
            m.flags |= 1u << SPM_AREA_FLAG_TWOSIDED;
        char name[SPM_NAME_MAX];
        snprintf(name, sizeof name, "%.50s (light)", m.name);
        snprintf(m.name, sizeof m.name, "%s", name);
    }
    return spm_sb_material_typed(&p->b, &m, where, p->err);
}

static int add_mesh(pbrt_parser *p, const spm_mesh_data *d, int material, int smooth,
                    const double m[4][4], const char *what, const char *where)
{
    spm_mesh_opts o = {.material = material,
                       .shading = smooth ? SPM_MESH_SHADE_SMOOTH : SPM_MESH_SHADE_DEFAULT,
                       .line = pbrt_lx(p)->tline};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            o.m[i][j] = m[i][j];
    return spm_mesh_add(&p->b, &p->cache, d, &o, what, where, p->err);
}

/* alpha cut-outs: a constant 1 is the default; anything else is warned. */
static int shape_alpha(pbrt_parser *p, pbrt_params *ps, const char *what)
{
    int bad = 0;
    pbrt_param *a = pbrt_param_find(ps, "alpha", 1u << PP_FLOAT | 1u << PP_TEXTURE, &bad, p->err);
    if (bad)
        return 1;
    if (!a || (a->type == PP_FLOAT && a->nnum == 1 && a->num[0] == 1.0))
        return 0;
    char w[160];
    snprintf(w, sizeof w, "%.100s: 'alpha' (a cut-out)", what);
    return pbrt_warn(a->where, w, "the surface is rendered whole", p->err);
}

static int dir_shape(pbrt_parser *p, const char *where)
{
    char type[64], what[128];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a shape type", type, sizeof type) || pbrt_arg_params(p, &ps))
        return 1;
    snprintf(what, sizeof what, "Shape \"%.40s\"", type);
    spm_mesh_data d;
    pbrt_shape_ctx c = {.reverse = p->gs.reverse, .dir = pbrt_lx(p)->dir};
    int rc = shape_alpha(p, &ps, what);
    int made = rc ? 1 : pbrt_shape_make(type, &ps, &c, where, &d, p->err);
    if (made == 2)
        rc = pbrt_warn(where, what, "a shape type specmip does not tessellate yet", p->err);
    else if (made == 1)
        rc = 1;
    for (int k = 0; made == 2 && k < ps.n; k++)
        ps.p[k].used = 1;
    rc = rc || pbrt_params_unused(&ps, what, p->err);
    pbrt_params_free(&ps);
    if (rc || made)
        return made == 0 ? (spm_mesh_free(&d), 1) : rc;
    if (p->cur_obj >= 0) { /* kept for its instances */
        pbrt_object *o = &p->objs[p->cur_obj];
        if (p->gs.area_colour >= 0 &&
            pbrt_warn(where, "an area light inside ObjectBegin",
                      "instances do not emit (as in pbrt-v4)", p->err)) {
            spm_mesh_free(&d);
            return 1;
        }
        int m = shape_material(p, 0, where);
        if (m < 0) {
            spm_mesh_free(&d);
            return 1;
        }
        o->shapes = spm_xrealloc(o->shapes, (size_t)(o->n + 1) * sizeof *o->shapes);
        pbrt_obj_shape *s = &o->shapes[o->n++];
        s->d = d;
        s->material = m;
        s->smooth = c.has_normals;
        memcpy(s->m, p->gs.ctm, sizeof s->m);
        snprintf(s->where, sizeof s->where, "%s", where);
        return 0;
    }
    int m = shape_material(p, 1, where);
    rc = m < 0 || add_mesh(p, &d, m, c.has_normals, p->gs.ctm, what, where);
    spm_mesh_free(&d);
    return rc;
}

static int dir_object_begin(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    if (pbrt_arg_string(p, "an object name", name, sizeof name))
        return 1;
    if (p->cur_obj >= 0) {
        spm_errorf(p->err, "%s: ObjectBegin inside ObjectBegin \"%s\"", where,
                   p->objs[p->cur_obj].name);
        return 1;
    }
    if (spm_names_get(&p->obj_names, name) >= 0) {
        spm_errorf(p->err, "%s: object \"%s\" is defined twice", where, name);
        return 1;
    }
    p->stack = spm_xrealloc(p->stack, (size_t)(p->nstack + 1) * sizeof *p->stack);
    p->stack[p->nstack++] = p->gs; /* ObjectBegin begins an attribute block */
    p->objs = spm_xrealloc(p->objs, (size_t)(p->nobjs + 1) * sizeof *p->objs);
    memset(&p->objs[p->nobjs], 0, sizeof *p->objs);
    snprintf(p->objs[p->nobjs].name, sizeof p->objs[p->nobjs].name, "%s", name);
    spm_names_put(&p->obj_names, name, p->nobjs);
    p->cur_obj = p->nobjs++;
    return 0;
}

static int dir_object_end(pbrt_parser *p, const char *where)
{
    if (p->cur_obj < 0 || p->nstack == 0) {
        spm_errorf(p->err, "%s: ObjectEnd without ObjectBegin", where);
        return 1;
    }
    p->cur_obj = -1;
    p->gs = p->stack[--p->nstack];
    return 0;
}

/* Every shape of the object, its transform the instance's times its own. */
static int dir_object_instance(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    if (pbrt_arg_string(p, "an object name", name, sizeof name))
        return 1;
    int i = spm_names_get(&p->obj_names, name);
    if (i < 0 || i == p->cur_obj) {
        spm_errorf(p->err, "%s: ObjectInstance \"%s\": %s", where, name,
                   i < 0 ? "no ObjectBegin defines it (before this line)"
                         : "inside its own definition");
        return 1;
    }
    const pbrt_object *o = &p->objs[i];
    char what[SPM_NAME_MAX + 32];
    snprintf(what, sizeof what, "ObjectInstance \"%s\"", name);
    for (int k = 0; k < o->n; k++) {
        double m[4][4];
        pbrt_mat_mul(p->gs.ctm, o->shapes[k].m, m);
        if (add_mesh(p, &o->shapes[k].d, o->shapes[k].material, o->shapes[k].smooth, m, what,
                     where))
            return 1;
    }
    return 0;
}

void pbrt_objects_free(pbrt_parser *p)
{
    for (int i = 0; i < p->nobjs; i++) {
        for (int k = 0; k < p->objs[i].n; k++)
            spm_mesh_free(&p->objs[i].shapes[k].d);
        free(p->objs[i].shapes);
    }
    free(p->objs);
    p->objs = NULL;
    p->nobjs = 0;
}

const pbrt_directive pbrt_world_directives[] = {
    {"Material", dir_material},
    {"MakeNamedMaterial", dir_make_named},
    {"NamedMaterial", dir_named_material},
    {"Texture", dir_texture},
    {"LightSource", dir_light},
    {"AreaLightSource", dir_area_light},
    {"Shape", dir_shape},
    {"ObjectBegin", dir_object_begin},
    {"ObjectEnd", dir_object_end},
    {"ObjectInstance", dir_object_instance},
    {NULL, NULL},
};
