/* Image textures: the pyramid, wrap modes and lookups (texture.h). */
#include "texture.h"
#include "util.h"
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* One axis of the area-mean reduction: output texel o of m covers input
 * [o s, (o+1) s], s = n / m; weights are the covered length of each input
 * texel over s. Returns the number of taps (at most 4: s < 3). */
static int taps(int o, int n, int m, int idx[4], double wt[4])
{
    double s = (double)n / m, a = o * s, b = (o + 1) * s;
    int k = 0;
    for (int i = (int)floor(a); i < n && i < b && k < 4; i++) {
        double lo = fmax(a, i), hi = fmin(b, i + 1.0);
        if (hi > lo) {
            idx[k] = i;
            wt[k++] = (hi - lo) / s;
        }
    }
    return k;
}

static void reduce(const spm_texmap *in, spm_texmap *out)
{
    out->w = in->w > 1 ? in->w / 2 : 1;
    out->h = in->h > 1 ? in->h / 2 : 1;
    out->rgb = spm_xmalloc(sizeof(float) * 3 * out->w * out->h);
    for (int oy = 0; oy < out->h; oy++) {
        int iy[4], ix[4];
        double wy[4], wx[4];
        int ny = taps(oy, in->h, out->h, iy, wy);
        for (int ox = 0; ox < out->w; ox++) {
            int nx = taps(ox, in->w, out->w, ix, wx);
            double sum[3] = {0, 0, 0};
            for (int a = 0; a < ny; a++)
                for (int b = 0; b < nx; b++) {
                    const float *p = in->rgb + 3 * ((size_t)iy[a] * in->w + ix[b]);
                    for (int c = 0; c < 3; c++)
                        sum[c] += wy[a] * wx[b] * p[c];
                }
            float *q = out->rgb + 3 * ((size_t)oy * out->w + ox);
            for (int c = 0; c < 3; c++)
                q[c] = (float)sum[c];
        }
    }
}

void spm_texture_from_pixels(int w, int h, const float *rgb, spm_wrap wrap_u, spm_wrap wrap_v,
                             spm_texture *t)
{
    memset(t, 0, sizeof *t);
    t->wrap[0] = wrap_u;
    t->wrap[1] = wrap_v;
    t->lv[0].w = w;
    t->lv[0].h = h;
    t->lv[0].rgb = spm_xmalloc(sizeof(float) * 3 * (size_t)w * h);
    memcpy(t->lv[0].rgb, rgb, sizeof(float) * 3 * (size_t)w * h);
    t->nlevels = 1;
    while ((t->lv[t->nlevels - 1].w > 1 || t->lv[t->nlevels - 1].h > 1) &&
           t->nlevels < SPM_TEXTURE_MAX_LEVELS) {
        reduce(&t->lv[t->nlevels - 1], &t->lv[t->nlevels]);
        t->nlevels++;
    }
}

void spm_uvx_gltf(const double offset[2], double rotation, const double scale[2], spm_uvx *out)
{
    double c = cos(rotation), s = sin(rotation);
    const double m[6] = {c * scale[0], -s * scale[1], s * scale[1] + offset[0],
                         s * scale[0], c * scale[1], 1.0 - c * scale[1] - offset[1]};
    static const double id[6] = {1, 0, 0, 0, 1, 0};
    out->on = 0;
    for (int i = 0; i < 6; i++) {
        out->m[i] = (float)m[i];
        out->on |= out->m[i] != (float)id[i];
    }
}

void spm_texture_checker(int checks, int res, const float a[3], const float b[3], spm_wrap wrap,
                         spm_texture *t)
{
    int n = checks * res;
    float *px = spm_xmalloc(sizeof(float) * 3 * (size_t)n * n);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++)
            memcpy(px + 3 * ((size_t)y * n + x), ((x / res + y / res) % 2) ? b : a,
                   sizeof(float) * 3);
    spm_texture_from_pixels(n, n, px, wrap, wrap, t);
    free(px);
}

void spm_texture_free(spm_texture *t)
{
    for (int l = 0; l < t->nlevels; l++)
        free(t->lv[l].rgb);
    memset(t, 0, sizeof *t);
}

int spm_wrap_index(int i, int n, spm_wrap mode)
{
    switch (mode) {
    case SPM_WRAP_CLAMP:
        return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case SPM_WRAP_MIRROR: {
        int p = i % (2 * n);
        p = p < 0 ? p + 2 * n : p;
        return p < n ? p : 2 * n - 1 - p;
    }
    default: {
        int p = i % n;
        return p < 0 ? p + n : p;
    }
    }
}

void spm_texture_texel(const spm_texture *t, int level, int i, int j, float out[3])
{
    const spm_texmap *m = &t->lv[level];
    int x = spm_wrap_index(i, m->w, t->wrap[0]), y = spm_wrap_index(j, m->h, t->wrap[1]);
    memcpy(out, m->rgb + 3 * ((size_t)y * m->w + x), sizeof(float) * 3);
}

