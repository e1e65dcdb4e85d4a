/* Opacity in traversal on the host (geometry.h spm_alpha_there; the layout:
 * spm_shared.h SPM_ALPHA_*): the materials' opacity records and maps laid
 * out in the texture words, and the test the BVH's closest-hit query makes
 * of each candidate hit. kernels/alpha.clh does the same operations in the
 * same order (contraction off on both sides), so both backends decide a
 * ray alike. */
#include "geometry.h"
#include "geometry_vec3.h"
#include "spm_rng.h"
#include "texture.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static spm_u32 fbits(float f)
{
    spm_u32 u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bitsf(spm_u32 u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static size_t map_words(const spm_alpha_map *m)
{
    return SPM_ALPHA_MAP_HEAD + ((size_t)m->w * m->h + 3) / 4 + spm_geometry_uvx_words(&m->uvx);
}

size_t spm_geometry_alpha_words(const spm_scene *s)
{
    size_t n = 0, mix = 0;
    for (int m = 0; m < s->nmaterials; m++) {
        n += s->materials[m].alpha_mode ? SPM_ALPHA_RECORD : 0;
        mix += s->materials[m].mix_metal ? SPM_MIX_RECORD : 0;
    }
    if (!n && !mix)
        return 0;
    for (int i = 0; i < s->nalphas; i++)
        n += map_words(&s->alphas[i]);
    return n + (n ? (size_t)s->nmaterials : 0) + (mix ? mix + (size_t)s->nmaterials : 0);
}

/* the metallic-roughness records (SPM_MIX_*) from word w on: a word per
 * material, then the records; the words' end */
static size_t mix_put(const spm_scene *s, const spm_u32 *offs, spm_u32 *x, size_t w)
{
    x[SPM_TEXD_MIX] = (spm_u32)w;
    size_t rec = w + (size_t)s->nmaterials;
    for (int i = 0; i < s->nmaterials; i++) {
        const spm_scene_material *m = &s->materials[i];
        if (!m->mix_metal)
            continue;
        x[w + (size_t)i] = (spm_u32)rec;
        x[rec] = (spm_u32)(m->mix_metal - 1);
        x[rec + 1] = fbits(m->mix_metallic);
        x[rec + 2] = fbits(m->mix_rough);
        x[rec + 3] = m->mix_mmap > 0 && m->mix_mmap <= s->nalphas ? offs[m->mix_mmap - 1] : 0u;
        x[rec + 4] = m->mix_rmap > 0 && m->mix_rmap <= s->nalphas ? offs[m->mix_rmap - 1] : 0u;
        rec += SPM_MIX_RECORD;
    }
    return rec;
}

/* The maps first (their offsets in *offs), then a word per material and the
 * opacity records, then the mix's. */
size_t spm_geometry_alpha_put(const spm_scene *s, spm_u32 *x, size_t w)
{
    if (!spm_geometry_alpha_words(s))
        return w;
    spm_u32 *offs = spm_xcalloc((size_t)s->nalphas + 1, sizeof *offs);
    int any_alpha = 0, any_mix = 0;
    for (int i = 0; i < s->nmaterials; i++) {
        any_alpha |= s->materials[i].alpha_mode != 0;
        any_mix |= s->materials[i].mix_metal != 0;
    }
    for (int i = 0; i < s->nalphas; i++) {
        const spm_alpha_map *m = &s->alphas[i];
        offs[i] = (spm_u32)w;
        x[w] = (spm_u32)m->w, x[w + 1] = (spm_u32)m->h;
        x[w + 2] = (spm_u32)m->wrap[0], x[w + 3] = (spm_u32)m->wrap[1];
        for (size_t k = 0; k < (size_t)m->w * m->h; k++)
            x[w + SPM_ALPHA_MAP_HEAD + k / 4] |= (spm_u32)m->a[k] << (8 * (k % 4));
        spm_geometry_uvx_put(&m->uvx, x, w, SPM_ALPHA_UVX,
                             w + SPM_ALPHA_MAP_HEAD + ((size_t)m->w * m->h + 3) / 4);
        w += map_words(m);
    }
    size_t rec = w;
    if (any_alpha) {
        x[SPM_TEXD_ALPHA] = (spm_u32)w;
        rec = w + (size_t)s->nmaterials;
        for (int i = 0; i < s->nmaterials; i++) {
            const spm_scene_material *m = &s->materials[i];
            if (!m->alpha_mode)
                continue;
            x[w + (size_t)i] = (spm_u32)rec;
            x[rec] = (spm_u32)m->alpha_mode;
            x[rec + 1] = fbits(m->alpha_cutoff);
            x[rec + 2] = fbits(m->alpha_factor);
            x[rec + 3] =
                m->alpha_map > 0 && m->alpha_map <= s->nalphas ? offs[m->alpha_map - 1] : 0u;
            rec += SPM_ALPHA_RECORD;
        }
    }
    if (any_mix)
        rec = mix_put(s, offs, x, rec);
    free(offs);
    return rec;
}

void spm_tri_uv(const spm_tri *tr, const float uv[6], const float p[3], float *u, float *v)
{
    float e1[3], e2[3], q[3];
    v3_sub(e1, tr->v1, tr->v0);
    v3_sub(e2, tr->v2, tr->v0);
    v3_sub(q, p, tr->v0);
    float d11 = v3_dot(e1, e1), d12 = v3_dot(e1, e2), d22 = v3_dot(e2, e2);
    float q1 = v3_dot(q, e1), q2 = v3_dot(q, e2), den = d11 * d22 - d12 * d12;
    float b1 = (d22 * q1 - d12 * q2) / den, b2 = (d11 * q2 - d12 * q1) / den;
    float b0 = 1.0f - b1 - b2;
    *u = b0 * uv[0] + b1 * uv[2] + b2 * uv[4];
    *v = b0 * uv[1] + b1 * uv[3] + b2 * uv[5];
}

int spm_geometry_has_alpha(const spm_geometry *g)
{
    return g->ntex && g->tex[SPM_TEXD_ALPHA] != 0;
}

float spm_tex_wrap_coord(float u, spm_u32 mode)
{
    if (!isfinite(u))
        return 0.0f;
    if (mode == 0u)
        return u - floorf(u);
    if (mode == 2u)
        return u - 2.0f * floorf(0.5f * u);
    return fminf(fmaxf(u, -1.0f), 2.0f);
}

static float texel(const spm_u32 *m, int i, int j)
{
    spm_u32 k = (spm_u32)j * m[0] + (spm_u32)i;
    return (float)((m[SPM_ALPHA_MAP_HEAD + k / 4u] >> (8u * (k % 4u))) & 255u);
}

/* The map's bilinear value at (u, v): the four texel centres around
 * (u w - 1/2, (1 - v) h - 1/2), weighted by the fractions; in [0, 1]. */
float spm_byte_map_bilinear(const spm_u32 *m, float u, float v)
{
    int w = (int)m[0], h = (int)m[1];
    spm_tex_uvx(m, m[SPM_ALPHA_UVX], &u, &v);
    float x = spm_tex_wrap_coord(u, m[2]) * (float)w - 0.5f;
    float y = (1.0f - spm_tex_wrap_coord(v, m[3])) * (float)h - 0.5f;
    float x0 = floorf(x), y0 = floorf(y), fx = x - x0, fy = y - y0;
    int i0 = spm_wrap_index((int)x0, w, (spm_wrap)m[2]), i1 = spm_wrap_index((int)x0 + 1, w, (spm_wrap)m[2]);
    int j0 = spm_wrap_index((int)y0, h, (spm_wrap)m[3]), j1 = spm_wrap_index((int)y0 + 1, h, (spm_wrap)m[3]);
    float top = texel(m, i0, j0) + fx * (texel(m, i1, j0) - texel(m, i0, j0));
    float bot = texel(m, i0, j1) + fx * (texel(m, i1, j1) - texel(m, i0, j1));
    return (top + fy * (bot - top)) * (1.0f / 255.0f);
}

int spm_alpha_there(const spm_geometry *g, spm_u32 tri, const float o[3], const float d[3],
                    float t)
{
    const spm_u32 *x = g->tex;
    if (!g->ntex || !x[SPM_TEXD_ALPHA])
        return 1;
    const spm_tri *tr = &g->tris[tri];
    spm_u32 r = x[x[SPM_TEXD_ALPHA] + tr->material];
    if (!r)
        return 1;
    float a = bitsf(x[r + 2]);
    if (x[r + 3]) { /* the map at the hit's (u, v) */
        float p[3], u, v;
        for (int i = 0; i < 3; i++)
            p[i] = o[i] + d[i] * t;
        spm_tri_uv(tr, g->uvs + 6u * tri, p, &u, &v);
        a = a * spm_byte_map_bilinear(x + x[r + 3], u, v);
    }
    if (x[r] == SPM_ALPHA_MASK)
        return a >= bitsf(x[r + 1]);
    spm_u32 h = spm_alpha_hash(tri, fbits(o[0]), fbits(o[1]), fbits(o[2]), fbits(d[0]),
                               fbits(d[1]), fbits(d[2]));
    return (float)(h >> 8) * SPM_RNG_UNIT < a;
}

/* The metallic-roughness record of triangle tri's material at point p
 * (SPM_MIX_*): the metal's material index, *metallic and *alpha; -1 when the
 * material has none (kernels/metalrough.clh mix_values). */
int spm_mix_values(const spm_geometry *g, spm_u32 tri, const float p[3], float *metallic,
                   float *alpha)
{
    const spm_u32 *x = g->tex;
    if (!g->ntex || !x[SPM_TEXD_MIX])
        return -1;
    const spm_tri *tr = &g->tris[tri];
    spm_u32 r = x[x[SPM_TEXD_MIX] + tr->material];
    if (!r)
        return -1;
    float mt = bitsf(x[r + 1]), ro = bitsf(x[r + 2]);
    if (x[r + 3] || x[r + 4]) {
        float u, v;
        spm_tri_uv(tr, g->uvs + 6u * tri, p, &u, &v);
        if (x[r + 3])
            mt = mt * spm_byte_map_bilinear(x + x[r + 3], u, v);
        if (x[r + 4])
            ro = ro * spm_byte_map_bilinear(x + x[r + 4], u, v);
    }
    float a = ro * ro;
    *metallic = mt;
    *alpha = a < (float)SPM_COND_MIN_ALPHA ? 0.0f : fminf(a, 1.0f);
    return (int)x[r];
}
