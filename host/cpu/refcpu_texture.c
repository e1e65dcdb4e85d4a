/* CPU reference, a textured vertex's colour (refcpu_texture.h): the
 * kernel's operations in the same order, in plain scalar float C. */
#include "refcpu_texture.h"
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "texture.h"
#include <math.h>
#include <string.h>

static float word_float(spm_u32 w)
{
    float f;
    memcpy(&f, &w, sizeof f);
    return f;
}

/* floor(x - 1/2), or the next texel with probability the fraction */
static int tap(float x, float r)
{
    float c = x - 0.5f, f = floorf(c);
    return (int)f + (r < c - f ? 1 : 0);
}

/* the cell's lower grid node, or its upper one with probability the fraction;
 * *r rescaled for the next axis */
static spm_u32 grid_pick(const spm_u32 *nodes, float x, float *r)
{
    x = fminf(fmaxf(x, 0.0f), 1.0f);
    spm_u32 lo = 0u, hi = SPM_TEX_GRID - 1u;
    while (hi - lo > 1u) {
        spm_u32 mid = (lo + hi) / 2u;
        if (word_float(nodes[mid]) <= x)
            lo = mid;
        else
            hi = mid;
    }
    float a = word_float(nodes[lo]), f = (x - a) / (word_float(nodes[lo + 1u]) - a);
    if (*r < f) {
        *r = *r / f;
        return lo + 1u;
    }
    *r = (*r - f) / (1.0f - f);
    return lo;
}

spm_u32 spm_ref_texture_node(const spm_geometry *g, const spm_u32 *h, spm_u32 l, float u, float v,
                             float r1, float r2, float r3)
{
    const spm_u32 *tex = g->tex, *lv = h + 4u + 4u * l;
    int w = (int)lv[1], ht = (int)lv[2];
    spm_tex_uvx(h, h[SPM_TEX_UVX], &u, &v);
    u = spm_tex_wrap_coord(u, h[1]);
    v = spm_tex_wrap_coord(v, h[2]);
    int ix = spm_wrap_index(tap(u * (float)w, r1), w, (spm_wrap)h[1]);
    int iy = spm_wrap_index(tap((1.0f - v) * (float)ht, r2), ht, (spm_wrap)h[2]);
    const spm_u32 *t = tex + lv[0] + 3u * ((spm_u32)iy * (spm_u32)w + (spm_u32)ix);
    const spm_u32 *nodes = tex + tex[SPM_TEXD_NODES];
    spm_u32 nr = grid_pick(nodes, word_float(t[0]), &r3);
    spm_u32 ng = grid_pick(nodes, word_float(t[1]), &r3);
    spm_u32 nb = grid_pick(nodes, word_float(t[2]), &r3);
    return (nr * SPM_TEX_GRID + ng) * SPM_TEX_GRID + nb;
}

spm_u32 spm_ref_texture_colour(const spm_geometry *g, spm_u32 mat, spm_u32 hit, const float x[3],
                               const float d[3], float cone, const spm_ref_key *k, int j,
                               spm_u32 refl, spm_u32 base, float *survive)
{
    const spm_u32 *tex = g->tex;
    spm_u32 tw = g->ntex ? tex[tex[SPM_TEXD_MATS] + mat] : 0u, tx = tw & 0xFFFFu;
    if (tx == 0u || refl != base)
        return refl;
    const spm_u32 *h = tex + tex[tex[SPM_TEXD_TEXS] + tx - 1u];
    const float *uv = g->uvs + 6u * hit;
    const spm_tri *tr = &g->tris[hit];
    float u, v;
    spm_tri_uv(tr, uv, x, &u, &v);
    float ta = fabsf((uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[4] - uv[0]) * (uv[3] - uv[1]));
    float width = cone / fabsf(v3_dot(d, tr->n)) * sqrtf(ta / (2.0f * tr->area)) *
                  spm_tex_uvx_scale(h, h[SPM_TEX_UVX]);
    spm_u32 nl = h[0];
    float lod = log2f(width * sqrtf((float)h[5] * (float)h[6]));
    lod = lod > 0.0f ? fminf(lod, (float)(nl - 1u)) : 0.0f;
    spm_u32 l = (spm_u32)lod;
    if (spm_ref_rnd(k, SPM_DIM_TEX(j, 0)) < lod - (float)l)
        l++;
    spm_u32 node = spm_ref_texture_node(g, h, l, u, v, spm_ref_rnd(k, SPM_DIM_TEX(j, 1)),
                                        spm_ref_rnd(k, SPM_DIM_TEX(j, 2)),
                                        spm_ref_rnd(k, SPM_DIM_TEX(j, 3)));
    spm_u32 at = (tw >> 16) * SPM_TEX_NODES_ALL + node;
    *survive = word_float(tex[tex[SPM_TEXD_SURVIVE] + at]);
    return tex[tex[SPM_TEXD_PALETTE] + at];
}

