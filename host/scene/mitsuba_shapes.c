/* Mitsuba 3's shapes as triangles in object space, with its conventions:
 * rectangle the square [-1, 1]^2 at z = 0 facing +z, cube [-1, 1]^3 facing
 * out, disk the unit disk at z = 0 facing +z, sphere `center` and `radius`
 * facing out (tessellated with vertex normals, by pbrt-v4's code), obj and
 * ply read by the mesh statement's importer (their winding is the front
 * face, as Mitsuba's geometric normal). `flip_normals` turns the front
 * face; `face_normals` drops a mesh's vertex normals. */
#include "mitsuba.h"
#include <math.h>
#include <string.h>

/* The unit shapes as pbrt trianglemesh parameters. */
static const double rect_p[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
static const double rect_i[] = {0, 1, 2, 0, 2, 3};
static const double cube_p[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
/* each face counter-clockwise seen from outside */
static const double cube_i[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

static int unit_mesh(const double *p, size_t np, const double *idx, size_t ni, int reverse,
                     const char *where, spm_mesh_data *out, spm_error *err)
{
    pbrt_param prm[2] = {{.type = PP_POINT3, .name = "P", .num = (double *)p, .nnum = np},
                         {.type = PP_INTEGER, .name = "indices", .num = (double *)idx,
                          .nnum = ni}};
    pbrt_params ps = {.p = prm, .n = 2};
    pbrt_shape_ctx c = {.reverse = reverse};
    return pbrt_shape_make("trianglemesh", &ps, &c, where, out, err);
}

static int mesh_file(const mi_doc *doc, mi_node *s, int reverse, spm_mesh_data *out,
                     int *smooth, spm_error *err)
{
    int bad = 0;
    const char *fn = mi_string(s, "filename", NULL, &bad, err);
    int face_normals = mi_bool(s, "face_normals", 0, &bad, err);
    if (bad)
        return 1;
    if (!fn) {
        spm_errorf(err, "%s: <shape type=\"%s\"> needs a 'filename'", s->where,
                   mi_attr(s, "type"));
        return 1;
    }
    mi_node *k = mi_prop(s, "filename", "string", &bad, err);
    spm_file path;
    if (mi_file(doc, k, fn, &path, err))
        return 1;
    if (spm_mesh_import(&path, out, err)) {
        spm_error inner = *err;
        spm_errorf(err, "%s: %.900s", k->where, inner.msg);
        return 1;
    }
    if (face_normals)
        out->normals = NULL; /* owned by buf: freed with it */
    *smooth = out->normals != NULL;
    for (uint64_t t = 0; reverse && t < out->ntris; t++)
        for (int i = 0; i < 3; i++) {
            float a = out->tris[t].p[1][i];
            out->tris[t].p[1][i] = out->tris[t].p[2][i];
            out->tris[t].p[2][i] = a;
            if (out->normals) {
                a = out->normals[t].n[1][i];
                out->normals[t].n[1][i] = out->normals[t].n[2][i];
                out->normals[t].n[2][i] = a;
            }
        }
    return 0;
}

static int sphere(mi_node *s, int reverse, spm_mesh_data *out, double obj[4][4], spm_error *err)
{
    int bad = 0;
    double c[3] = {0, 0, 0}, sc[4][4], tr[4][4], m[4][4];
    double r = mi_float(s, "radius", 1.0, &bad, err);
    mi_node *ck = mi_prop(s, "center", "point|vector", &bad, err);
    const char *xyz[3] = {"x", "y", "z"};
    if (bad || (ck && mi_vec3(ck, xyz, "value", c, err)))
        return 1;
    if (!(r > 0) || !isfinite(r)) {
        spm_errorf(err, "%s: sphere radius %g (it must be positive)", s->where, r);
        return 1;
    }
    pbrt_mat_scale((double[]){r, r, r}, sc);
    pbrt_mat_translate(c, tr);
    pbrt_mat_mul(tr, sc, m);
    pbrt_mat_mul(obj, m, tr);
    memcpy(obj, tr, sizeof tr);
    pbrt_params ps = {0};
    pbrt_shape_ctx ctx = {.reverse = reverse};
    return pbrt_shape_make("sphere", &ps, &ctx, s->where, out, err);
}

int mi_shape_make(const mi_doc *doc, mi_node *s, const char *type, spm_mesh_data *out,
                  int *smooth, double obj[4][4], spm_error *err)
{
    int bad = 0;
    memset(out, 0, sizeof *out);
    *smooth = 0;
    int flip = mi_bool(s, "flip_normals", 0, &bad, err);
    if (bad || mi_to_world(s, obj, err))
        return 1;
    if (!strcmp(type, "obj") || !strcmp(type, "ply"))
        return mesh_file(doc, s, flip, out, smooth, err);
    if (!strcmp(type, "rectangle"))
        return unit_mesh(rect_p, 12, rect_i, 6, flip, s->where, out, err);
    if (!strcmp(type, "cube"))
        return unit_mesh(cube_p, 24, cube_i, 36, flip, s->where, out, err);
    if (!strcmp(type, "disk")) {
        pbrt_params ps = {0};
        pbrt_shape_ctx ctx = {.reverse = flip};
        return pbrt_shape_make("disk", &ps, &ctx, s->where, out, err);
    }
    if (!strcmp(type, "sphere")) {
        *smooth = 1;
        return sphere(s, flip, out, obj, err);
    }
    return 2;
}
