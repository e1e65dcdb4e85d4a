/* The graphics state: the current transform and its directives, the
 * attribute stack (AttributeBegin/End saves transform, material, area light
 * and orientation), named coordinate systems. */
#include "pbrt_parser.h"
#include <string.h>

static int concat(pbrt_parser *p, const double m[4][4])
{
    pbrt_mat_mul(p->gs.ctm, m, p->gs.ctm);
    return 0;
}

static int dir_translate(pbrt_parser *p, const char *where)
{
    double t[3], m[4][4];
    (void)where;
    if (pbrt_arg_numbers(p, 3, "a translation", t))
        return 1;
    pbrt_mat_translate(t, m);
    return concat(p, m);
}

static int dir_scale(pbrt_parser *p, const char *where)
{
    double s[3], m[4][4];
    (void)where;
    if (pbrt_arg_numbers(p, 3, "a scale", s))
        return 1;
    pbrt_mat_scale(s, m);
    return concat(p, m);
}

static int dir_rotate(pbrt_parser *p, const char *where)
{
    double a[4], m[4][4];
    if (pbrt_arg_numbers(p, 4, "an angle and an axis", a))
        return 1;
    if (pbrt_mat_rotate(a[0], a + 1, m)) {
        spm_errorf(p->err, "%s: Rotate about a zero axis", where);
        return 1;
    }
    return concat(p, m);
}

static int dir_lookat(pbrt_parser *p, const char *where)
{
    double v[9], m[4][4];
    if (pbrt_arg_numbers(p, 9, "eye, look-at point and up vector", v))
        return 1;
    if (pbrt_mat_lookat(v, v + 3, v + 6, m)) {
        spm_errorf(p->err, "%s: LookAt: the eye is the point looked at, or the up vector is zero "
                           "or along the view", where);
        return 1;
    }
    return concat(p, m);
}

/* 16 numbers, column by column (pbrt's matrices are given transposed). */
static int matrix_arg(pbrt_parser *p, double m[4][4])
{
    double v[16];
    if (pbrt_arg_numbers(p, 16, "a 4x4 matrix", v))
        return 1;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            m[i][j] = v[4 * j + i];
    return 0;
}

static int dir_transform(pbrt_parser *p, const char *where)
{
    (void)where;
    return matrix_arg(p, p->gs.ctm);
}

static int dir_concat(pbrt_parser *p, const char *where)
{
    double m[4][4];
    (void)where;
    return matrix_arg(p, m) || concat(p, m);
}

static int dir_identity(pbrt_parser *p, const char *where)
{
    (void)where;
    pbrt_mat_identity(p->gs.ctm);
    return 0;
}

static int dir_reverse(pbrt_parser *p, const char *where)
{
    (void)where;
    p->gs.reverse = !p->gs.reverse;
    return 0;
}

void pbrt_coordsys_set(pbrt_parser *p, const char *name, const double m[4][4])
{
    int i = spm_names_get(&p->coordsys, name);
    if (i < 0) {
        p->cs = spm_xrealloc(p->cs, (size_t)(p->ncs + 1) * sizeof *p->cs);
        i = p->ncs++;
        spm_names_put(&p->coordsys, name, i);
    }
    memcpy(p->cs[i], m, sizeof p->cs[i]);
}

static int dir_coordsys(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    (void)where;
    if (pbrt_arg_string(p, "a coordinate system's name", name, sizeof name))
        return 1;
    pbrt_coordsys_set(p, name, p->gs.ctm);
    return 0;
}

static int dir_coordsys_transform(pbrt_parser *p, const char *where)
{
    char name[SPM_NAME_MAX];
    if (pbrt_arg_string(p, "a coordinate system's name", name, sizeof name))
        return 1;
    int i = spm_names_get(&p->coordsys, name);
    if (i < 0) {
        spm_errorf(p->err, "%s: CoordSysTransform: no coordinate system \"%s\" (CoordinateSystem "
                           "names one; \"camera\" and \"world\" are pbrt's own)", where, name);
        return 1;
    }
    memcpy(p->gs.ctm, p->cs[i], sizeof p->gs.ctm);
    return 0;
}

static int dir_attr_begin(pbrt_parser *p, const char *where)
{
    (void)where;
    p->stack = spm_xrealloc(p->stack, (size_t)(p->nstack + 1) * sizeof *p->stack);
    p->stack[p->nstack++] = p->gs;
    return 0;
}

static int dir_attr_end(pbrt_parser *p, const char *where)
{
    if (p->nstack == 0) {
        spm_errorf(p->err, "%s: AttributeEnd without AttributeBegin", where);
        return 1;
    }
    p->gs = p->stack[--p->nstack];
    return 0;
}

/* TransformBegin/End (pbrt-v3, still read by v4): the transform alone. */
static int dir_transform_begin(pbrt_parser *p, const char *where)
{
    return dir_attr_begin(p, where);
}

static int dir_transform_end(pbrt_parser *p, const char *where)
{
    if (p->nstack == 0) {
        spm_errorf(p->err, "%s: TransformEnd without TransformBegin", where);
        return 1;
    }
    memcpy(p->gs.ctm, p->stack[--p->nstack].ctm, sizeof p->gs.ctm);
    return 0;
}

/* Attribute "shape"|"light"|"material"|... params: defaults for later
 * directives, which this importer does not keep. */
static int dir_attribute(pbrt_parser *p, const char *where)
{
    char target[64];
    pbrt_params ps;
    if (pbrt_arg_string(p, "a target (shape, light, material, medium, texture)", target,
                        sizeof target) || pbrt_arg_params(p, &ps))
        return 1;
    int rc = pbrt_warn(where, "Attribute (default parameters)", "not applied", p->err);
    pbrt_params_free(&ps);
    return rc;
}

/* Motion blur: the transforms at the start time are the ones used. */
static int dir_motion(pbrt_parser *p, const char *where)
{
    pbrt_lexer *lx = pbrt_lx(p);
    while (lx->type == PT_NUMBER || lx->type == PT_WORD) {
        if (lx->type == PT_WORD && strcmp(lx->text, "StartTime") && strcmp(lx->text, "EndTime") &&
            strcmp(lx->text, "All"))
            break;
        if (pbrt_lex_next(lx, p->err))
            return 1;
    }
    return pbrt_warn(where, "TransformTimes/ActiveTransform (motion blur)",
                     "the transforms are applied as if all were at the start time", p->err);
}

const pbrt_directive pbrt_state_directives[] = {
    {"Translate", dir_translate},
    {"Scale", dir_scale},
    {"Rotate", dir_rotate},
    {"LookAt", dir_lookat},
    {"Transform", dir_transform},
    {"ConcatTransform", dir_concat},
    {"Identity", dir_identity},
    {"ReverseOrientation", dir_reverse},
    {"CoordinateSystem", dir_coordsys},
    {"CoordSysTransform", dir_coordsys_transform},
    {"AttributeBegin", dir_attr_begin},
    {"AttributeEnd", dir_attr_end},
    {"TransformBegin", dir_transform_begin},
    {"TransformEnd", dir_transform_end},
    {"Attribute", dir_attribute},
    {"TransformTimes", dir_motion},
    {"ActiveTransform", dir_motion},
    {NULL, NULL},
};
