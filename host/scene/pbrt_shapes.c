/* pbrt-v4's shapes as triangles in object space: trianglemesh and
 * bilinearmesh from their arrays, plymesh by the PLY reader (mesh_import.c),
 * sphere and disk tessellated (specmip traces triangles only: a note says
 * so once). Each triangle is wound so that its front face is the side of
 * pbrt-v4's geometric normal: its vertex normals' side when it has them,
 * else the winding's; ReverseOrientation turns it. */
#include "pbrt.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SPHERE_RINGS 48   /* latitude bands; twice as many longitude segments */
#define DISK_SEGMENTS 128
#define PATCH_GRID 8      /* a non-planar bilinear patch: 8 x 8 quads */
#define PI 3.14159265358979323846

/* A mesh of n triangles, one unnamed material, normals when asked. */
static void mesh_alloc(spm_mesh_data *d, uint64_t n, int normals)
{
    memset(d, 0, sizeof *d);
    size_t bytes = sizeof(spm_mesh_material) + n * sizeof(spm_mesh_tri) +
                   (normals ? n * sizeof(spm_mesh_normals) : 0);
    d->buf = spm_xcalloc(1, bytes);
    d->mats = d->buf;
    d->tris = (spm_mesh_tri *)(d->mats + 1);
    d->normals = normals ? (spm_mesh_normals *)(d->tris + n) : NULL;
    d->nmats = 1;
    d->ntris = n;
}

static void swap3(float a[3], float b[3])
{
    for (int i = 0; i < 3; i++) {
        float t = a[i];
        a[i] = b[i];
        b[i] = t;
    }
}

/* The winding turned to the normals' side (pbrt-v4 turns its geometric
 * normal to the shading normal), then reversed under ReverseOrientation. */
static void orient(spm_mesh_data *d, int reverse)
{
    for (uint64_t t = 0; t < d->ntris; t++) {
        float(*p)[3] = d->tris[t].p;
        int turn = reverse;
        if (d->normals) {
            double e1[3], e2[3], s[3] = {0, 0, 0};
            for (int i = 0; i < 3; i++) {
                e1[i] = p[1][i] - p[0][i];
                e2[i] = p[2][i] - p[0][i];
                for (int v = 0; v < 3; v++)
                    s[i] += d->normals[t].n[v][i];
            }
            double g = (e1[1] * e2[2] - e1[2] * e2[1]) * s[0] +
                       (e1[2] * e2[0] - e1[0] * e2[2]) * s[1] +
                       (e1[0] * e2[1] - e1[1] * e2[0]) * s[2];
            turn ^= g < 0;
        }
        if (turn) {
            swap3(p[1], p[2]);
            if (d->normals)
                swap3(d->normals[t].n[1], d->normals[t].n[2]);
        }
    }
}

/* The float3 arrays of a mesh: P (required), N (optional, as many). */
static int points(pbrt_params *ps, const char *where, const pbrt_param **P, const pbrt_param **N,
                  spm_error *err)
{
    int bad = 0;
    *P = pbrt_param_find(ps, "P", 1u << PP_POINT3, &bad, err);
    *N = pbrt_param_find(ps, "N", 1u << PP_NORMAL, &bad, err);
    if (bad)
        return 1;
    if (!*P) {
        spm_errorf(err, "%s: the shape needs 'point3 P'", where);
        return 1;
    }
    if (*N && (*N)->nnum != (*P)->nnum) {
        spm_errorf(err, "%s: 'normal N' has %zu normals for %zu points", (*N)->where,
                   (*N)->nnum / 3, (*P)->nnum / 3);
        return 1;
    }
    for (const char *const *u = (const char *const[]){"uv", "S", "faceIndices", NULL}; *u; u++)
        pbrt_param_find(ps, *u, ~0u, &bad, err); /* texture coordinates, tangents: no use yet */
    return 0;
}

static void put_vertex(spm_mesh_data *d, uint64_t t, int v, const pbrt_param *P,
                       const pbrt_param *N, size_t i)
{
    for (int k = 0; k < 3; k++) {
        d->tris[t].p[v][k] = (float)P->num[3 * i + k];
        if (N)
            d->normals[t].n[v][k] = (float)N->num[3 * i + k];
    }
}

