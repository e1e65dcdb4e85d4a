/* Normal maps for the device (geometry.h; the layout: spm_shared.h
 * SPM_NMAP_*): the maps, a record per material, and a tangent frame per
 * vertex of every triangle, the file's or one made as MikkTSpace makes it
 * (Mikkelsen 2008, the tangent space Blender and glTF's samples bake normal
 * maps in), so that a baked map bends the normal it was baked against. */
#include "geometry.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static spm_u32 fbits(float f)
{
    spm_u32 u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* A corner's vertex: position, normal and (u, v) as bits (-0 made +0), and
 * its face's handedness; MikkTSpace shares a tangent between the corners
 * where all of these are equal. */
typedef struct {
    spm_u32 key[9];
    spm_u32 corner;
} corner_key;

static int cmp_key(const void *a, const void *b)
{
    const corner_key *x = a, *y = b;
    for (int i = 0; i < 9; i++)
        if (x->key[i] != y->key[i])
            return x->key[i] < y->key[i] ? -1 : 1;
    return 0;
}

static void put_bits(spm_u32 *k, const float *f, int n)
{
    for (int i = 0; i < n; i++)
        k[i] = fbits(f[i] + 0.0f);
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* v minus its part along unit n, made unit (0 when nothing is left) */
static void perp_unit(double v[3], const double n[3])
{
    double k = dot(v, n);
    for (int i = 0; i < 3; i++)
        v[i] -= n[i] * k;
    double len = sqrt(dot(v, v));
    for (int i = 0; i < 3; i++)
        v[i] = len > 0.0 && isfinite(len) ? v[i] / len : 0.0;
}

/* A face's tangent and bitangent from its (u, v) derivatives: with
 * e1 = p1 - p0, e2 = p2 - p0 and (du1, dv1), (du2, dv2) the same of (u, v),
 * dP/du = (dv2 e1 - dv1 e2) / det and dP/dv = (du1 e2 - du2 e1) / det,
 * det = du1 dv2 - du2 dv1 (only det's sign is kept: the lengths do not
 * matter); the corner angles atan2(|a x b|, a . b) weigh each face. */
static void face_frame(const spm_tangent_in *f, double t[3], double b[3], double angle[3])
{
    double e1[3], e2[3];
    for (int i = 0; i < 3; i++)
        e1[i] = (double)f->p[1][i] - f->p[0][i], e2[i] = (double)f->p[2][i] - f->p[0][i];
    double du1 = (double)f->uv[1][0] - f->uv[0][0], dv1 = (double)f->uv[1][1] - f->uv[0][1];
    double du2 = (double)f->uv[2][0] - f->uv[0][0], dv2 = (double)f->uv[2][1] - f->uv[0][1];
    double det = du1 * dv2 - du2 * dv1, s = det > 0.0 ? 1.0 : det < 0.0 ? -1.0 : 0.0;
    for (int i = 0; i < 3; i++) {
        t[i] = s * (dv2 * e1[i] - dv1 * e2[i]);
        b[i] = s * (du1 * e2[i] - du2 * e1[i]);
    }
    for (int v = 0; v < 3; v++) {
        double a[3], c[3];
        for (int i = 0; i < 3; i++) {
            a[i] = (double)f->p[(v + 1) % 3][i] - f->p[v][i];
            c[i] = (double)f->p[(v + 2) % 3][i] - f->p[v][i];
        }
        double x[3] = {a[1] * c[2] - a[2] * c[1], a[2] * c[0] - a[0] * c[2],
                       a[0] * c[1] - a[1] * c[0]};
        angle[v] = atan2(sqrt(dot(x, x)), dot(a, c));
    }
}

/* any unit vector perpendicular to unit n (Duff et al. 2017's basis) */
static void any_perp(const double n[3], double t[3])
{
    double s = n[2] >= 0.0 ? 1.0 : -1.0, a = -1.0 / (s + n[2]), b = n[0] * n[1] * a;
    t[0] = 1.0 + s * n[0] * n[0] * a, t[1] = s * b, t[2] = -s * n[0];
}

void spm_tangents_make(const spm_tangent_in *in, int n, float (*out)[12])
{
    size_t nc = (size_t)n * 3;
    corner_key *k = spm_xmalloc((nc + 1) * sizeof *k);
    double (*proj)[3] = spm_xmalloc((nc + 1) * sizeof *proj), *w = spm_xmalloc((nc + 1) * sizeof *w);
    double (*nrm)[3] = spm_xmalloc((nc + 1) * sizeof *nrm);
    for (int f = 0; f < n; f++) {
        double t[3], b[3], angle[3];
        face_frame(&in[f], t, b, angle);
        for (int v = 0; v < 3; v++) {
            size_t c = 3 * (size_t)f + v;
            double *nv = nrm[c], bp[3] = {b[0], b[1], b[2]};
            for (int i = 0; i < 3; i++)
                nv[i] = in[f].n[v][i];
            double len = sqrt(dot(nv, nv));
            for (int i = 0; i < 3; i++)
                nv[i] = len > 0.0 ? nv[i] / len : 0.0;
            memcpy(proj[c], t, sizeof t);
            perp_unit(proj[c], nv);
            perp_unit(bp, nv);
            /* handedness: B on the side of N x T (+1), or against it (-1) */
            double x[3] = {nv[1] * t[2] - nv[2] * t[1], nv[2] * t[0] - nv[0] * t[2],
                           nv[0] * t[1] - nv[1] * t[0]};
            float hand = dot(x, bp) < 0.0 ? -1.0f : 1.0f;
            w[c] = angle[v];
            put_bits(k[c].key, in[f].p[v], 3);
            put_bits(k[c].key + 3, in[f].n[v], 3);
            put_bits(k[c].key + 6, in[f].uv[v], 2);
            k[c].key[8] = fbits(hand);
            k[c].corner = (spm_u32)c;
        }
    }
    qsort(k, nc, sizeof *k, cmp_key);
    for (size_t i = 0; i < nc;) { /* each vertex: sum of angle x projected face tangent */
        size_t j = i;
        double sum[3] = {0, 0, 0};
        for (; j < nc && !cmp_key(&k[i], &k[j]); j++)
            for (int a = 0; a < 3; a++)
                sum[a] += w[k[j].corner] * proj[k[j].corner][a];
        for (size_t q = i; q < j; q++) {
            size_t c = k[q].corner;
            double t[3] = {sum[0], sum[1], sum[2]};
            perp_unit(t, nrm[c]); /* Gram-Schmidt against the vertex's normal */
            if (dot(t, t) == 0.0)
                any_perp(nrm[c], t);
            float *o = out[c / 3] + 4 * (c % 3);
            for (int a = 0; a < 3; a++)
                o[a] = (float)t[a];
            memcpy(&o[3], &k[q].key[8], sizeof o[3]);
        }
        i = j;
    }
    free(k);
    free(proj);
    free(w);
    free(nrm);
}

int spm_geometry_has_nmap(const spm_scene *s)
{
    for (int m = 0; m < s->nmaterials; m++)
        if (s->materials[m].nmap)
            return 1;
    return 0;
}

static size_t map_words(const spm_normal_map *m)
{
    return SPM_NMAP_MAP_HEAD + (size_t)m->w * m->h + spm_geometry_uvx_words(&m->uvx);
}

size_t spm_geometry_nmap_words(const spm_scene *s)
{
    if (!spm_geometry_has_nmap(s))
        return 0;
    size_t n = (size_t)s->nmaterials * (1 + SPM_NMAP_RECORD) + 12 * (size_t)s->ntris;
    for (int i = 0; i < s->nnmaps; i++)
        n += map_words(&s->nmaps[i]);
    return n;
}

/* The tangents of every triangle: the file's where it gave them, the others
 * made from the normals the shading interpolates (a flat triangle's face
 * normal) and the texture coordinates. */
static void put_tangents(const spm_scene *s, float *out)
{
    spm_tangent_in *in = spm_xcalloc((size_t)s->ntris + 1, sizeof *in);
    for (int t = 0; t < s->ntris; t++) {
        const spm_scene_tri *tr = &s->tris[t];
        memcpy(in[t].p, tr->p, sizeof in[t].p);
        if (tr->uv > 0 && tr->uv <= s->nuvs)
            memcpy(in[t].uv, s->uvs[tr->uv - 1], sizeof in[t].uv);
        if (tr->vn > 0 && tr->vn <= s->nvnormals) {
            memcpy(in[t].n, s->vnormals[tr->vn - 1], sizeof in[t].n);
            continue;
        }
        float e1[3], e2[3];
        for (int i = 0; i < 3; i++)
            e1[i] = tr->p[1][i] - tr->p[0][i], e2[i] = tr->p[2][i] - tr->p[0][i];
        float fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        for (int v = 0; v < 3; v++)
            memcpy(in[t].n[v], fn, sizeof fn);
    }
    spm_tangents_make(in, s->ntris, (float (*)[12])out);
    free(in);
    for (int t = 0; t < s->ntris; t++)
        if (s->tris[t].tg > 0 && s->tris[t].tg <= s->ntangents)
            memcpy(out + 12 * (size_t)t, s->tangents[s->tris[t].tg - 1], 12 * sizeof *out);
}

size_t spm_geometry_nmap_put(const spm_scene *s, spm_u32 *x, size_t w)
{
    if (!spm_geometry_has_nmap(s))
        return w;
    spm_u32 *offs = spm_xcalloc((size_t)s->nnmaps + 1, sizeof *offs);
    for (int i = 0; i < s->nnmaps; i++) {
        const spm_normal_map *m = &s->nmaps[i];
        offs[i] = (spm_u32)w;
        x[w] = (spm_u32)m->w, x[w + 1] = (spm_u32)m->h;
        x[w + 2] = (spm_u32)m->wrap[0], x[w + 3] = (spm_u32)m->wrap[1];
        memcpy(x + w + SPM_NMAP_MAP_HEAD, m->q, (size_t)m->w * m->h * sizeof *x);
        spm_geometry_uvx_put(&m->uvx, x, w, SPM_NMAP_UVX,
                             w + SPM_NMAP_MAP_HEAD + (size_t)m->w * m->h);
        w += map_words(m);
    }
    x[SPM_TEXD_NMAP] = (spm_u32)w;
    size_t rec = w + (size_t)s->nmaterials;
    for (int i = 0; i < s->nmaterials; i++) {
        const spm_scene_material *m = &s->materials[i];
        if (m->nmap <= 0 || m->nmap > s->nnmaps)
            continue;
        x[w + (size_t)i] = (spm_u32)rec;
        x[rec] = fbits(m->nmap_scale);
        x[rec + 1] = offs[m->nmap - 1];
        rec += SPM_NMAP_RECORD;
    }
    free(offs);
    rec = w + (size_t)s->nmaterials * (1 + SPM_NMAP_RECORD);
    x[SPM_TEXD_TANGENT] = (spm_u32)rec;
    put_tangents(s, (float *)(x + rec));
    return rec + 12 * (size_t)s->ntris;
}

void spm_geometry_tangents_permute(spm_geometry *g, const int *perm)
{
    if (!g->ntex || !g->tex[SPM_TEXD_TANGENT])
        return;
    spm_u32 *t = g->tex + g->tex[SPM_TEXD_TANGENT];
    spm_u32 *to = spm_xmalloc(((size_t)g->ntris * 12 + 1) * sizeof *to);
    for (int i = 0; i < g->ntris; i++)
        memcpy(to + 12 * (size_t)i, t + 12 * (size_t)perm[i], 12 * sizeof *to);
    memcpy(t, to, (size_t)g->ntris * 12 * sizeof *to);
    free(to);
}