/* A coordinate brought into one period of its wrap mode (repeat 1, mirror 2;
 * clamp is constant beyond [-1, 2]), so that texel indices stay small; NaN
 * becomes 0. */
static double wrap_coord(double u, spm_wrap mode)
{
    if (!isfinite(u))
        return 0.0;
    if (mode == SPM_WRAP_REPEAT)
        return u - floor(u);
    if (mode == SPM_WRAP_MIRROR)
        return u - 2.0 * floor(0.5 * u);
    return u < -1.0 ? -1.0 : (u > 2.0 ? 2.0 : u);
}

void spm_texture_bilinear(const spm_texture *t, int level, double u, double v, float out[3])
{
    const spm_texmap *m = &t->lv[level];
    u = wrap_coord(u, t->wrap[0]);
    v = wrap_coord(v, t->wrap[1]);
    double x = u * m->w - 0.5, y = (1.0 - v) * m->h - 0.5;
    double fx = floor(x), fy = floor(y);
    int i = (int)fx, j = (int)fy;
    double ax = x - fx, ay = y - fy, sum[3] = {0, 0, 0};
    for (int c4 = 0; c4 < 4; c4++) {
        int ox = c4 & 1, oy = c4 >> 1;
        double wgt = (ox ? ax : 1 - ax) * (oy ? ay : 1 - ay);
        float p[3];
        spm_texture_texel(t, level, i + ox, j + oy, p);
        for (int c = 0; c < 3; c++)
            sum[c] += wgt * p[c];
    }
    for (int c = 0; c < 3; c++)
        out[c] = (float)sum[c];
}

double spm_texture_lod(const spm_texture *t, double width)
{
    double lod = log2(width * sqrt((double)t->lv[0].w * t->lv[0].h));
    if (!(lod > 0.0)) /* NaN and a footprint under a texel: level 0 */
        return 0.0;
    return lod < t->nlevels - 1 ? lod : t->nlevels - 1;
}

double spm_texture_cone_footprint(double cone_width, double cos_theta, const float uv[6],
                                  const float p[9])
{
    /* areas as |cross products| / 2; the halves cancel in the ratio */
    double ta = fabs((uv[2] - uv[0]) * (double)(uv[5] - uv[1]) -
                     (uv[4] - uv[0]) * (double)(uv[3] - uv[1]));
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++)
        e1[k] = p[3 + k] - p[k], e2[k] = p[6 + k] - p[k];
    double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
           cz = e1[0] * e2[1] - e1[1] * e2[0], pa = sqrt(cx * cx + cy * cy + cz * cz);
    double c = fabs(cos_theta);
    if (!(pa > 0.0) || !(c > 0.0))
        return 0.0;
    return cone_width / c * sqrt(ta / pa);
}

void spm_texture_trilinear(const spm_texture *t, double u, double v, double width, float out[3])
{
    double lod = spm_texture_lod(t, width);
    int l0 = (int)lod, l1 = l0 + 1 < t->nlevels ? l0 + 1 : l0;
    double f = lod - l0;
    float a[3], b[3];
    spm_texture_bilinear(t, l0, u, v, a);
    spm_texture_bilinear(t, l1, u, v, b);
    for (int c = 0; c < 3; c++)
        out[c] = (float)((1 - f) * a[c] + f * b[c]);
}

void spm_texture_mean(const spm_texture *t, float out[3])
{
    memcpy(out, t->lv[t->nlevels - 1].rgb, sizeof(float) * 3);
}

/* FNV-1a of a texel's three floats' bits */
static uint64_t texel_hash(const float *p)
{
    uint64_t h = 1469598103934665603ull;
    const unsigned char *b = (const unsigned char *)p;
    for (int i = 0; i < 12; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

long spm_texture_lift(const spm_rgb2spec_table *t, spm_texel_kind kind, const spm_texmap *m,
                      float *out)
{
    size_t n = (size_t)m->w * m->h, cap = 16;
    while (cap < 2 * n)
        cap *= 2;
    /* open addressing: slot -> index of the first texel with that value, + 1 */
    size_t *slot = spm_xcalloc(cap, sizeof *slot);
    long distinct = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = m->rgb + 3 * i;
        size_t s = (size_t)texel_hash(p) & (cap - 1);
        while (slot[s] && memcmp(m->rgb + 3 * (slot[s] - 1), p, 12))
            s = (s + 1) & (cap - 1);
        if (slot[s]) {
            memcpy(out + 4 * i, out + 4 * (slot[s] - 1), sizeof(float) * 4);
            continue;
        }
        slot[s] = i + 1;
        distinct++;
        double rgb[3] = {p[0], p[1], p[2]}, c[3], scale;
        spm_rgb2spec_texel(t, kind, rgb, c, &scale);
        for (int k = 0; k < 3; k++)
            out[4 * i + k] = (float)c[k];
        out[4 * i + 3] = (float)scale;
    }
    free(slot);
    return distinct;
}
