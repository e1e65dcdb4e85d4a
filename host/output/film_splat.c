/* Splats summed in fixed point (film_splat.h). */
#include "film_splat.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

void spm_splats_init(spm_splats *s, int ch)
{
    memset(s, 0, sizeof *s);
    s->ch = ch;
}

void spm_splats_free(spm_splats *s)
{
    free(s->px);
    free(s->v);
    memset(s, 0, sizeof *s);
}

float *spm_splats_push(spm_splats *s, uint32_t px)
{
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 4096;
        s->px = spm_xrealloc(s->px, s->cap * sizeof *s->px);
        s->v = spm_xrealloc(s->v, s->cap * (size_t)s->ch * sizeof *s->v);
    }
    s->px[s->n] = px;
    return &s->v[(size_t)s->ch * s->n++];
}

void spm_splat_acc_init(spm_splat_acc *a, size_t npix, int ch)
{
    a->npix = npix;
    a->ch = ch;
    a->acc = spm_xcalloc(npix * (size_t)ch, sizeof *a->acc);
    a->touched = spm_xcalloc(npix, 1);
}

void spm_splat_acc_free(spm_splat_acc *a)
{
    free(a->acc);
    free(a->touched);
    memset(a, 0, sizeof *a);
}

static int finite_splat(const float *v, int ch)
{
    for (int c = 0; c < ch; c++)
        if (!isfinite(v[c]))
            return 0;
    return 1;
}

/* The chunk's scale: with every |v| < 2^e (e the largest exponent among the
 * splats, frexp's) and n <= 2^b splats, the unit 2^-(62 - e - b) makes each
 * |round(v 2^shift)| <= 2^(62 - b) and any sum of them at most 2^62 < 2^63:
 * no pixel's sum overflows, whatever the order. The maximum and the count
 * do not depend on the order either. */
static int chunk_shift(const spm_splats *s, int ch)
{
    int e = -1074;
    for (size_t i = 0; i < s->n; i++) {
        const float *v = &s->v[(size_t)ch * i];
        if (!finite_splat(v, ch))
            continue;
        for (int c = 0; c < ch; c++) {
            int ex;
            if (v[c] != 0.0f && (frexp(v[c], &ex), ex > e))
                e = ex;
        }
    }
    return spm_splat_shift(e, s->n);
}

int spm_splat_shift(int e, size_t n)
{
    int b = 0;
    while (((size_t)1 << b) < n)
        b++;
    return 62 - e - b;
}

int spm_splats_add_chunk(spm_splat_acc *a, const spm_splats *s, float *pass, uint64_t *nonfinite)
{
    int ch = a->ch, shift = chunk_shift(s, ch);
    for (size_t i = 0; i < s->n; i++) {
        const float *v = &s->v[(size_t)ch * i];
        if (!finite_splat(v, ch)) {
            ++*nonfinite;
            continue;
        }
        int64_t *acc = &a->acc[(size_t)ch * s->px[i]];
        for (int c = 0; c < ch; c++)
            acc[c] += (int64_t)llrint(ldexp((double)v[c], shift));
        a->touched[s->px[i]] = 1;
    }
    /* each touched pixel's sum into the pass image once, and the accumulator
     * back to zero: the pixels' order does not matter, each is its own */
    for (size_t i = 0; i < s->n; i++) {
        uint32_t p = s->px[i];
        if (!a->touched[p])
            continue;
        a->touched[p] = 0;
        int64_t *acc = &a->acc[(size_t)ch * p];
        for (int c = 0; c < ch; c++) {
            pass[(size_t)ch * p + (size_t)c] += (float)ldexp((double)acc[c], -shift);
            acc[c] = 0;
        }
    }
    return shift;
}