/* indices: a multiple of `per`, each below the count of points. */
static const pbrt_param *indices(pbrt_params *ps, const pbrt_param *P, int per, const char *where,
                                 spm_error *err)
{
    int bad = 0;
    const pbrt_param *I = pbrt_param_find(ps, "indices", 1u << PP_INTEGER, &bad, err);
    if (bad)
        return NULL;
    if (!I) {
        if ((int)(P->nnum / 3) == per)
            return P; /* pbrt: one polygon of exactly `per` points needs no indices */
        spm_errorf(err, "%s: the shape needs 'integer indices' (%zu points)", where, P->nnum / 3);
        return NULL;
    }
    if (I->nnum % (size_t)per) {
        spm_errorf(err, "%s: 'indices' has %zu values, not a multiple of %d", I->where, I->nnum,
                   per);
        return NULL;
    }
    for (size_t k = 0; k < I->nnum; k++)
        if (!(I->num[k] >= 0 && I->num[k] < (double)(P->nnum / 3))) {
            spm_errorf(err, "%s: index %g (value %zu) is outside the %zu points", I->where,
                       I->num[k], k + 1, P->nnum / 3);
            return NULL;
        }
    return I;
}

static size_t idx(const pbrt_param *I, const pbrt_param *P, size_t k)
{
    return I == P ? k : (size_t)I->num[k];
}

static int trianglemesh(pbrt_params *ps, const char *where, spm_mesh_data *d, spm_error *err)
{
    const pbrt_param *P, *N, *I;
    if (points(ps, where, &P, &N, err) || !(I = indices(ps, P, 3, where, err)))
        return 1;
    size_t n = I == P ? 1 : I->nnum / 3;
    mesh_alloc(d, n, N != NULL);
    for (size_t t = 0; t < n; t++)
        for (int v = 0; v < 3; v++)
            put_vertex(d, t, v, P, N, idx(I, P, 3 * t + v));
    return 0;
}

/* A bilinear patch p00 p10 p01 p11: two triangles when planar, else a grid. */
static int bilinearmesh(pbrt_params *ps, const char *where, spm_mesh_data *d, spm_error *err)
{
    const pbrt_param *P, *N, *I;
    if (points(ps, where, &P, &N, err) || !(I = indices(ps, P, 4, where, err)))
        return 1;
    size_t npatch = I == P ? 1 : I->nnum / 4;
    mesh_alloc(d, npatch * 2 * PATCH_GRID * PATCH_GRID, N != NULL);
    uint64_t t = 0;
    for (size_t q = 0; q < npatch; q++) {
        double c[4][3], nn[4][3] = {{0}};
        for (int v = 0; v < 4; v++)
            for (int k = 0; k < 3; k++) {
                c[v][k] = P->num[3 * idx(I, P, 4 * q + v) + k];
                if (N)
                    nn[v][k] = N->num[3 * idx(I, P, 4 * q + v) + k];
            }
        double e1[3], e2[3], e3[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = c[1][k] - c[0][k];
            e2[k] = c[2][k] - c[0][k];
            e3[k] = c[3][k] - c[0][k];
        }
        double vol = e1[0] * (e2[1] * e3[2] - e2[2] * e3[1]) - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0]) +
                     e1[2] * (e2[0] * e3[1] - e2[1] * e3[0]);
        int g = fabs(vol) > 1e-9 * (1e-30 + pow(fabs(e1[0]) + fabs(e1[1]) + fabs(e1[2]) +
                                                    fabs(e2[0]) + fabs(e2[1]) + fabs(e2[2]), 3))
                    ? PATCH_GRID : 1;
        for (int a = 0; a < g; a++)
            for (int b = 0; b < g; b++) {
                /* corners (u, v) of the cell, p(u, v) = bilinear of the four */
                double uv[4][2] = {{(double)a / g, (double)b / g}, {(double)(a + 1) / g, (double)b / g},
                                   {(double)a / g, (double)(b + 1) / g},
                                   {(double)(a + 1) / g, (double)(b + 1) / g}};
                float q4[4][3], n4[4][3];
                for (int v = 0; v < 4; v++)
                    for (int k = 0; k < 3; k++) {
                        double u = uv[v][0], w = uv[v][1];
                        double w4[4] = {(1 - u) * (1 - w), u * (1 - w), (1 - u) * w, u * w};
                        q4[v][k] = (float)(w4[0] * c[0][k] + w4[1] * c[1][k] + w4[2] * c[2][k] +
                                           w4[3] * c[3][k]);
                        n4[v][k] = (float)(w4[0] * nn[0][k] + w4[1] * nn[1][k] +
                                           w4[2] * nn[2][k] + w4[3] * nn[3][k]);
                    }
                static const int tri[2][3] = {{0, 1, 3}, {0, 3, 2}};
                for (int h = 0; h < 2; h++, t++)
                    for (int v = 0; v < 3; v++) {
                        memcpy(d->tris[t].p[v], q4[tri[h][v]], sizeof q4[0]);
                        if (N)
                            memcpy(d->normals[t].n[v], n4[tri[h][v]], sizeof n4[0]);
                    }
            }
    }
    d->ntris = t;
    return 0;
}

