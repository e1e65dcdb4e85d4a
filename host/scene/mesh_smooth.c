/* Vertex normals for the triangles of a mesh file that has none, under the
 * mesh statement's `smooth`: angle-weighted (Thürmer and Wüthrich 1998) over
 * the faces around each vertex, the fan broken at every edge whose two faces
 * meet at more than the crease angle, so a cube keeps its edges while a
 * tessellated sphere turns round. */
#include "mesh.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A corner's position in the file, as bits (-0 made +0): equal bits, one vertex. */
typedef struct {
    uint32_t key[3];
    uint32_t corner;
} corner_key;

/* An edge between vertex ids lo < hi, of triangle tri (its corners ca at lo, cb at hi). */
typedef struct {
    uint32_t lo, hi, ca, cb;
} edge_rec;

static int cmp_corner(const void *a, const void *b)
{
    const corner_key *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x->key[i] != y->key[i])
            return x->key[i] < y->key[i] ? -1 : 1;
    return 0;
}

static int cmp_edge(const void *a, const void *b)
{
    const edge_rec *x = a, *y = b;
    if (x->lo != y->lo)
        return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    return x->ca < y->ca ? -1 : x->ca > y->ca;
}

/* vid[c]: one id per distinct position of the file's corners c = 3 t + v. */
static void weld(const spm_mesh_data *d, uint32_t *vid)
{
    size_t nc = (size_t)d->ntris * 3;
    corner_key *k = spm_xmalloc(nc * sizeof *k);
    for (size_t c = 0; c < nc; c++) {
        for (int i = 0; i < 3; i++) {
            float f = d->tris[c / 3].p[c % 3][i] + 0.0f; /* -0 + 0 = +0 */
            memcpy(&k[c].key[i], &f, sizeof f);
        }
        k[c].corner = (uint32_t)c;
    }
    qsort(k, nc, sizeof *k, cmp_corner);
    uint32_t id = 0;
    for (size_t c = 0; c < nc; c++) {
        if (c && cmp_corner(&k[c - 1], &k[c]))
            id++;
        vid[k[c].corner] = id;
    }
    free(k);
}

static uint32_t find(uint32_t *parent, uint32_t c)
{
    while (parent[c] != c) {
        parent[c] = parent[parent[c]]; /* path halving */
        c = parent[c];
    }
    return c;
}

/* Each triangle's unit face normal in scene coordinates, (p1 - p0) x (p2 - p0)
 * of x' = M x + t (zero for a degenerate one), and its corner angles, the
 * angle between the two edges leaving the corner: atan2(|a x b|, a . b). */
static void faces(const spm_mesh_data *d, const double m[3][4], double (*fn)[3], double *angle)
{
    for (uint64_t t = 0; t < d->ntris; t++) {
        double p[3][3];
        for (int v = 0; v < 3; v++)
            for (int i = 0; i < 3; i++) {
                const float *q = d->tris[t].p[v];
                p[v][i] = m[i][0] * q[0] + m[i][1] * q[1] + m[i][2] * q[2] + m[i][3];
            }
        for (int v = 0; v < 3; v++) {
            const double *o = p[v], *u = p[(v + 1) % 3], *w = p[(v + 2) % 3];
            double a[3] = {u[0] - o[0], u[1] - o[1], u[2] - o[2]};
            double b[3] = {w[0] - o[0], w[1] - o[1], w[2] - o[2]};
            double x[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]};
            double len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
            angle[3 * t + v] = atan2(len, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
            if (v == 0)
                for (int i = 0; i < 3; i++)
                    fn[t][i] = len > 0 && isfinite(len) ? x[i] / len : 0.0;
        }
    }
}

/* Joins the corners of two triangles across each edge they share alone whose
 * faces meet within the crease (their normals' dot product at least cos_crease). */
