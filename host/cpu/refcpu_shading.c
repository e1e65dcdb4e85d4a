/* The CPU reference's smooth shading (refcpu_shading.h). */
#include "refcpu_shading.h"
#include <math.h>
#include <string.h>
#include "geometry_vec3.h"
#include "refcpu_lights.h"
#include "texture.h"

/* Barycentrics (Moeller and Trumbore 1997): e1 = v1 - v0, e2 = v2 - v0,
 * s = o - v0, q = d x e2, u = s.q / e1.q, v = d.(s x e1) / e1.q, clamped into
 * the triangle; bary = (1 - u - v, u, v). */
static void bary_of(const spm_tri *tr, const float o[3], const float d[3], float bary[3])
{
    float e1[3], e2[3], q[3], s[3], se[3];
    v3_sub(e1, tr->v1, tr->v0);
    v3_sub(e2, tr->v2, tr->v0);
    v3_cross(q, d, e2);
    float det = v3_dot(e1, q);
    float inv = det != 0.0f ? 1.0f / det : 0.0f;
    v3_sub(s, o, tr->v0);
    float u = v3_dot(s, q) * inv;
    v3_cross(se, s, e1);
    float v = v3_dot(d, se) * inv;
    u = fminf(fmaxf(u, 0.0f), 1.0f);
    v = fminf(fmaxf(v, 0.0f), 1.0f - u);
    bary[0] = 1.0f - u - v, bary[1] = u, bary[2] = v;
}

/* n = unit(w x0 + u x1 + v x2) of three vectors `stride` floats apart */
static void interp_unit(const float *x, int stride, const float bary[3], float n[3])
{
    float sum[3];
    for (int i = 0; i < 3; i++)
        sum[i] = x[i] * bary[0] + x[stride + i] * bary[1] + x[2 * stride + i] * bary[2];
    v3_normalise(n, sum);
}

/* Keller et al. 2017's bend of n (the viewer's side): r = 2 (wo.n) n - wo;
 * where r.gn < SPM_SMOOTH_LIFT, r' = unit(r + gn (LIFT - r.gn)) and
 * n = unit(wo + r'). The tangent unit(t - n (t.n)) (t parallel to n:
 * unit(gn x n)). */
static void bend(const spm_tri *tr, float n[3], const float d[3], const float gn[3],
                 float sn[3], float st[3])
{
    float back[3] = {-d[0], -d[1], -d[2]}, r[3];
    float c = v3_dot(back, n);
    for (int i = 0; i < 3; i++)
        r[i] = n[i] * (2.0f * c) - back[i];
    float rg = v3_dot(r, gn);
    if (rg < SPM_SMOOTH_LIFT) {
        float rl[3], h[3];
        for (int i = 0; i < 3; i++)
            rl[i] = r[i] + gn[i] * (SPM_SMOOTH_LIFT - rg);
        v3_normalise(rl, rl);
        for (int i = 0; i < 3; i++)
            h[i] = back[i] + rl[i];
        v3_normalise(n, h);
    }
    float tn = v3_dot(tr->t, n), tp[3];
    for (int i = 0; i < 3; i++)
        tp[i] = tr->t[i] - n[i] * tn;
    v3_normalise(st, tp);
    if (v3_dot(st, st) == 0.0f) {
        v3_cross(tp, gn, n);
        v3_normalise(st, tp);
    }
    memcpy(sn, n, 3 * sizeof *n);
}

/* n interpolated at the barycentrics, turned with gn when the viewer is
 * behind the front face (a zero sum: gn); then the bend. */
void spm_ref_shading_frame(const spm_tri *tr, const float vn[9], const float o[3],
                           const float d[3], const float gn[3], float sn[3], float st[3])
{
    float b[3], n[3];
    bary_of(tr, o, d, b);
    interp_unit(vn, 3, b, n);
    if (v3_dot(gn, tr->n) < 0.0f)
        n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    if (v3_dot(n, n) == 0.0f)
        memcpy(n, gn, sizeof n);
    bend(tr, n, d, gn, sn, st);
}

static float word_float(spm_u32 w)
{
    float f;
    memcpy(&f, &w, sizeof f);
    return f;
}

/* component c of a normal map's texel word: (k - 511) / 511 */
static float nmap_comp(spm_u32 q, int c)
{
    return (float)((int)((q >> (10 * c)) & 1023u) - 511) * (1.0f / SPM_NMAP_CODE);
}

/* the map's bilinear normal at (u, v), as geometry_alpha.c's map_bilinear */
static void nmap_bilinear(const spm_u32 *m, float u, float v, float r[3])
{
    int w = (int)m[0], h = (int)m[1];
    spm_tex_uvx(m, m[SPM_NMAP_UVX], &u, &v);
    float x = spm_tex_wrap_coord(u, m[2]) * (float)w - 0.5f;
    float y = (1.0f - spm_tex_wrap_coord(v, m[3])) * (float)h - 0.5f;
    float x0 = floorf(x), y0 = floorf(y), fx = x - x0, fy = y - y0;
    int i0 = spm_wrap_index((int)x0, w, (spm_wrap)m[2]);
    int i1 = spm_wrap_index((int)x0 + 1, w, (spm_wrap)m[2]);
    int j0 = spm_wrap_index((int)y0, h, (spm_wrap)m[3]);
    int j1 = spm_wrap_index((int)y0 + 1, h, (spm_wrap)m[3]);
    const spm_u32 *t = m + SPM_NMAP_MAP_HEAD;
    spm_u32 a = t[j0 * w + i0], b = t[j0 * w + i1], c = t[j1 * w + i0], e = t[j1 * w + i1];
    for (int k = 0; k < 3; k++) {
        float top = nmap_comp(a, k) + fx * (nmap_comp(b, k) - nmap_comp(a, k));
        float bot = nmap_comp(c, k) + fx * (nmap_comp(e, k) - nmap_comp(c, k));
        r[k] = top + fy * (bot - top);
    }
}