static void sphere_point(double r, double theta, double phi, float p[3], float n[3])
{
    double s = sin(theta), c = cos(theta);
    double u[3] = {s * cos(phi), s * sin(phi), c};
    for (int k = 0; k < 3; k++) {
        p[k] = (float)(r * u[k]);
        n[k] = (float)u[k];
    }
}

static int sphere(pbrt_params *ps, const char *where, spm_mesh_data *d, spm_error *err)
{
    int bad = 0;
    double r = pbrt_param_float(ps, "radius", 1.0, &bad, err);
    double zmin = pbrt_param_float(ps, "zmin", -r, &bad, err);
    double zmax = pbrt_param_float(ps, "zmax", r, &bad, err);
    double phimax = pbrt_param_float(ps, "phimax", 360.0, &bad, err);
    if (bad)
        return 1;
    if (!(r > 0) || !isfinite(r)) {
        spm_errorf(err, "%s: sphere radius %g (it must be positive)", where, r);
        return 1;
    }
    if ((zmin > -r || zmax < r || phimax < 360.0) &&
        pbrt_warn(where, "Shape \"sphere\": zmin, zmax or phimax", "a partial sphere is "
                                                                     "rendered whole", err))
        return 1;
    const int nr = SPHERE_RINGS, ns = 2 * SPHERE_RINGS;
    mesh_alloc(d, (uint64_t)nr * ns * 2, 1);
    uint64_t t = 0;
    for (int i = 0; i < nr; i++)
        for (int j = 0; j < ns; j++) {
            double th0 = PI * i / nr, th1 = PI * (i + 1) / nr;
            double ph0 = 2 * PI * j / ns, ph1 = 2 * PI * (j + 1) / ns;
            float p[4][3], n[4][3];
            sphere_point(r, th0, ph0, p[0], n[0]);
            sphere_point(r, th1, ph0, p[1], n[1]);
            sphere_point(r, th1, ph1, p[2], n[2]);
            sphere_point(r, th0, ph1, p[3], n[3]);
            static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (int h = 0; h < 2; h++) {
                if ((i == 0 && h == 1) || (i == nr - 1 && h == 0))
                    continue; /* at a pole this one has two vertices in one */
                for (int v = 0; v < 3; v++) {
                    memcpy(d->tris[t].p[v], p[tri[h][v]], sizeof p[0]);
                    memcpy(d->normals[t].n[v], n[tri[h][v]], sizeof n[0]);
                }
                t++;
            }
        }
    d->ntris = t;
    return 0;
}