static void join_smooth_edges(const spm_mesh_data *d, const uint32_t *vid,
                              const double (*fn)[3], double cos_crease, uint32_t *parent)
{
    size_t ne = (size_t)d->ntris * 3;
    edge_rec *e = spm_xmalloc(ne * sizeof *e);
    for (size_t c = 0; c < ne; c++) {
        uint32_t c2 = (uint32_t)(c - c % 3 + (c + 1) % 3);
        int up = vid[c] < vid[c2];
        e[c] = (edge_rec){up ? vid[c] : vid[c2], up ? vid[c2] : vid[c], up ? (uint32_t)c : c2,
                          up ? c2 : (uint32_t)c};
    }
    qsort(e, ne, sizeof *e, cmp_edge);
    for (size_t i = 0; i < ne;) {
        size_t j = i + 1;
        while (j < ne && e[j].lo == e[i].lo && e[j].hi == e[i].hi)
            j++;
        if (j == i + 2 && e[i].lo != e[i].hi) { /* a manifold edge */
            const double *a = fn[e[i].ca / 3], *b = fn[e[i + 1].ca / 3];
            double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            int flat = a[0] == 0 && a[1] == 0 && a[2] == 0;
            flat |= b[0] == 0 && b[1] == 0 && b[2] == 0;
            if (!flat && dot >= cos_crease) {
                parent[find(parent, e[i].ca)] = find(parent, e[i + 1].ca);
                parent[find(parent, e[i].cb)] = find(parent, e[i + 1].cb);
            }
        }
        i = j;
    }
    free(e);
}

static int has_normals(const spm_mesh_normals *n)
{
    for (int v = 0; v < 3; v++)
        if (n->n[v][0] != 0 || n->n[v][1] != 0 || n->n[v][2] != 0)
            return 1;
    return 0;
}

spm_mesh_normals *spm_mesh_smooth_normals(const spm_mesh_data *d, const double m[3][4],
                                          double crease_deg, uint64_t *made)
{
    *made = 0;
    for (uint64_t t = 0; t < d->ntris && !*made; t++)
        *made = !d->normals || !has_normals(&d->normals[t]);
    if (!*made)
        return NULL;
    size_t nc = (size_t)d->ntris * 3;
    uint32_t *vid = spm_xmalloc(nc * sizeof *vid), *parent = spm_xmalloc(nc * sizeof *parent);
    double (*fn)[3] = spm_xmalloc((size_t)d->ntris * sizeof *fn);
    double *angle = spm_xmalloc(nc * sizeof *angle);
    weld(d, vid);
    faces(d, m, fn, angle);
    for (size_t c = 0; c < nc; c++)
        parent[c] = (uint32_t)c;
    join_smooth_edges(d, vid, (const double (*)[3])fn, cos(crease_deg * (M_PI / 180.0)),
                      parent);
    free(vid);
    /* n = sum over a corner's fan of angle * face normal, gathered at the fan's root */
    double (*sum)[3] = spm_xcalloc(nc, sizeof *sum);
    for (size_t c = 0; c < nc; c++) {
        uint32_t r = find(parent, (uint32_t)c);
        for (int i = 0; i < 3; i++)
            sum[r][i] += angle[c] * fn[c / 3][i];
    }
    free(angle);
    free(fn);
    spm_mesh_normals *out = spm_xmalloc((size_t)d->ntris * sizeof *out);
    *made = 0;
    for (uint64_t t = 0; t < d->ntris; t++) {
        if (d->normals && has_normals(&d->normals[t])) {
            out[t] = d->normals[t];
            continue;
        }
        (*made)++;
        /* as a file normal q, which spm_mesh_add maps by M^-T: q = M^T n */
        for (int v = 0; v < 3; v++) {
            const double *n = sum[find(parent, (uint32_t)(3 * t + v))];
            for (int i = 0; i < 3; i++)
                out[t].n[v][i] = (float)(m[0][i] * n[0] + m[1][i] * n[1] + m[2][i] * n[2]);
        }
    }
    free(sum);
    free(parent);
    return out;
}
