/* A map's texture coordinate transform (texture.h spm_uvx; glTF
 * KHR_texture_transform): its six words beside the map, written for the trace
 * stage, and read back by the CPU reference as kernels/uvx.clh reads them. */
#include "geometry.h"
#include "texture.h"
#include <math.h>
#include <string.h>

static spm_u32 fbits(float f)
{
    spm_u32 u;
    memcpy(&u, &f, sizeof u);
    return u;
}

size_t spm_geometry_uvx_words(const spm_uvx *t)
{
    return t->on ? 6 : 0;
}

size_t spm_geometry_uvx_put(const spm_uvx *t, spm_u32 *x, size_t head, size_t slot, size_t w)
{
    x[head + slot] = t->on ? (spm_u32)(w - head) : 0u;
    for (size_t i = 0; i < spm_geometry_uvx_words(t); i++)
        x[w + i] = fbits(t->m[i]);
    return w + spm_geometry_uvx_words(t);
}

void spm_tex_uvx(const spm_u32 *h, spm_u32 off, float *u, float *v)
{
    if (off == 0u)
        return;
    float m[6], a = *u, b = *v;
    memcpy(m, h + off, sizeof m);
    *u = m[0] * a + m[1] * b + m[2];
    *v = m[3] * a + m[4] * b + m[5];
}

float spm_tex_uvx_scale(const spm_u32 *h, spm_u32 off)
{
    if (off == 0u)
        return 1.0f;
    float m[6];
    memcpy(m, h + off, sizeof m);
    return sqrtf(fabsf(m[0] * m[4] - m[1] * m[3]));
}

void spm_tex_uvx_frame(const spm_u32 *h, spm_u32 off, float t[3], float b[3])
{
    if (off == 0u)
        return;
    float m[6], tu[3], tv[3], len = 0, lu = 0, lv = 0;
    memcpy(m, h + off, sizeof m);
    float det = m[0] * m[4] - m[1] * m[3];
    for (int i = 0; i < 3; i++) {
        tu[i] = (m[4] * t[i] - m[3] * b[i]) * det;
        tv[i] = (m[0] * b[i] - m[1] * t[i]) * det;
        len += t[i] * t[i], lu += tu[i] * tu[i], lv += tv[i] * tv[i];
    }
    len = sqrtf(len), lu = sqrtf(lu), lv = sqrtf(lv);
    if (!(lu > 0.0f && lv > 0.0f))
        return;
    for (int i = 0; i < 3; i++) {
        t[i] = tu[i] * (len / lu);
        b[i] = tv[i] * (len / lv);
    }
}