static int disk(pbrt_params *ps, const char *where, spm_mesh_data *d, spm_error *err)
{
    int bad = 0;
    double h = pbrt_param_float(ps, "height", 0.0, &bad, err);
    double r = pbrt_param_float(ps, "radius", 1.0, &bad, err);
    double ri = pbrt_param_float(ps, "innerradius", 0.0, &bad, err);
    double phimax = pbrt_param_float(ps, "phimax", 360.0, &bad, err);
    if (bad)
        return 1;
    if (!(r > 0 && ri >= 0 && ri < r) || !isfinite(r)) {
        spm_errorf(err, "%s: disk radius %g, inner radius %g", where, r, ri);
        return 1;
    }
    if (phimax < 360.0 &&
        pbrt_warn(where, "Shape \"disk\": phimax", "a partial disk is rendered whole", err))
        return 1;
    mesh_alloc(d, (uint64_t)DISK_SEGMENTS * (ri > 0 ? 2 : 1), 0);
    uint64_t t = 0;
    for (int j = 0; j < DISK_SEGMENTS; j++) {
        double a0 = 2 * PI * j / DISK_SEGMENTS, a1 = 2 * PI * (j + 1) / DISK_SEGMENTS;
        float o0[3] = {(float)(r * cos(a0)), (float)(r * sin(a0)), (float)h};
        float o1[3] = {(float)(r * cos(a1)), (float)(r * sin(a1)), (float)h};
        float i0[3] = {(float)(ri * cos(a0)), (float)(ri * sin(a0)), (float)h};
        float i1[3] = {(float)(ri * cos(a1)), (float)(ri * sin(a1)), (float)h};
        /* counter-clockwise seen from +z: the front face is +z, pbrt's disk normal */
        const float *tri[2][3] = {{i0, o0, o1}, {i0, o1, i1}};
        for (int k = 0; k < (ri > 0 ? 2 : 1); k++, t++)
            for (int v = 0; v < 3; v++)
                memcpy(d->tris[t].p[v], tri[k][v], 3 * sizeof(float));
    }
    return 0;
}

static int plymesh(pbrt_params *ps, pbrt_shape_ctx *c, const char *where, spm_mesh_data *d,
                   spm_error *err)
{
    int bad = 0;
    const pbrt_param *fp = pbrt_param_find(ps, "filename", 1u << PP_STRING, &bad, err);
    if (bad)
        return 1;
    if (!fp || fp->nstr != 1) {
        spm_errorf(err, "%s: Shape \"plymesh\" needs one 'string filename'", where);
        return 1;
    }
    spm_file path;
    if (spm_path_check(c->dir, fp->str[0], fp->where, &path, err))
        return 1;
    const char *dot = strrchr(fp->str[0], '.');
    if (!dot || (strcmp(dot, ".ply") && strcmp(dot, ".PLY"))) {
        spm_errorf(err, "%s: '%s': plymesh reads .ply files (a .ply.gz is not read: unpack it)",
                   fp->where, fp->str[0]);
        return 1;
    }
    if (spm_mesh_import(&path, d, err)) {
        spm_error inner = *err;
        spm_errorf(err, "%s: plymesh %.900s", fp->where, inner.msg);
        return 1;
    }
    return 0;
}

int pbrt_shape_make(const char *type, pbrt_params *ps, pbrt_shape_ctx *c, const char *where,
                    spm_mesh_data *out, spm_error *err)
{
    static int noted;
    int rc;
    memset(out, 0, sizeof *out);
    if (!strcmp(type, "trianglemesh"))
        rc = trianglemesh(ps, where, out, err);
    else if (!strcmp(type, "bilinearmesh"))
        rc = bilinearmesh(ps, where, out, err);
    else if (!strcmp(type, "plymesh"))
        rc = plymesh(ps, c, where, out, err);
    else if (!strcmp(type, "sphere") || !strcmp(type, "disk")) {
        if (!noted++)
            spm_warnf("%s: note: spheres (%d x %d quads, vertex normals) and disks (%d "
                      "segments) are tessellated: specmip traces triangles", where,
                      SPHERE_RINGS, 2 * SPHERE_RINGS, DISK_SEGMENTS);
        rc = type[0] == 's' ? sphere(ps, where, out, err) : disk(ps, where, out, err);
    } else {
        return 2;
    }
    if (rc) {
        spm_mesh_free(out);
        return 1;
    }
    c->has_normals = out->normals != NULL;
    orient(out, c->reverse);
    return 0;
}
