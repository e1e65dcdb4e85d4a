/* The CPU reference's smooth shading (refcpu_shading.h). */
#include "refcpu_shading.h"
#include <math.h>
#include <string.h>
#include "geometry_vec3.h"
#include "refcpu_lights.h"

/* Barycentrics (Moeller and Trumbore 1997): e1 = v1 - v0, e2 = v2 - v0,
 * s = o - v0, q = d x e2, u = s.q / e1.q, v = d.(s x e1) / e1.q, clamped into
 * the triangle; n = unit((1 - u - v) n0 + u n1 + v n2), turned with gn when
 * the viewer is behind the front face (a zero sum: gn). Keller et al. 2017's
 * bend: r = 2 (wo.n) n - wo; where r.gn < SPM_SMOOTH_LIFT,
 * r' = unit(r + gn (LIFT - r.gn)) and n = unit(wo + r'). The tangent
 * unit(t - n (t.n)) (t parallel to n: unit(gn x n)). */
void spm_ref_shading_frame(const spm_tri *tr, const float vn[9], const float o[3],
                           const float d[3], const float gn[3], float sn[3], float st[3])
{
    float e1[3], e2[3], q[3], s[3], se[3], n[3], sum[3];
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
    float w = 1.0f - u - v;
    for (int i = 0; i < 3; i++)
        sum[i] = vn[i] * w + vn[3 + i] * u + vn[6 + i] * v;
    v3_normalise(n, sum);
    if (v3_dot(gn, tr->n) < 0.0f)
        n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    if (v3_dot(n, n) == 0.0f)
        memcpy(n, gn, sizeof n);
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
    memcpy(sn, n, sizeof n);
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