int spm_ref_nmap_frame(const spm_geometry *g, spm_u32 hit, const float o[3], const float d[3],
                       const float gn[3], float sn[3], float st[3])
{
    const spm_u32 *x = g->tex;
    const spm_tri *tr = &g->tris[hit];
    spm_u32 r = g->ntex && x[SPM_TEXD_NMAP] ? x[x[SPM_TEXD_NMAP] + tr->material] : 0u;
    if (r == 0u)
        return 0;
    float b[3], m[3], n[3], t[3], bt[3], sum[3];
    bary_of(tr, o, d, b);
    const float *uv = g->uvs + 6u * hit;
    float u = b[0] * uv[0] + b[1] * uv[2] + b[2] * uv[4];
    float v = b[0] * uv[1] + b[1] * uv[3] + b[2] * uv[5];
    nmap_bilinear(x + x[r + 1], u, v, m);
    float scale = word_float(x[r]);
    m[0] = m[0] * scale;
    m[1] = m[1] * scale;
    if (m[0] == 0.0f && m[1] == 0.0f)
        return 0;
    memcpy(n, tr->n, sizeof n);
    if (tr->vn != 0u)
        interp_unit(&g->vnormals[9 * (size_t)(tr->vn - 1u)], 3, b, n);
    const float *tg = (const float *)(x + x[SPM_TEXD_TANGENT]) + 12u * hit;
    for (int i = 0; i < 3; i++)
        t[i] = tg[i] * b[0] + tg[4 + i] * b[1] + tg[8 + i] * b[2];
    v3_cross(bt, n, t);
    for (int i = 0; i < 3; i++)
        bt[i] *= tg[3];
    const spm_u32 *map = x + x[r + 1];
    spm_tex_uvx_frame(map, map[SPM_NMAP_UVX], t, bt);
    for (int i = 0; i < 3; i++)
        sum[i] = t[i] * m[0] + bt[i] * m[1] + n[i] * m[2];
    v3_normalise(n, sum);
    if (!(v3_dot(n, n) > 0.0f))
        return 0;
    if (v3_dot(gn, tr->n) < 0.0f)
        n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    bend(tr, n, d, gn, sn, st);
    return 1;
}

void spm_ref_cond_frame(const float n[3], const float t[3], const float d[3], float alpha,
                        spm_ref_cond *c)
{
    for (int i = 0; i < 3; i++)
        c->n[i] = n[i], c->t[i] = t[i], c->back[i] = -d[i];
    v3_cross(c->b, c->n, c->t);
    c->wo[0] = v3_dot(c->back, c->t);
    c->wo[1] = v3_dot(c->back, c->b);
    c->wo[2] = v3_dot(c->back, c->n);
    c->alpha = alpha;
}

/* The hit's shading frame, the one place a type finds it: the normal n on
 * the viewer's side and tangent t every type shades with; gn, the geometric
 * normal on the viewer's side (MiniLight: dot(n, -d) < 0 flips n), decides
 * which side a direction is on. A flat triangle's is gn and its own tangent
 * (refcpu_shading.h). */
void spm_ref_hit_frame(const spm_geometry *g, const spm_tri *tri, const float o[3],
                      const float d[3], spm_ref_hit *h)
{
    for (int i = 0; i < 3; i++)
        h->gn[i] = h->ng[i] = tri->n[i], h->d[i] = d[i];
    if (v3_dot(h->gn, d) > 0.0f)
        h->gn[0] = -h->gn[0], h->gn[1] = -h->gn[1], h->gn[2] = -h->gn[2];
    h->smooth = tri->vn != 0u;
    int mapped = spm_ref_nmap_frame(g, (spm_u32)(tri - g->tris), o, d, h->gn, h->n, h->t);
    h->smooth |= mapped;
    if (mapped)
        return;
    if (h->smooth)
        spm_ref_shading_frame(tri, &g->vnormals[9 * (size_t)(tri->vn - 1u)], o, d, h->gn, h->n,
                              h->t);
    else
        for (int i = 0; i < 3; i++)
            h->n[i] = h->gn[i], h->t[i] = tri->t[i];
}

int spm_ref_sample_sided(const spm_material *m, const spm_ref_bsdf *b, const spm_ref_hit *h,
                         const spm_ref_key *k, int j, int mode, spm_ref_bsample *s)
{
    if (!spm_ref_sample(m, b, h, k, j, mode, s))
        return 0;
    if (!h->smooth)
        return 1;
    float c = v3_dot(s->wi, h->gn);
    return s->refract ? c < 0.0f : c > 0.0f;
}

int spm_ref_next_vertex(const spm_geometry *g, const float o[3], const float d[3], spm_u32 skip,
                        float *t, float x[3], spm_ref_hit *h)
{
    spm_ref_record_ray(o, d, skip, SPM_RAY_CLOSEST);
    int hit = spm_bvh_intersect(g, o, d, skip, t);
    if (hit < 0)
        return hit;
    v3_madd(x, o, d, *t);
    spm_ref_hit_frame(g, &g->tris[hit], o, d, h);
    return hit;
}

float spm_ref_adjoint_ns(const spm_ref_hit *h, const float wo[3], const float wi[3])
{
    if (!h->smooth)
        return 1.0f;
    float num = fabsf(v3_dot(wo, h->n)) * fabsf(v3_dot(wi, h->gn));
    float den = fabsf(v3_dot(wo, h->gn)) * fabsf(v3_dot(wi, h->n));
    return den > 0.0f ? num / den : 0.0f;
}