/* A light integrator's vertex colour: the texture's pick with the footprint
 * the camera sees x with, a pixel's angle times the distance from the eye,
 * along the eye's ray to it (kernels/texture.clh texture_seen). It depends on
 * x alone, not on the subpath that made the vertex, so every strategy that
 * reaches x weighs one filter of the texture. */
spm_u32 spm_ref_texture_seen(const spm_geometry *g, spm_u32 mat, spm_u32 hit, const float x[3],
                             const spm_ref_key *k, int j, spm_u32 refl, spm_u32 base, float *mean,
                             float *inv_mean)
{
    if (!g->ntex)
        return refl;
    float d[3], r = 1.0f;
    v3_sub(d, x, g->cam.eye);
    float dist = sqrtf(v3_dot(d, d)), pix = 2.0f * g->cam.tan_half / (float)g->cam.width;
    if (!(dist > 0.0f))
        return refl;
    for (int i = 0; i < 3; i++)
        d[i] /= dist;
    refl = spm_ref_texture_colour(g, mat, hit, x, d, pix * dist, k, j, refl, base, &r);
    *mean *= r;
    *inv_mean = r > 0.0f ? *inv_mean / r : 0.0f;
    return refl;
}

/* the largest of the edges' |(n_j - n_i) . (p_j - p_i)| / |p_j - p_i|^2 (0 flat) */
static float curvature(const spm_geometry *g, const spm_tri *tri)
{
    if (tri->vn == 0u)
        return 0.0f;
    const float *vn = &g->vnormals[9 * (size_t)(tri->vn - 1u)];
    const float *p[3] = {tri->v0, tri->v1, tri->v2};
    float k = 0.0f;
    for (int e = 0; e < 3; e++) {
        int f = (e + 1) % 3;
        float dp[3], dn[3];
        v3_sub(dp, p[f], p[e]);
        v3_sub(dn, &vn[3 * f], &vn[3 * e]);
        k = fmaxf(k, fabsf(v3_dot(dn, dp)) / v3_dot(dp, dp));
    }
    return k;
}

float spm_ref_cone_bounce(const spm_geometry *g, const spm_tri *tri, float spread, float w,
                          const float n[3], float eta, const float d[3],
                          const spm_ref_bsample *s)
{
    if (s->refract) {
        float ci = fabsf(v3_dot(d, n)), ct = fabsf(v3_dot(s->wi, n));
        spread = spread * ci / fmaxf(eta * ct, 1e-6f) +
                 fabsf(1.0f - 1.0f / eta) * curvature(g, tri) * w;
    } else {
        spread += 2.0f * curvature(g, tri) * w;
    }
    /* a diffuse lobe (pdf < 0) is cosine-sampled */
    float p = s->pdf < 0.0f ? fabsf(v3_dot(s->wi, n)) / SPM_PI_F : s->pdf;
    if (p > 0.0f)
        spread += SPM_CONE_LOBE * sqrtf(1.0f / (SPM_PI_F * p));
    return spread;
}
